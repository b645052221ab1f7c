#include "converge.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "accum/film.h"
#include "accum/guide_tile.h"
#include "render/renderer.h"

namespace tessera {

double loglog_slope(const std::vector<double>& x, const std::vector<double>& y, double x_min,
                    double x_max) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (x[i] < x_min || x[i] > x_max) continue;
    if (!(x[i] > 0) || !(y[i] > 0)) return std::numeric_limits<double>::quiet_NaN();
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++n;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || !(denominator > 0)) return std::numeric_limits<double>::quiet_NaN();
  return (n * sxy - sx * sy) / denominator;
}

namespace {

void check_same_size(const RgbImage& a, const RgbImage& b) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size()) {
    throw std::invalid_argument("images of different sizes");
  }
}

}  // namespace

double image_rmse(const RgbImage& image, const RgbImage& reference) {
  check_same_size(image, reference);
  double sum = 0;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double d = double(image.rgb[i]) - double(reference.rgb[i]);
    sum += d * d;
  }
  return std::sqrt(sum / double(image.rgb.size()));
}

double image_relmse(const RgbImage& image, const RgbImage& reference) {
  check_same_size(image, reference);
  double sum = 0;
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    const double r = reference.rgb[i];
    const double d = double(image.rgb[i]) - r;
    sum += d * d / (r * r + kRelMseEpsilon);
  }
  return sum / double(image.rgb.size());
}

glm::dvec3 image_mean(const RgbImage& image) {
  glm::dvec3 sum(0.0);
  const size_t pixels = image.rgb.size() / 3;
  for (size_t i = 0; i < pixels; ++i) {
    sum += glm::dvec3(image.rgb[i * 3], image.rgb[i * 3 + 1], image.rgb[i * 3 + 2]);
  }
  return pixels ? sum / double(pixels) : sum;
}

namespace {

double seconds_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

ImageMeasure measure_image(const RgbImage& image, const RgbImage& reference, double seconds) {
  ImageMeasure m;
  m.seconds = seconds;
  m.rmse = image_rmse(image, reference);
  m.relmse = image_relmse(image, reference);
  m.mean = image_mean(image);
  return m;
}

/// The log-log slopes of the rows with spp >= fit_from, against spp and against time.
ConvergenceFit fit_rows(const std::vector<ConvergenceRow>& rows, uint32_t spp_to, uint32_t fit_from) {
  std::vector<double> spp, seconds, rmse, relmse;
  for (const ConvergenceRow& r : rows) {
    spp.push_back(r.spp);
    seconds.push_back(r.seconds);
    rmse.push_back(r.rmse);
    relmse.push_back(r.relmse);
  }
  ConvergenceFit fit;
  fit.spp_from = fit_from;
  fit.spp_to = spp_to;
  const double inf = std::numeric_limits<double>::infinity();
  fit.rmse_vs_spp = loglog_slope(spp, rmse, fit_from, inf);
  fit.relmse_vs_spp = loglog_slope(spp, relmse, fit_from, inf);
  // The same rows against their times.
  double t_from = inf;
  for (const ConvergenceRow& r : rows) {
    if (r.spp >= fit_from) t_from = std::min(t_from, r.seconds);
  }
  fit.rmse_vs_seconds = loglog_slope(seconds, rmse, t_from, inf);
  fit.relmse_vs_seconds = loglog_slope(seconds, relmse, t_from, inf);
  return fit;
}

}  // namespace

