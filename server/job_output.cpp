#include "job_output.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>

#include "accum/accumulation_codec.h"
#include "accum/film.h"
#include "denoise/denoised_outputs.h"
#include "job/provenance.h"
#include "job/tile_summary.h"
#include "wire/job_options_wire.h"

namespace tessera::server {
namespace {

std::string joined(const std::vector<std::string>& items, const char* separator = ",") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : separator) + s;
  return out;
}

}  // namespace

std::optional<std::string> read_output_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream ss;
  ss << in.rdbuf();
  return std::move(ss).str();
}

JobOutput::JobOutput(std::filesystem::path output_dir, ImageFileOpener opener)
    : dir_(std::move(output_dir)), opener_(std::move(opener)) {
  if (!opener_) {
    opener_ = [](const std::filesystem::path& path, int width, int height, const ImageWriteOptions& options) {
      return ImageFileStream(path, width, height, options);
    };
  }
}

std::map<std::string, std::string> JobOutput::provenance(const JobRecord& job) {
  Provenance p;
  p.scene_file = job.scene_file;
  // A worker's build names its commit, compiler, Embree and C library, with commas
  // (worker/render/renderer_build.h): builds are separated by "; ".
  p.renderer = joined(job.versions, "; ");
  p.isa = joined(job.isas);
  p.options = &job.options;
  p.stop_reason = job.stop_reason;
  p.spp = job.spp_merged;
  p.reached = job.reached;
  p.nan_dropped = job.counters.nan_dropped;
  p.inf_dropped = job.counters.inf_dropped;
  if (job.started_unix_ms > 0 && job.finished_unix_ms >= job.started_unix_ms) {
    p.wall_time_s = double(job.finished_unix_ms - job.started_unix_ms) / 1000.0;
  }
  p.job_id = job.id;
  p.scene_sha256 = job.bundle_sha256;
  p.options_json = wire::options_to_json(job.options);
  p.samples_merged = job.counters.samples_merged;
  return provenance_metadata(p);
}

OutputFiles JobOutput::files(const JobRecord& job) const {
  const std::string stem = "job-" + std::to_string(job.id);
  return {std::filesystem::absolute(dir_ / (stem + ".exr")),
          std::filesystem::absolute(dir_ / (stem + ".png"))};
}

void JobOutput::for_each_band(const JobRecord& job, const std::vector<TilePosition>& tiles,
                              const TileCheckpointReader& checkpoint, const TileGuideReader& guides,
                              const BandFn& band_fn) {
  const int width = job.options.width, height = job.options.height;
  const std::string what = "job " + std::to_string(job.id) + "'s image";
  // The rows of tiles, top to bottom, each tile's index in x order.
  std::map<int, std::vector<uint32_t>> rows_of_tiles;
  for (uint32_t t = 0; t < uint32_t(tiles.size()); ++t) rows_of_tiles[tiles[t].rect.y0].push_back(t);
  const bool with_spp = job.options.rule != StopRule::spp;
  const JobPlan plan = job.options.plan();
  RgbImage band;
  band.width = width;
  std::vector<ExtraChannel> extra(with_spp ? 1 : 0, ExtraChannel{"spp", {}});
  int next_row = 0;
  for (const auto& [y0, row] : rows_of_tiles) {
    const int rows = tiles[row.front()].rect.y1 - y0;
    if (y0 != next_row || rows <= 0) {
      throw std::runtime_error(what + ": its tiles leave rows " + std::to_string(next_row) + " to " +
                               std::to_string(y0 - 1) + " uncovered");
    }
    band.height = rows;
    band.rgb.assign(size_t(width) * size_t(rows) * 3, 0.0f);
    std::vector<TileRect> band_rects;  // the row's tiles in the band's rows, and their spp
    std::vector<uint32_t> band_spp;
    std::vector<GuideTile> band_guides;  // the row's tiles' guides in the band's rows
    for (const uint32_t t : row) {
      const TilePosition& tile = tiles[t];
      if (tile.rect.y1 - tile.rect.y0 != rows || tile.rect.x0 < 0 || tile.rect.x1 > width) {
        throw std::runtime_error(what + ": tile " + std::to_string(t) + " does not fit its row of tiles");
      }
      const std::string bytes = checkpoint(t);
      if (!bytes.empty()) {
        Accumulation acc = decode_accumulation(bytes);
        if (!(acc.rect == tile.rect)) {
          throw std::runtime_error(what + ": tile " + std::to_string(t) + "'s stored sum covers another rectangle");
        }
        acc.rect.y0 -= y0;  // into the band's rows
        acc.rect.y1 -= y0;
        resolve_into(band, acc);
      }
      if (with_spp) {
        band_rects.push_back({tile.rect.x0, 0, tile.rect.x1, rows});
        band_spp.push_back(tile.next_batch == 0 ? 0 : plan.batch_end(tile.next_batch - 1));
      }
      if (guides) {
        band_guides.push_back(guides(t));
        band_guides.back().rect = {tile.rect.x0, 0, tile.rect.x1, rows};
      }
    }
    if (with_spp) extra[0].values = spp_channel(width, rows, band_rects, band_spp);
    extra.resize(with_spp ? 1 : 0);
    if (guides) {
      for (ExtraChannel& c : guide_channels(resolve_guides(width, rows, band_guides))) {
        extra.push_back(std::move(c));
      }
    }
    band_fn(band, extra);
    next_row = y0 + rows;
  }
  if (next_row != height) {
    throw std::runtime_error(what + ": its tiles leave rows " + std::to_string(next_row) + " to " +
                             std::to_string(height - 1) + " uncovered");
  }
}

