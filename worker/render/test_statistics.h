// Statistics for the renderer's statistical tests: means of accumulations with their standard
// error estimated from the samples themselves, so that every tolerance is a number of standard
// errors, never a value tuned to pass.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "accum/accumulation.h"
#include "render/testing/test_scenes.h"
#include "renderer.h"
#include "scene/scene.h"

namespace tessera::test {

/// How many standard errors a statistical test allows. With the fixed seeds of the tests a
/// pass is reproducible; 5 sigma keeps the chance that an unbiased renderer fails a fresh seed
/// below 1e-6 per comparison.
inline constexpr double kSigmas = 5.0;

/// Relative rounding allowance for a mean computed from float path arithmetic (throughput,
/// emission and geometry are float; sums are double): a path of tens of float operations is
/// exact to ~1e-6 relative, the allowance adds a margin of 10. It matters only for estimators
/// with (nearly) zero variance, where 5 standard errors would be 0.
inline constexpr double kFloatRounding = 1e-5;

/// A Monte Carlo mean and its estimated standard error.
struct Estimate {
  double mean = 0;
  double se = 0;
  uint64_t samples = 0;
};

/// The mean luminance over the pixels of `acc` (each pixel weighted alike) and its standard
/// error, from each pixel's sample variance (sum of squared luminance). Samples of one pixel are
/// treated as independent: for Tessera's stratified samples this over-estimates the error, so a
/// test using it is conservative, never tight by luck. Pixels with one sample add to the mean
/// but not to the error (their variance is unknown).
inline Estimate mean_luminance(const Accumulation& acc) {
  Estimate e;
  double var_of_sum = 0;
  const double pixels = double(acc.pixels());
  for (size_t i = 0; i < acc.pixels(); ++i) {
    const double n = acc.count[i];
    if (n < 1) continue;
    const double m = luminance(acc.rgb[i * 3], acc.rgb[i * 3 + 1], acc.rgb[i * 3 + 2]) / n;
    e.mean += m;
    e.samples += uint64_t(n);
    if (n >= 2) var_of_sum += std::max(0.0, (acc.lum2[i] - n * m * m) / (n - 1)) / n;
  }
  e.mean /= pixels;
  e.se = std::sqrt(var_of_sum) / pixels;
  return e;
}

/// The mean luminance of one pixel with its standard error.
inline Estimate pixel_luminance(const Accumulation& acc, size_t i) {
  Estimate e;
  const double n = acc.count[i];
  e.samples = uint64_t(n);
  if (n < 1) return e;
  e.mean = luminance(acc.rgb[i * 3], acc.rgb[i * 3 + 1], acc.rgb[i * 3 + 2]) / n;
  if (n >= 2) e.se = std::sqrt(std::max(0.0, (acc.lum2[i] - n * e.mean * e.mean) / (n - 1)) / n);
  return e;
}

/// The tolerance for comparing an estimate with an exact value.
inline double tolerance(const Estimate& e, double expected) {
  return kSigmas * e.se + kFloatRounding * std::abs(expected);
}

/// The tolerance for comparing two independent estimates of the same quantity.
inline double tolerance(const Estimate& a, const Estimate& b) {
  return kSigmas * std::sqrt(a.se * a.se + b.se * b.se) +
         kFloatRounding * std::max(std::abs(a.mean), std::abs(b.mean));
}

/// True when every sum of the accumulation is finite and no sample was dropped.
inline bool all_finite(const Accumulation& acc) {
  for (double v : acc.rgb) {
    if (!std::isfinite(v)) return false;
  }
  for (double v : acc.lum2) {
    if (!std::isfinite(v)) return false;
  }
  return acc.nan_dropped == 0 && acc.inf_dropped == 0;
}

/// The blocks of `block` x `block` pixels (of images `width` pixels wide, the same size) whose
/// mean luminances in a and b differ by more than tolerance(): each as "block at x, y: a vs b"
/// (empty when every block agrees). For comparing two renders of one scene that must have the
/// same expectation (a sampling strategy on and off).
inline std::vector<std::string> differing_blocks(const Accumulation& a, const Accumulation& b, int width,
                                                 int block) {
  std::vector<std::string> out;
  const int height = int(a.count.size()) / width;
  for (int by = 0; by + block <= height; by += block) {
    for (int bx = 0; bx + block <= width; bx += block) {
      Estimate ea, eb;
      for (int y = by; y < by + block; ++y) {
        for (int x = bx; x < bx + block; ++x) {
          const Estimate pa = pixel_luminance(a, size_t(y * width + x));
          const Estimate pb = pixel_luminance(b, size_t(y * width + x));
          ea.mean += pa.mean / (block * block);
          eb.mean += pb.mean / (block * block);
          ea.se += pa.se * pa.se;
          eb.se += pb.se * pb.se;
        }
      }
      ea.se = std::sqrt(ea.se) / (block * block);
      eb.se = std::sqrt(eb.se) / (block * block);
      if (std::abs(ea.mean - eb.mean) > tolerance(ea, eb)) {
        out.push_back("block at " + std::to_string(bx) + ", " + std::to_string(by) + ": " +
                      std::to_string(ea.mean) + " vs " + std::to_string(eb.mean));
      }
    }
  }
  return out;
}

/// Job options for a small test render; the batch is the whole range unless given.
inline JobOptions test_job(int w, int h, uint32_t spp, int max_depth = -1, uint64_t seed = 11) {
  JobOptions o;
  o.width = w;
  o.height = h;
  o.spp = spp;
  o.max_depth = max_depth;
  o.seed = seed;
  o.tile_size = 64;
  o.batch_spp = spp;
  return o;
}

/// Renders samples [0, spp) of the whole (small) image in batches of `batch` samples, merged in
/// batch order as the farm merges them.
inline Accumulation render_batches(const Renderer& renderer, uint32_t spp, uint32_t batch,
                                   RenderStats* stats = nullptr) {
  const JobOptions& o = renderer.options();
  const TileRect all{0, 0, o.width, o.height};
  Accumulation acc(all);
  for (uint32_t begin = 0; begin < spp; begin += batch) {
    acc.merge(renderer.render(all, begin, std::min(spp, begin + batch), stats));
  }
  return acc;
}

/// A white furnace: the camera inside a closed diffuse enclosure of albedo `albedo` that emits
/// `le` everywhere. Every point then sees radiance le * sum_{k < depth} albedo^k, i.e.
/// le / (1 - albedo) unbounded (furnace_expected).
inline Scene furnace_scene(bool sphere_enclosure, double albedo, double le, double scale = 1.0) {
  Scene s;
  s.camera.position = {0.1 * scale, 0.05 * scale, 0.2 * scale};
  s.camera.look_at = {0.3 * scale, -0.2 * scale, -0.5 * scale};
  s.camera.fov_deg = 90;
  const uint32_t m = add_diffuse(s, {albedo, albedo, albedo});
  Shape enclosure = sphere_enclosure ? sphere({0, 0, 0}, scale, m, /*inward=*/true)
                                     : box({-scale, -scale, -scale}, {scale, scale, scale}, m, true);
  enclosure.emission = {le, le, le};
  s.shapes.push_back(enclosure);
  return s;
}

/// The radiance everywhere in a white furnace with Mitsuba's max_depth (-1 = unbounded).
inline double furnace_expected(double albedo, double le, int max_depth) {
  if (max_depth < 0) return le / (1.0 - albedo);
  return le * (1.0 - std::pow(albedo, max_depth)) / (1.0 - albedo);
}

}  // namespace tessera::test