ConvergenceResult measure_convergence(const Scene& scene, const JobOptions& options,
                                      const RgbImage& reference, uint32_t fit_from,
                                      const ConvergenceHooks& hooks) {
  if (reference.width != options.width || reference.height != options.height) {
    throw std::invalid_argument("the reference is " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height) + " but the render is " +
                                std::to_string(options.width) + "x" +
                                std::to_string(options.height));
  }
  if (hooks.denoiser != nullptr) {
    // OIDN loads its weights and plans its filter on the first image of a size: done once here,
    // as a render farm's process does once, so that no level's time carries it.
    RgbImage black;
    black.width = options.width;
    black.height = options.height;
    black.rgb.assign(size_t(options.width) * options.height * 3, 0.0f);
    hooks.denoiser->denoise(black);
  }
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  ConvergenceResult result;
  result.options = options;
  result.reference_mean = image_mean(reference);
  const Renderer renderer(scene, options);
  result.isa = renderer.isa();
  const std::vector<TileRect> tiles = options.plan().tiles();
  std::vector<Accumulation> merged;
  for (const TileRect& t : tiles) merged.emplace_back(t);
  std::vector<Accumulation> batch(tiles.size());
  const bool denoise = hooks.denoiser != nullptr;
  std::vector<GuideTile> guides(denoise ? tiles.size() : 0), batch_guides(guides.size());

  double error_seconds = 0;  // time spent measuring, left out of every row's time
  double guide_seconds = 0;  // time spent on the guides, in the denoised rows' time only
  uint32_t done = 0;
  while (done < options.spp) {
    const uint32_t next = done == 0 ? 1 : std::min(options.spp, done * 2);
    tbb::parallel_for(size_t(0), tiles.size(),
                      [&](size_t t) { batch[t] = renderer.render(tiles[t], done, next); });
    for (size_t t = 0; t < tiles.size(); ++t) merged[t].merge(batch[t]);
    if (denoise && done < kGuideSamples) {
      const Clock::time_point guides_start = Clock::now();
      const uint32_t end = std::min(next, kGuideSamples);
      tbb::parallel_for(size_t(0), tiles.size(),
                        [&](size_t t) { batch_guides[t] = renderer.render_guides(tiles[t], done, end); });
      for (size_t t = 0; t < tiles.size(); ++t) guides[t].merge(batch_guides[t]);
      guide_seconds += seconds_between(guides_start, Clock::now());
    }
    done = next;

    const Clock::time_point rendered = Clock::now();
    ConvergenceRow row;
    row.spp = done;
    const RgbImage image = resolve_image(options.width, options.height, merged);
    static_cast<ImageMeasure&>(row) =
        measure_image(image, reference, seconds_between(start, rendered) - error_seconds - guide_seconds);
    std::optional<RgbImage> denoised;
    if (denoise) {
      const Clock::time_point denoise_start = Clock::now();
      const GuideImages g = resolve_guides(options.width, options.height, guides);
      denoised = hooks.denoiser->denoise(image, {&g.albedo, &g.normal});
      const double denoise_seconds = seconds_between(denoise_start, Clock::now());
      row.denoised = measure_image(*denoised, reference, row.seconds + guide_seconds + denoise_seconds);
    }
    result.rows.push_back(row);
    if (hooks.on_row) hooks.on_row(row);
    if (hooks.on_images) hooks.on_images(done, image, denoised ? &*denoised : nullptr);
    error_seconds += seconds_between(rendered, Clock::now());
  }

  result.fit = fit_rows(result.rows, options.spp, fit_from);
  return result;
}

std::string convergence_csv(const ConvergenceResult& result) {
  const bool denoised = !result.rows.empty() && result.rows.front().denoised.has_value();
  std::ostringstream out;
  out << "spp,seconds,rmse,relmse,mean_r,mean_g,mean_b";
  if (denoised) out << ",denoised_seconds,denoised_rmse,denoised_relmse,denoised_mean_r,denoised_mean_g,denoised_mean_b";
  out << "\n";
  char line[256];
  const auto measure = [&](const ImageMeasure& m) {
    std::snprintf(line, sizeof line, "%.4f,%.6g,%.6g,%.6f,%.6f,%.6f", m.seconds, m.rmse, m.relmse,
                  m.mean.x, m.mean.y, m.mean.z);
    out << line;
  };
  for (const ConvergenceRow& r : result.rows) {
    out << r.spp << ',';
    measure(r);
    if (denoised && r.denoised) {
      out << ',';
      measure(*r.denoised);
    }
    out << '\n';
  }
  return out.str();
}

