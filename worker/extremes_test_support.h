// What the extremes tests of the materials (render/bsdf/material_extremes_test.cpp) and the
// lights (render/light/light_extremes_test.cpp) share: a scene folder, files written into it, and
// the scene rendered the way `tessera-worker render` renders a file (render_job: the farm's tile, batch and
// merge path), then checked for NaN, Inf and black pixels (docs/accuracy.md, "The extremes, each
// a test").
#pragma once

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "accum/film.h"
#include "job/job_options.h"
#include "local_render.h"
#include "scene/loader/scene_loader.h"

namespace tessera::extremes_test {

namespace fs = std::filesystem;

/// A fresh, empty folder for one test's scene files, removed with its contents at the end of
/// the scope. Its name holds the process id, so that two builds' test runs never share one.
class SceneFolder {
 public:
  explicit SceneFolder(const std::string& name)
      : dir_(fs::path(::testing::TempDir()) /
             ("tessera_extremes_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~SceneFolder() {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  SceneFolder(const SceneFolder&) = delete;
  SceneFolder& operator=(const SceneFolder&) = delete;
  fs::path operator/(const std::string& file) const { return dir_ / file; }
  const fs::path& path() const { return dir_; }

 private:
  fs::path dir_;
};

inline void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  ASSERT_TRUE(out.good()) << path;
}

/// What `tessera-worker render` computes for a scene file, and what it counted as dropped.
struct Rendered {
  RgbImage image;
  uint64_t nan_dropped = 0, inf_dropped = 0;

  glm::dvec3 pixel(int x, int y) const {
    const size_t i = (size_t(y) * size_t(image.width) + size_t(x)) * 3;
    return {image.rgb[i], image.rgb[i + 1], image.rgb[i + 2]};
  }
  double luminance(int x, int y) const {
    const glm::dvec3 p = pixel(x, y);
    return 0.2126 * p.x + 0.7152 * p.y + 0.0722 * p.z;
  }
  double mean_luminance() const {
    double sum = 0;
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) sum += luminance(x, y);
    }
    return sum / (double(image.width) * image.height);
  }
};

inline Rendered render_file(const fs::path& scene_file, int width, int height, int spp,
                     int max_depth = -1) {
  const Scene scene = load_scene_file(scene_file);
  JobOverrides overrides;
  overrides.width = width;
  overrides.height = height;
  overrides.spp = spp;
  overrides.max_depth = max_depth;
  overrides.seed = 5;
  overrides.tile_size = 8;  // several tiles, as on the farm
  const JobOptions options = resolve_job_options(scene, overrides);
  const LocalRenderResult result = render_job(scene, options);
  Rendered r;
  r.image = resolve_image(options.width, options.height, result.tiles);
  for (const Accumulation& t : result.tiles) {
    r.nan_dropped += t.nan_dropped;
    r.inf_dropped += t.inf_dropped;
  }
  return r;
}

/// No sample was dropped as NaN or Inf and every pixel is finite and >= 0; with `positive`,
/// every pixel is > 0 too. Failures name the case and the first bad pixel.
inline void expect_finite(const Rendered& r, const std::string& what, bool positive) {
  EXPECT_EQ(r.nan_dropped, 0u) << what << ": NaN samples";
  EXPECT_EQ(r.inf_dropped, 0u) << what << ": Inf samples";
  int bad = 0, dark = 0;
  for (int y = 0; y < r.image.height; ++y) {
    for (int x = 0; x < r.image.width; ++x) {
      const glm::dvec3 p = r.pixel(x, y);
      const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
                          p.x >= 0 && p.y >= 0 && p.z >= 0;
      if (!finite && bad++ == 0) {
        ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") is " << p.x << " " << p.y
                      << " " << p.z;
      }
      if (finite && positive && r.luminance(x, y) <= 0 && dark++ == 0) {
        ADD_FAILURE() << what << ": pixel (" << x << ", " << y << ") is black where light arrives";
      }
    }
  }
  EXPECT_EQ(bad, 0) << what << ": pixels not finite or negative";
  EXPECT_EQ(dark, 0) << what << ": black pixels";
}

// A camera that sees the stage, and one 2 mm above the floor looking along it (rays meet the
// floor at 0.04 to 0.6 degrees, and the sphere's silhouette edge-on).
inline constexpr const char* kStageCamera = R"({"position": [0.3, 1.4, 3.2], "look_at": [0, 0.45, 0], "fov": 45})";
inline constexpr const char* kGrazingCamera =
    R"({"position": [0, 0.002, 3], "look_at": [0, -0.01, 0], "fov": 1.2, "fov_axis": "y"})";

}  // namespace tessera::extremes_test
