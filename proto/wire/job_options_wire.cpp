#include "wire/job_options_wire.h"

#include <google/protobuf/util/json_util.h>

#include <optional>
#include <stdexcept>

#include "scene/message_text.h"

namespace tessera::wire {

v1::StopRule stop_rule_to_proto(StopRule rule) {
  switch (rule) {
    case StopRule::spp: return v1::STOP_RULE_SPP;
    case StopRule::time: return v1::STOP_RULE_TIME;
    case StopRule::noise: return v1::STOP_RULE_NOISE;
  }
  return v1::STOP_RULE_UNSPECIFIED;
}

StopRule stop_rule_from_proto(v1::StopRule rule) {
  switch (rule) {
    case v1::STOP_RULE_TIME: return StopRule::time;
    case v1::STOP_RULE_NOISE: return StopRule::noise;
    default: return StopRule::spp;  // UNSPECIFIED: messages from before stopping rules
  }
}

v1::StopReason stop_reason_to_proto(StopReason reason) {
  switch (reason) {
    case StopReason::none: return v1::STOP_REASON_UNSPECIFIED;
    case StopReason::spp_reached: return v1::STOP_REASON_SPP_REACHED;
    case StopReason::noise_target: return v1::STOP_REASON_NOISE_TARGET;
    case StopReason::max_spp: return v1::STOP_REASON_MAX_SPP;
    case StopReason::time_budget: return v1::STOP_REASON_TIME_BUDGET;
    case StopReason::cancelled: return v1::STOP_REASON_CANCELLED;
  }
  return v1::STOP_REASON_UNSPECIFIED;
}

StopReason stop_reason_from_proto(v1::StopReason reason) {
  switch (reason) {
    case v1::STOP_REASON_SPP_REACHED: return StopReason::spp_reached;
    case v1::STOP_REASON_NOISE_TARGET: return StopReason::noise_target;
    case v1::STOP_REASON_MAX_SPP: return StopReason::max_spp;
    case v1::STOP_REASON_TIME_BUDGET: return StopReason::time_budget;
    case v1::STOP_REASON_CANCELLED: return StopReason::cancelled;
    default: return StopReason::none;
  }
}

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
  if (o.has_time_s()) out.time_s = o.time_s();
  if (o.has_noise()) out.noise = o.noise();
  if (o.has_max_spp()) out.max_spp = o.max_spp();
  if (o.has_preset()) out.preset = o.preset();
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
  if (o.time_s) out.set_time_s(*o.time_s);
  if (o.noise) out.set_noise(*o.noise);
  if (o.max_spp) out.set_max_spp(*o.max_spp);
  if (o.preset) out.set_preset(*o.preset);
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
  out.set_stop_rule(stop_rule_to_proto(o.rule));
  out.set_time_budget_s(o.time_budget_s);
  out.set_noise_target(o.noise_target);
  out.set_batch_schedule(std::string(to_string(o.batch_kind)));
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
  out.rule = stop_rule_from_proto(o.stop_rule());
  out.time_budget_s = o.time_budget_s();
  out.noise_target = o.noise_target();
  if (!o.batch_schedule().empty()) {
    const std::optional<BatchKind> kind = batch_kind_from_string(o.batch_schedule());
    if (!kind) {
      throw std::invalid_argument("options: unknown batch schedule \"" + printable(o.batch_schedule()) + "\"");
    }
    out.batch_kind = *kind;
  }
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
