// A job's image: assembled from its merged tiles (resolve_image), written as EXR (float32, with
// provenance attributes) and PNG when the job finishes, or encoded in memory as a preview.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "image/image_output.h"
#include "job_store.h"

namespace tessera::server {

struct OutputFiles {
  std::filesystem::path exr, png;
};

/// Writes one image file (core's write_image in production). The seam through which tests
/// make the disk full (ENOSPC) or fail in other ways.
using ImageFileWriter = std::function<void(const RgbImage&, const std::filesystem::path&,
                                           const ImageWriteOptions&)>;

class JobOutput {
 public:
  /// `writer` empty: write_image.
  explicit JobOutput(std::filesystem::path output_dir, ImageFileWriter writer = {})
      : dir_(std::move(output_dir)), writer_(writer ? std::move(writer) : ImageFileWriter(write_image)) {}

  /// The image of the merged samples so far: per pixel the mean of what is merged, black where
  /// nothing is. Throws CodecError when a stored tile does not decode.
  static RgbImage resolve(const JobRecord& job, const std::vector<TileRecord>& tiles);

  /// The provenance written in EXR headers and PNG text chunks (all keys "tessera:..."): job id,
  /// scene file, scene bundle SHA-256, resolved options (JSON), spp reached, renderer versions,
  /// worker ISAs, NaN/Inf samples dropped, wall time, stopping rule and reason, spp and
  /// estimated error over tiles.
  static std::map<std::string, std::string> provenance(const JobRecord& job);

  /// The EXR channels after R, G, B: for `noise` and `time` jobs, "spp" (each pixel's merged
  /// samples per pixel: its tile's); none for `spp` jobs.
  static std::vector<ExtraChannel> extra_channels(const JobRecord& job,
                                                  const std::vector<TileRecord>& tiles);

  /// Where the job's files go: <output_dir>/job-<id>.exr and .png, absolute.
  OutputFiles files(const JobRecord& job) const;

  /// Writes files(job) (each to a temporary name, then renamed, so a reader never sees half a
  /// file). Throws std::runtime_error naming the file and why (e.g. "No space left on device").
  OutputFiles write(const JobRecord& job, const std::vector<TileRecord>& tiles) const;

  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  ImageFileWriter writer_;
};

}  // namespace tessera::server