ImageWriteOptions JobOutput::file_options(const JobRecord& job, bool guides) {
  ImageWriteOptions options;
  options.metadata = provenance(job);
  // For `noise` and `time` jobs, each pixel's merged samples per pixel (its tile's), after R, G, B.
  if (job.options.rule != StopRule::spp) options.extra_channels = {{"spp", {}}};
  if (guides) {
    for (const char* name : {"albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z"}) {
      options.extra_channels.push_back({name, {}});
    }
  }
  return options;
}

OutputFiles JobOutput::write(const JobRecord& job, const std::vector<TilePosition>& tiles,
                             const TileCheckpointReader& checkpoint,
                             const TileGuideReader& guides) const {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw std::runtime_error(dir_.string() + ": cannot create: " + ec.message());
  const TileGuideReader with_guides = job.guides ? guides : TileGuideReader{};
  const ImageWriteOptions options = file_options(job, bool(with_guides));
  const OutputFiles out = files(job);
  ImageFileStream exr = opener_(out.exr, job.options.width, job.options.height, options);
  ImageFileStream png = opener_(out.png, job.options.width, job.options.height, options);
  for_each_band(job, tiles, checkpoint, with_guides,
                [&](const RgbImage& band, const std::vector<ExtraChannel>& extra) {
                  exr.write_rows(band, extra);
                  png.write_rows(band);
                });
  exr.finish();
  png.finish();
  return out;
}

std::string JobOutput::encode(const JobRecord& job, const std::vector<TilePosition>& tiles,
                              const TileCheckpointReader& checkpoint, const std::string& format,
                              const TileGuideReader& guides) {
  const TileGuideReader with_guides = job.guides && format == "exr" ? guides : TileGuideReader{};
  ImageWriteOptions options = file_options(job, bool(with_guides));
  if (format != "exr") options.extra_channels.clear();
  ImageFileStream stream = ImageFileStream::in_memory(format, job.options.width, job.options.height, options);
  for_each_band(job, tiles, checkpoint, with_guides,
                [&](const RgbImage& band, const std::vector<ExtraChannel>& extra) {
                  stream.write_rows(band, format == "exr" ? extra : std::vector<ExtraChannel>{});
                });
  stream.finish();
  return stream.take_bytes();
}

RgbImage JobOutput::assemble(const JobRecord& job, const std::vector<TilePosition>& tiles,
                             const TileCheckpointReader& checkpoint) {
  RgbImage image{job.options.width, job.options.height,
                 std::vector<float>(size_t(job.options.width) * size_t(job.options.height) * 3)};
  size_t at = 0;
  for_each_band(job, tiles, checkpoint, {},
                [&](const RgbImage& band, const std::vector<ExtraChannel>&) {
                  std::copy(band.rgb.begin(), band.rgb.end(), image.rgb.begin() + ptrdiff_t(at));
                  at += band.rgb.size();
                });
  return image;
}

OutputFiles JobOutput::denoised_files(const JobRecord& job) const {
  const OutputFiles raw = files(job);
  const std::vector<std::string> paths =
      denoised_output_paths({raw.exr.string(), raw.png.string()});
  // [stem.denoised.exr, stem.denoised.png] (the PNG's EXR is the first one).
  return {paths.at(0), paths.at(1)};
}

ImageWriteOptions JobOutput::denoised_options(const JobRecord& job, const std::string& denoiser,
                                              double seconds) {
  ImageWriteOptions options;
  options.metadata = provenance(job);
  options.metadata["tessera:denoiser"] = denoiser;
  options.metadata["tessera:denoise_s"] = std::to_string(seconds);
  return options;
}

OutputFiles JobOutput::write_denoised(const JobRecord& job, const RgbImage& denoised,
                                      const std::string& denoiser, double seconds) const {
  const ImageWriteOptions options = denoised_options(job, denoiser, seconds);
  const OutputFiles out = denoised_files(job);
  for (const std::filesystem::path& path : {out.exr, out.png}) {
    ImageFileStream file = opener_(path, denoised.width, denoised.height, options);
    file.write_rows(denoised);
    file.finish();
  }
  return out;
}

std::string JobOutput::encode_denoised(const JobRecord& job, const RgbImage& denoised,
                                       const std::string& denoiser, double seconds,
                                       const std::string& format) {
  return encode_image(denoised, format, denoised_options(job, denoiser, seconds));
}

}  // namespace tessera::server
