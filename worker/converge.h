// `tessera-worker converge`: how the error of a render against a reference image falls with
// samples per pixel and with wall time (docs/accuracy.md).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "denoise/denoiser.h"
#include "image/image_output.h"
#include "job/job_options.h"
#include "scene/scene.h"

namespace tessera {

/// One image's error against the reference, and when it was there.
struct ImageMeasure {
  double seconds = 0;   ///< wall time from the start of the BVH build to this image
  double rmse = 0;      ///< root mean square difference over all pixels and channels
  double relmse = 0;    ///< mean over pixels and channels of (x - ref)^2 / (ref^2 + kRelMseEpsilon)
  glm::dvec3 mean{0.0};  ///< per-channel image mean
};

/// The error of the image after `spp` samples per pixel, and of the same image denoised.
struct ConvergenceRow : ImageMeasure {
  uint32_t spp = 0;
  /// Set when the run denoises: `seconds` also counts the guides rendered so far and this
  /// level's denoising (the raw row's time counts neither).
  std::optional<ImageMeasure> denoised;
};

/// Offset in the denominator of the relative MSE (Rousselle et al. 2011; Mitsuba and Tungsten
/// use 1e-2 as well): keeps black reference pixels from dominating.
inline constexpr double kRelMseEpsilon = 1e-2;

/// Slope of the least-squares line through (log x, log y) of the points with x in [x_min, x_max].
/// Returns NaN when fewer than two points qualify or a y is not positive.
double loglog_slope(const std::vector<double>& x, const std::vector<double>& y, double x_min,
                    double x_max);

struct ConvergenceFit {
  double spp_from = 0, spp_to = 0;  ///< the rows the fit uses
  double rmse_vs_spp = 0, relmse_vs_spp = 0;
  double rmse_vs_seconds = 0, relmse_vs_seconds = 0;
};

struct ConvergenceResult {
  std::string scene_name;
  JobOptions options;
  glm::dvec3 reference_mean{0.0};
  std::vector<ConvergenceRow> rows;
  ConvergenceFit fit;
  std::string isa;
};

/// RMSE and relative MSE of `image` against `reference` (same size).
double image_rmse(const RgbImage& image, const RgbImage& reference);
double image_relmse(const RgbImage& image, const RgbImage& reference);
glm::dvec3 image_mean(const RgbImage& image);

/// What a convergence run does beside measuring the raw image; every member optional.
struct ConvergenceHooks {
  /// Set: each level's image is also denoised, guided by the albedo and normal of its first
  /// kGuideSamples samples (accum/guide_tile.h) as `tessera-worker render --denoise`
  /// is, and measured.
  const Denoiser* denoiser = nullptr;
  /// Called after each level with its row.
  std::function<void(const ConvergenceRow&)> on_row;
  /// Called after each level with its raw image and, with a denoiser, the denoised one (else
  /// null); outside the measured time.
  std::function<void(uint32_t spp, const RgbImage& raw, const RgbImage* denoised)> on_images;
};

/// Renders `scene` progressively with `options` (its spp is the largest level) and measures the
/// image against `reference` after 1, 2, 4, ... samples per pixel (every power of two up to
/// options.spp, and options.spp itself). Samples [2^k, 2^(k+1)) are one batch, merged in order,
/// so the image at each level is the one a render of that many samples gives (every power-of-two
/// prefix of Tessera's sample sequence is stratified). The fit uses the rows with spp >= fit_from.
/// Throws std::invalid_argument when the reference's size differs from the job's.
ConvergenceResult measure_convergence(const Scene& scene, const JobOptions& options,
                                      const RgbImage& reference, uint32_t fit_from,
                                      const ConvergenceHooks& hooks = {});

/// The table as CSV (header line, one row per level) and as Markdown (with the fit below it);
/// with denoised rows, their time and errors in columns of their own.
std::string convergence_csv(const ConvergenceResult& result);
/// The raw image's RMSE at `seconds`, interpolated log-log between the rows around it; NaN
/// outside the rows' times. What plain Monte Carlo reaches in the time a denoised row took.
double raw_rmse_at(const std::vector<ConvergenceRow>& rows, double seconds);
std::string convergence_markdown(const ConvergenceResult& result);

/// Draws the plot (PNG, width x height): RMSE and relative MSE against spp (left) and against
/// wall time (right), log-log, with the fitted lines. Labels need a TrueType font
/// (`font`, default DejaVu Sans); without one the plot is drawn unlabelled and a warning goes to
/// stderr. Throws std::runtime_error when the file cannot be written.
void write_convergence_plot(const ConvergenceResult& result, const std::string& path,
                            int width = 1200, int height = 520, const std::string& font = "");

}  // namespace tessera
