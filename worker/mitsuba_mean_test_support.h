// Test support: a scene rendered as `tessera-worker render` renders it, compared with Mitsuba
// 3.9.1's image mean per channel, by scripts/mitsuba_sweep.py's rule (within 4 sigma or 1 %).
// The means come from a committed text file that a committed script made with Mitsuba (e.g.
// worker/render/bsdf/mitsuba_hair_scene.py -> mitsuba_hair_scene.txt), one line per channel:
//
//   [SCENE] CHANNEL MEAN STANDARD_ERROR      # CHANNEL r, g or b; '#' starts a comment line
//
// Used by the hair, volume-texture and SDF-grid scene tests.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "scene/scene.h"

namespace tessera::mitsuba_mean {

/// Mitsuba's mean and its standard error per channel (r, g, b).
struct MitsubaMean {
  std::array<double, 3> mean{}, se{};
};

/// Reads a means file: scene name -> means ("" for files whose lines carry no scene name).
/// Adds a test failure for a file that cannot be read or a malformed line.
inline std::map<std::string, MitsubaMean> read_mitsuba_means(const std::string& path) {
  std::map<std::string, MitsubaMean> out;
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot read " << path;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string f; row >> f;) fields.push_back(f);
    if (fields.size() != 3 && fields.size() != 4) {
      ADD_FAILURE() << path << ": expected [scene] channel mean se: " << line;
      continue;
    }
    const std::string scene = fields.size() == 4 ? fields[0] : "";
    const std::string& channel = fields[fields.size() - 3];
    const int c = channel == "r" ? 0 : channel == "g" ? 1 : channel == "b" ? 2 : -1;
    if (c < 0) {
      ADD_FAILURE() << path << ": channel must be r, g or b: " << line;
      continue;
    }
    out[scene].mean[c] = std::stod(fields[fields.size() - 2]);
    out[scene].se[c] = std::stod(fields[fields.size() - 1]);
  }
  return out;
}

/// Renders `scene` at its own film size with `spp` samples and seeds 0 and 1 (no NaN or Inf may
/// be dropped) and expects the two renders' mean, leaving out `border` pixels on each side (as
/// the Mitsuba script left them out), within 4 sigma or 1 % of `mitsuba` per channel. Sigma
/// combines Mitsuba's standard error with Tessera's, estimated from the two seeds' per-pixel
/// difference (as scripts/mitsuba_sweep.py estimates it). `label` names the scene in failures.
inline void expect_mean_matches_mitsuba(const Scene& scene, int spp, int border,
                                        const MitsubaMean& mitsuba, const std::string& label) {
  std::array<RgbImage, 2> images;
  for (int seed = 0; seed < 2; ++seed) {
    JobOverrides overrides;
    overrides.spp = spp;
    overrides.seed = uint64_t(seed);
    const JobOptions options = resolve_job_options(scene, overrides);
    const LocalRenderResult result = render_job(scene, options);
    for (const Accumulation& t : result.tiles) {
      EXPECT_EQ(t.nan_dropped + t.inf_dropped, 0u) << label;
    }
    images[seed] = resolve_image(options.width, options.height, result.tiles);
  }
  const RgbImage& a = images[0];
  const RgbImage& b = images[1];
  std::array<double, 3> sum{0, 0, 0}, diff2{0, 0, 0};
  int n = 0;
  for (int y = border; y < a.height - border; ++y) {
    for (int x = border; x < a.width - border; ++x, ++n) {
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * a.width + x) * 3 + c;
        sum[c] += double(a.rgb[i]) + double(b.rgb[i]);
        const double d = double(a.rgb[i]) - b.rgb[i];
        diff2[c] += d * d;
      }
    }
  }
  ASSERT_GT(n, 0) << label << ": the border leaves no pixel";
  for (int c = 0; c < 3; ++c) {
    const double tessera = sum[c] / (2.0 * n);
    // Variance of one render's mean is mean((a - b)^2) / (2 n); of the two renders' mean, half.
    const double tessera_var = diff2[c] / n / (2.0 * n) / 2.0;
    const double sigma = std::sqrt(tessera_var + mitsuba.se[c] * mitsuba.se[c]);
    const double delta = std::abs(tessera - mitsuba.mean[c]);
    EXPECT_TRUE(delta <= 4 * sigma || delta <= 0.01 * mitsuba.mean[c])
        << label << " channel " << c << ": Tessera " << tessera << ", Mitsuba " << mitsuba.mean[c]
        << " (" << 100 * (tessera - mitsuba.mean[c]) / mitsuba.mean[c] << " %, " << delta / sigma
        << " sigma)";
  }
}

}  // namespace tessera::mitsuba_mean
