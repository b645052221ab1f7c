// A job's image: assembled from its merged tiles (sums / count, black where nothing is merged) a
// row of tiles at a time, written as EXR (float32, with provenance attributes) and PNG when the
// job finishes, or encoded in memory as a preview.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "image/image_output.h"
#include "job_guides.h"
#include "job_store.h"
#include "store/tiles_table.h"

namespace tessera::server {

struct OutputFiles {
  std::filesystem::path exr, png;
};

/// Opens one image file for writing band by band (an ImageFileStream in production). The seam
/// through which tests make the disk full (ENOSPC) or fail in other ways.
using ImageFileOpener = std::function<ImageFileStream(const std::filesystem::path&, int width, int height,
                                                      const ImageWriteOptions&)>;

/// A tile's checkpoint bytes (encode_accumulation; empty when nothing is merged), read from the
/// store when the output writer reaches its row.
using TileCheckpointReader = std::function<std::string(uint32_t tile)>;

/// A written output file's bytes; nullopt when it cannot be read (missing).
std::optional<std::string> read_output_file(const std::filesystem::path& path);

class JobOutput {
 public:
  /// `opener` empty: an ImageFileStream.
  explicit JobOutput(std::filesystem::path output_dir, ImageFileOpener opener = {});

  /// The provenance written in EXR headers and PNG text chunks (all keys "tessera:..."): job id,
  /// scene file, scene bundle SHA-256, resolved options (JSON), spp reached, renderer versions,
  /// worker ISAs, NaN/Inf samples dropped, wall time, stopping rule and reason, spp and
  /// estimated error over tiles.
  static std::map<std::string, std::string> provenance(const JobRecord& job);

  /// Where the job's files go: <output_dir>/job-<id>.exr and .png, absolute.
  OutputFiles files(const JobRecord& job) const;

  /// Writes files(job), both a row of tiles at a time: each row's checkpoints read, decoded and
  /// resolved into a band of rows that goes to the EXR and the PNG before the next row is read, so
  /// the server holds a band of the image, not the image and every tile's bytes (an 8192 x 8192 job
  /// took 3 GiB more than its merge state that way: BENCHMARKS.md, "Server memory on the largest
  /// image"). `tiles`: every tile's rectangle and merged prefix, in tile order (tile i at index i);
  /// `checkpoint` reads a tile's bytes. Each file goes to a temporary name and is renamed into
  /// place when whole, so a reader never sees half a file. Throws std::runtime_error naming the
  /// file and why (e.g. "No space left on device"). A job with `guides` needs `guides`, whose
  /// tiles go into the EXR as channels albedo.R/G/B and N.X/Y/Z (after spp), as a local render's.
  OutputFiles write(const JobRecord& job, const std::vector<TilePosition>& tiles,
                    const TileCheckpointReader& checkpoint,
                    const TileGuideReader& guides = {}) const;

  /// What the server answers for a job's image before its files exist (a preview): the file of
  /// `format` ("exr" or "png") encoded in memory, a row of tiles at a time as write's.
  static std::string encode(const JobRecord& job, const std::vector<TilePosition>& tiles,
                            const TileCheckpointReader& checkpoint, const std::string& format,
                            const TileGuideReader& guides = {});

  /// The whole image, as write's bands make it (a denoise's input).
  static RgbImage assemble(const JobRecord& job, const std::vector<TilePosition>& tiles,
                           const TileCheckpointReader& checkpoint);
  /// Where the denoised files go: job-<id>.denoised.exr and .denoised.png, absolute.
  OutputFiles denoised_files(const JobRecord& job) const;
  /// Writes the denoised image to denoised_files(job) (each to a temporary name, then renamed),
  /// with the job's provenance and the denoiser's ("tessera:denoiser", "tessera:denoise_s").
  /// Throws std::runtime_error as write().
  OutputFiles write_denoised(const JobRecord& job, const RgbImage& denoised,
                             const std::string& denoiser, double seconds) const;
  /// The denoised image encoded in memory as `format` ("exr" or "png"), with that provenance.
  static std::string encode_denoised(const JobRecord& job, const RgbImage& denoised,
                                     const std::string& denoiser, double seconds,
                                     const std::string& format);

  const std::filesystem::path& dir() const { return dir_; }

 private:
  using BandFn = std::function<void(const RgbImage&, const std::vector<ExtraChannel>&)>;
  /// The image's rows of tiles, top to bottom: each resolved into a band of rows (black where
  /// nothing is merged) and handed to `band_fn` with the band's extra channels (file_options'),
  /// the guides' among them when `guides` is set.
  static void for_each_band(const JobRecord& job, const std::vector<TilePosition>& tiles,
                            const TileCheckpointReader& checkpoint, const TileGuideReader& guides,
                            const BandFn& band_fn);
  /// Provenance and the extra channels' names of the job's files; the guides' with `guides`.
  static ImageWriteOptions file_options(const JobRecord& job, bool guides);
  /// Provenance of the job's denoised files (no extra channels).
  static ImageWriteOptions denoised_options(const JobRecord& job, const std::string& denoiser,
                                            double seconds);

  std::filesystem::path dir_;
  ImageFileOpener opener_;
};

}  // namespace tessera::server
