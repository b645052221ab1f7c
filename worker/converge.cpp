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

ConvergenceResult measure_convergence(const Scene& scene, const JobOptions& options,
                                      const RgbImage& reference, uint32_t fit_from,
                                      const std::function<void(const ConvergenceRow&)>& on_row) {
  if (reference.width != options.width || reference.height != options.height) {
    throw std::invalid_argument("the reference is " + std::to_string(reference.width) + "x" +
                                std::to_string(reference.height) + " but the render is " +
                                std::to_string(options.width) + "x" +
                                std::to_string(options.height));
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

  double error_seconds = 0;  // time spent measuring, left out of the render time
  uint32_t done = 0;
  while (done < options.spp) {
    const uint32_t next = done == 0 ? 1 : std::min(options.spp, done * 2);
    tbb::parallel_for(size_t(0), tiles.size(),
                      [&](size_t t) { batch[t] = renderer.render(tiles[t], done, next); });
    for (size_t t = 0; t < tiles.size(); ++t) merged[t].merge(batch[t]);
    done = next;

    const Clock::time_point rendered = Clock::now();
    ConvergenceRow row;
    row.spp = done;
    row.seconds = std::chrono::duration<double>(rendered - start).count() - error_seconds;
    const RgbImage image = resolve_image(options.width, options.height, merged);
    row.rmse = image_rmse(image, reference);
    row.relmse = image_relmse(image, reference);
    row.mean = image_mean(image);
    result.rows.push_back(row);
    if (on_row) on_row(row);
    error_seconds += std::chrono::duration<double>(Clock::now() - rendered).count();
  }

  std::vector<double> spp, seconds, rmse, relmse;
  for (const ConvergenceRow& r : result.rows) {
    spp.push_back(r.spp);
    seconds.push_back(r.seconds);
    rmse.push_back(r.rmse);
    relmse.push_back(r.relmse);
  }
  ConvergenceFit& fit = result.fit;
  fit.spp_from = fit_from;
  fit.spp_to = options.spp;
  const double inf = std::numeric_limits<double>::infinity();
  fit.rmse_vs_spp = loglog_slope(spp, rmse, fit_from, inf);
  fit.relmse_vs_spp = loglog_slope(spp, relmse, fit_from, inf);
  // The same rows against their times.
  double t_from = inf;
  for (const ConvergenceRow& r : result.rows) {
    if (r.spp >= fit_from) t_from = std::min(t_from, r.seconds);
  }
  fit.rmse_vs_seconds = loglog_slope(seconds, rmse, t_from, inf);
  fit.relmse_vs_seconds = loglog_slope(seconds, relmse, t_from, inf);
  return result;
}

std::string convergence_csv(const ConvergenceResult& result) {
  std::ostringstream out;
  out << "spp,seconds,rmse,relmse,mean_r,mean_g,mean_b\n";
  char line[256];
  for (const ConvergenceRow& r : result.rows) {
    std::snprintf(line, sizeof line, "%u,%.4f,%.6g,%.6g,%.6f,%.6f,%.6f\n", r.spp, r.seconds, r.rmse,
                  r.relmse, r.mean.x, r.mean.y, r.mean.z);
    out << line;
  }
  return out.str();
}

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
    out << line;
    return out.str();
  }
  std::snprintf(line, sizeof line,
                "\nReference mean %.5f %.5f %.5f. Least-squares log-log fit over %g to %g spp: "
                "RMSE x %.3f per doubling of spp, i.e. RMSE ~ spp^%.3f and ~ time^%.3f; relative "
                "MSE ~ spp^%.3f and ~ time^%.3f.\n",
                ref.x, ref.y, ref.z, f.spp_from, f.spp_to, std::pow(2.0, f.rmse_vs_spp),
                f.rmse_vs_spp, f.rmse_vs_seconds, f.relmse_vs_spp, f.relmse_vs_seconds);
  out << line;
  return out.str();
}

}  // namespace tessera
