// JobImages' denoising (job_images.h): a denoise job's guides merged from the store, its image
// denoised once when it is done (written beside the raw files) or on request as a preview.
#include <filesystem>
#include <iostream>

#include "farm_error.h"
#include "job_images.h"
#include "store/guide_results_table.h"

namespace tessera::server {
void JobImages::check_denoise(int width, int height) const {
  if (!denoise_) {
    throw FarmError(ErrorCode::failed_precondition, "this server was started without a denoiser");
  }
  denoise_->check_submit(width, height);
}

TileGuideReader JobImages::guide_reader(const JobRecord& record, std::vector<TilePosition> tiles) {
  const JobPlan plan = record.options.plan();
  return [this, id = record.id, plan, tiles = std::move(tiles)](uint32_t t) {
    GuideRows rows;
    {
      FarmStore::ReadLock lock(store_);
      GuideResultsTable(store_.db())
          .for_each_below(id, t, tiles.at(t).next_batch,
                          [&](uint32_t batch, const std::string& bytes) {
                            rows.emplace_back(batch, bytes);
                          });
    }
    return merge_tile_guides(id, t, tiles.at(t), plan, rows);
  };
}

JobDenoise::Denoised JobImages::denoised(const JobRecord& record,
                                         const std::vector<TilePosition>& tiles) {
  if (!denoise_) {
    throw FarmError(ErrorCode::failed_precondition, "this server was started without a denoiser");
  }
  // Assembled once the denoise has its turn and its memory.
  const auto input = [&] {
    JobDenoise::Input in;
    in.color = JobOutput::assemble(record, tiles, checkpoint_reader(record.id));
    try {
      const TileGuideReader read = guide_reader(record, tiles);
      std::vector<GuideTile> all;
      for (uint32_t t = 0; t < uint32_t(tiles.size()); ++t) all.push_back(read(t));
      in.guides = resolve_guides(record.options.width, record.options.height, all);
    } catch (const std::exception& e) {
      std::cerr << "tessera-server: " << e.what() << "; job " << record.id
                << " is denoised from its colour alone" << std::endl;
    }
    return in;
  };
  return denoise_->denoise("job " + std::to_string(record.id) + "'s denoise",
                           record.options.width, record.options.height, input);
}

void JobImages::write_denoised(const JobRecord& record, const std::vector<TilePosition>& tiles) {
  std::string why;
  try {
    const JobDenoise::Denoised d = denoised(record, tiles);
    output_.write_denoised(record, d.image, d.denoiser, d.seconds);
    std::cerr << "tessera-server: job " << record.id << " denoised in " << d.seconds << " s ("
              << d.denoiser << ")" << std::endl;
  } catch (const std::exception& e) {
    why = e.what();
    if (why.empty()) why = "unknown error";
    std::cerr << "tessera-server: job " << record.id << " is done but was not denoised: " << why
              << std::endl;
  }
  std::lock_guard guard(finishing_mu_);
  if (why.empty()) {
    denoise_errors_.erase(record.id);
  } else {
    denoise_errors_[record.id] = why;
  }
}

void JobImages::denoised_image(const JobRecord& record, const std::string& format,
                               JobImage& out) {
  if (!record.denoise) {
    throw FarmError(ErrorCode::failed_precondition,
                    "job " + std::to_string(record.id) +
                        " was not submitted with --denoise: it has no denoised image");
  }
  if (out.final) {
    const OutputFiles files = output_.denoised_files(record);
    const std::filesystem::path& path = format == "exr" ? files.exr : files.png;
    std::optional<std::string> bytes = read_output_file(path);
    if (!bytes) {
      write_denoised(record, checkpointed_tiles(record.id));
      bytes = read_output_file(path);
    }
    if (bytes) {
      out.bytes = std::move(*bytes);
      return;
    }
  }
  // A preview: the merged tiles so far, denoised now.
  const JobDenoise::Denoised d = denoised(record, checkpointed_tiles(record.id, !out.final));
  out.bytes = JobOutput::encode_denoised(record, d.image, d.denoiser, d.seconds, format);
}

}  // namespace tessera::server
