#include "job_output.h"

#include <numeric>
#include <system_error>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "job/tile_summary.h"
#include "wire/job_options_wire.h"

namespace tessera::server {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
  return out;
}

void write_atomically(const ImageFileWriter& writer, const RgbImage& image,
                      const std::filesystem::path& path, const ImageWriteOptions& options) {
  // write_image picks the format from the extension: keep it last in the temporary name.
  std::filesystem::path temp = path;
  temp.replace_extension(".partial" + path.extension().string());
  try {
    writer(image, temp, options);
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temp, ignored);  // a full disk keeps no half-written file
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) throw std::runtime_error(path.string() + ": cannot rename into place: " + ec.message());
}

}  // namespace

RgbImage JobOutput::resolve(const JobRecord& job, const std::vector<TileRecord>& tiles) {
  // One tile decoded at a time (36 bytes a pixel), resolved into the image (12 bytes a pixel),
  // and dropped: decoding every tile first would hold the whole image three times over.
  RgbImage image = resolve_image(job.options.width, job.options.height, {});
  for (const TileRecord& t : tiles) {
    if (!t.accumulation.empty()) resolve_into(image, decode_accumulation(t.accumulation));
  }
  return image;
}

std::map<std::string, std::string> JobOutput::provenance(const JobRecord& job) {
  std::map<std::string, std::string> m;
  m["tessera:job_id"] = std::to_string(job.id);
  m["tessera:scene_file"] = job.scene_file;
  m["tessera:scene_sha256"] = job.bundle_sha256;
  m["tessera:job_options"] = wire::options_to_json(job.options);
  // job_options' batch_spp is the cap of a progressive schedule (docs/farm.md, "Batches").
  m["tessera:batch_schedule"] = std::string(to_string(job.options.batch_kind));
  m["tessera:spp"] = std::to_string(job.spp_merged);
  m["tessera:spp_min"] = std::to_string(job.reached.spp_min);
  m["tessera:spp_mean"] = std::to_string(job.reached.spp_mean);
  m["tessera:spp_max"] = std::to_string(job.reached.spp_max);
  m["tessera:stop_rule"] = std::string(to_string(job.options.rule));
  m["tessera:stop_reason"] = std::string(to_string(job.stop_reason));
  m["tessera:tile_error_max"] = std::to_string(job.reached.error_max);
  m["tessera:tile_error_mean"] = std::to_string(job.reached.error_mean);
  m["tessera:samples_merged"] = std::to_string(job.counters.samples_merged);
  if (job.options.rule == StopRule::noise) {
    m["tessera:noise_target"] = std::to_string(job.options.noise_target);
    m["tessera:max_spp"] = std::to_string(job.options.spp);
  } else if (job.options.rule == StopRule::time) {
    m["tessera:time_budget_s"] = std::to_string(job.options.time_budget_s);
    m["tessera:max_spp"] = std::to_string(job.options.spp);
  }
  m["tessera:renderer_version"] = joined(job.versions);
  m["tessera:isa"] = joined(job.isas);
  m["tessera:nan_dropped"] = std::to_string(job.counters.nan_dropped);
  m["tessera:inf_dropped"] = std::to_string(job.counters.inf_dropped);
  if (job.started_unix_ms > 0 && job.finished_unix_ms >= job.started_unix_ms) {
    m["tessera:wall_time_s"] = std::to_string(double(job.finished_unix_ms - job.started_unix_ms) / 1000.0);
  }
  return m;
}

std::vector<ExtraChannel> JobOutput::extra_channels(const JobRecord& job,
                                                    const std::vector<TileRecord>& tiles) {
  if (job.options.rule == StopRule::spp) return {};
  std::vector<TileRect> rects;
  std::vector<uint32_t> spp;
  const JobPlan plan = job.options.plan();
  for (const TileRecord& t : tiles) {
    rects.push_back(t.rect);
    spp.push_back(t.next_batch == 0 ? 0 : plan.batch_end(t.next_batch - 1));
  }
  return {{"spp", spp_channel(job.options.width, job.options.height, rects, spp)}};
}

OutputFiles JobOutput::files(const JobRecord& job) const {
  const std::string stem = "job-" + std::to_string(job.id);
  return {std::filesystem::absolute(dir_ / (stem + ".exr")),
          std::filesystem::absolute(dir_ / (stem + ".png"))};
}

OutputFiles JobOutput::write(const JobRecord& job, const std::vector<TileRecord>& tiles) const {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error(dir_.string() + ": cannot create: " + ec.message());
  const RgbImage image = resolve(job, tiles);
  ImageWriteOptions options;
  options.metadata = provenance(job);
  options.extra_channels = extra_channels(job, tiles);
  const OutputFiles out = files(job);
  write_atomically(writer_, image, out.exr, options);
  write_atomically(writer_, image, out.png, options);
  return out;
}

}  // namespace tessera::server
