// Where a denoised image goes: beside each raw output, NAME.denoised.EXT.
#pragma once

#include <string>
#include <vector>

#include "denoise/denoiser.h"
#include "image/image_output.h"

namespace tessera {

/// The denoised files for a render's outputs `raw` (.exr or .png): for X.exr, X.denoised.exr;
/// for X.png, X.denoised.png and X.denoised.exr (the denoised radiance is always kept as an
/// EXR). Each path once, in the order of `raw`.
std::vector<std::string> denoised_output_paths(const std::vector<std::string>& raw);

/// Denoises `raw` (with `guides` where both are set) and writes it to each of
/// denoised_output_paths(outputs) with `write`'s options, its metadata naming the denoiser
/// ("tessera:denoiser", "tessera:denoise_s"). Returns the seconds the denoising took (the
/// filter alone, not the files).
double write_denoised_outputs(const Denoiser& denoiser, const RgbImage& raw,
                              const DenoiseGuides& guides, const std::vector<std::string>& outputs,
                              ImageWriteOptions write);

}  // namespace tessera