double raw_rmse_at(const std::vector<ConvergenceRow>& rows, double seconds) {
  for (size_t i = 1; i < rows.size(); ++i) {
    const ConvergenceRow& a = rows[i - 1];
    const ConvergenceRow& b = rows[i];
    if (seconds < a.seconds || seconds > b.seconds) continue;
    if (!(a.seconds > 0) || !(a.rmse > 0) || !(b.rmse > 0) || b.seconds <= a.seconds) return a.rmse;
    const double t = std::log(seconds / a.seconds) / std::log(b.seconds / a.seconds);
    return std::exp(std::log(a.rmse) + t * (std::log(b.rmse) - std::log(a.rmse)));
  }
  return std::numeric_limits<double>::quiet_NaN();
}

namespace {

/// The denoised rows' table, each with the raw image's RMSE at the same time.
std::string denoised_markdown(const ConvergenceResult& result) {
  if (result.rows.empty() || !result.rows.front().denoised) return "";
  std::ostringstream out;
  char line[320];
  const glm::dvec3 ref = result.reference_mean;
  const auto pct = [](double a, double b) { return b != 0 ? 100.0 * (a - b) / b : 0.0; };
  out << "\nDenoised (time includes the guides and the denoising; the raw RMSE at the same time "
         "interpolated log-log between raw rows):\n\n"
      << "| spp | time (s) | RMSE | relative MSE | image mean R G B (difference to the reference) | "
         "raw RMSE at this time |\n"
      << "|---:|---:|---:|---:|---|---:|\n";
  for (const ConvergenceRow& r : result.rows) {
    if (!r.denoised) continue;
    const ImageMeasure& d = *r.denoised;
    const double raw = raw_rmse_at(result.rows, d.seconds);
    char raw_text[32] = "beyond the run";
    if (!std::isnan(raw)) std::snprintf(raw_text, sizeof raw_text, "%.5f", raw);
    std::snprintf(line, sizeof line,
                  "| %u | %.3f | %.5f | %.3e | %.5f %.5f %.5f (%+.2f %%, %+.2f %%, %+.2f %%) | %s |\n",
                  r.spp, d.seconds, d.rmse, d.relmse, d.mean.x, d.mean.y, d.mean.z,
                  pct(d.mean.x, ref.x), pct(d.mean.y, ref.y), pct(d.mean.z, ref.z), raw_text);
    out << line;
  }
  return out.str();
}

}  // namespace

std::string convergence_markdown(const ConvergenceResult& result) {
  std::ostringstream out;
  char line[320];
  const glm::dvec3 ref = result.reference_mean;
  out << "| spp | time (s) | RMSE | relative MSE | image mean R G B (difference to the reference) |\n"
      << "|---:|---:|---:|---:|---|\n";
  const auto pct = [](double a, double b) { return b != 0 ? 100.0 * (a - b) / b : 0.0; };
  for (const ConvergenceRow& r : result.rows) {
    std::snprintf(line, sizeof line,
                  "| %u | %.3f | %.5f | %.3e | %.5f %.5f %.5f (%+.2f %%, %+.2f %%, %+.2f %%) |\n",
                  r.spp, r.seconds, r.rmse, r.relmse, r.mean.x, r.mean.y, r.mean.z,
                  pct(r.mean.x, ref.x), pct(r.mean.y, ref.y), pct(r.mean.z, ref.z));
    out << line;
  }
  const ConvergenceFit& f = result.fit;
  if (std::isnan(f.rmse_vs_spp)) {
    std::snprintf(line, sizeof line,
                  "\nReference mean %.5f %.5f %.5f. No slope: fewer than two levels from %g spp on.\n",
                  ref.x, ref.y, ref.z, f.spp_from);
    out << line << denoised_markdown(result);
    return out.str();
  }
  std::snprintf(line, sizeof line,
                "\nReference mean %.5f %.5f %.5f. Least-squares log-log fit over %g to %g spp: "
                "RMSE x %.3f per doubling of spp, i.e. RMSE ~ spp^%.3f and ~ time^%.3f; relative "
                "MSE ~ spp^%.3f and ~ time^%.3f.\n",
                ref.x, ref.y, ref.z, f.spp_from, f.spp_to, std::pow(2.0, f.rmse_vs_spp),
                f.rmse_vs_spp, f.rmse_vs_seconds, f.relmse_vs_spp, f.relmse_vs_seconds);
  out << line << denoised_markdown(result);
  return out.str();
}

}  // namespace tessera
