// Denoising a rendered image with Open Image Denoise's "RT" filter (ray-traced images, HDR),
// from colour alone or with albedo and normal guides.
#pragma once

#include <memory>
#include <string>

#include "denoise/oidn_library.h"
#include "image/image_output.h"

namespace tessera {

/// The guides OIDN takes beside colour, each the image's size: albedo (the first non-specular
/// surface's reflectance, in [0,1]) and normal (its shading normal, world space, in [-1,1]).
/// Both or neither: OIDN takes a normal only with an albedo.
struct DenoiseGuides {
  const RgbImage* albedo = nullptr;
  const RgbImage* normal = nullptr;
};

/// One OIDN CPU device, made and committed at construction. Not thread-safe: one denoise at a
/// time per Denoiser.
class Denoiser {
 public:
  /// Throws std::runtime_error with OIDN's message when the device cannot be made (e.g. a CPU
  /// without SSE4.1). `threads`: the device's worker threads (0 = OIDN's default, every core).
  explicit Denoiser(std::shared_ptr<const OidnLibrary> library, int threads = 0);
  ~Denoiser();
  Denoiser(const Denoiser&) = delete;
  Denoiser& operator=(const Denoiser&) = delete;

  /// OIDN's version as the library reports it, e.g. "2.5.1".
  std::string version() const;
  /// What the denoised file's provenance names, e.g. "Intel Open Image Denoise 2.5.1 (RT filter,
  /// hdr, colour only)".
  std::string description(bool guided) const;

  /// `color` (linear HDR radiance) denoised; with guides (both set) the filter uses them and
  /// treats them as noisy (cleanAux off) only when `clean_guides` is false. Throws
  /// std::runtime_error with OIDN's message on failure, or when the guides' size differs.
  RgbImage denoise(const RgbImage& color, const DenoiseGuides& guides = {},
                   bool clean_guides = true) const;

 private:
  /// Throws with OIDN's message if the device holds an error.
  void check(const char* what) const;

  std::shared_ptr<const OidnLibrary> library_;
  oidn::Device device_ = nullptr;
};

}  // namespace tessera
