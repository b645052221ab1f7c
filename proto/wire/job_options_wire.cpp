#include "wire/job_options_wire.h"

#include <google/protobuf/util/json_util.h>

#include <stdexcept>

namespace tessera::wire {

JobOverrides overrides_from_proto(const v1::JobRequestOptions& o) {
  JobOverrides out;
  if (o.has_width()) out.width = o.width();
  if (o.has_height()) out.height = o.height();
  if (o.has_spp()) out.spp = o.spp();
  if (o.has_max_depth()) out.max_depth = o.max_depth();
  if (o.has_seed()) out.seed = o.seed();
  if (o.has_tile_size()) out.tile_size = o.tile_size();
  if (o.has_batch_spp()) out.batch_spp = o.batch_spp();
  if (o.has_isa()) out.isa = o.isa();
  return out;
}

v1::JobRequestOptions overrides_to_proto(const JobOverrides& o) {
  v1::JobRequestOptions out;
  if (o.width) out.set_width(*o.width);
  if (o.height) out.set_height(*o.height);
  if (o.spp) out.set_spp(*o.spp);
  if (o.max_depth) out.set_max_depth(*o.max_depth);
  if (o.seed) out.set_seed(*o.seed);
  if (o.tile_size) out.set_tile_size(*o.tile_size);
  if (o.batch_spp) out.set_batch_spp(*o.batch_spp);
  if (o.isa) out.set_isa(*o.isa);
  return out;
}

v1::ResolvedJobOptions options_to_proto(const JobOptions& o) {
  v1::ResolvedJobOptions out;
  out.set_width(o.width);
  out.set_height(o.height);
  out.set_spp(o.spp);
  out.set_max_depth(o.max_depth);
  out.set_seed(o.seed);
  out.set_tile_size(o.tile_size);
  out.set_batch_spp(o.batch_spp);
  out.set_isa(o.isa);
  return out;
}

JobOptions options_from_proto(const v1::ResolvedJobOptions& o) {
  JobOptions out;
  out.width = o.width();
  out.height = o.height();
  out.spp = o.spp();
  out.max_depth = o.max_depth();
  out.seed = o.seed();
  out.tile_size = o.tile_size();
  out.batch_spp = o.batch_spp();
  out.isa = o.isa();
  return out;
}

std::string options_to_json(const JobOptions& options) {
  google::protobuf::util::JsonPrintOptions print;
  print.always_print_primitive_fields = true;
  print.preserve_proto_field_names = true;
  std::string json;
  const auto status =
      google::protobuf::util::MessageToJsonString(options_to_proto(options), &json, print);
  if (!status.ok()) throw std::runtime_error("job options to JSON: " + status.ToString());
  return json;
}

}  // namespace tessera::wire
