#include "denoise/denoised_outputs.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>

namespace tessera {

std::vector<std::string> denoised_output_paths(const std::vector<std::string>& raw) {
  std::vector<std::string> paths;
  const auto add = [&](const std::string& path) {
    if (std::find(paths.begin(), paths.end(), path) == paths.end()) paths.push_back(path);
  };
  for (const std::string& output : raw) {
    const std::filesystem::path path(output);
    const std::string ext = path.extension().string();
    const std::string denoised = std::filesystem::path(path).replace_extension().string() + ".denoised";
    add(denoised + ext);
    std::string lower = ext;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (lower == ".png") add(denoised + ".exr");
  }
  return paths;
}

double write_denoised_outputs(const Denoiser& denoiser, const RgbImage& raw,
                              const DenoiseGuides& guides, const std::vector<std::string>& outputs,
                              ImageWriteOptions write) {
  const auto start = std::chrono::steady_clock::now();
  const RgbImage denoised = denoiser.denoise(raw, guides);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const bool guided = guides.albedo != nullptr && guides.normal != nullptr;
  write.metadata["tessera:denoiser"] = denoiser.description(guided);
  write.metadata["tessera:denoise_s"] = std::to_string(seconds);
  for (const std::string& path : denoised_output_paths(outputs)) write_image(denoised, path, write);
  return seconds;
}

}  // namespace tessera
