// Small Mitsuba 3 scenes rendered as `tessera-worker render` renders them, against Mitsuba
// 3.9.1's image means (mitsuba_mean_test_support.h; the means come from the scripts beside the
// scenes in tests/data/mitsuba/).
#include <gtest/gtest.h>

#include <string>

#include "job/job_options.h"
#include "mitsuba_mean_test_support.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

TEST(MitsubaSceneMean, RotateAboutANonUnitAxis) {
  // rotate_axis.xml turns a cube about (0, 1, 1): Mitsuba uses the axis as written, so the
  // cube is sheared and grows; with the axis normalised its mean is 23 % lower.
  const std::string dir = std::string(TESSERA_SOURCE_DIR) + "/tests/data/mitsuba/";
  const auto means = mitsuba_mean::read_mitsuba_means(dir + "rotate_axis_mean.txt");
  ASSERT_EQ(means.count(""), 1u);
  const Scene scene = load_scene_file(dir + "rotate_axis.xml");
  const JobOptions options = resolve_job_options(scene, {});
  ASSERT_EQ(options.width, 32);
  ASSERT_EQ(options.height, 24);
  mitsuba_mean::expect_mean_matches_mitsuba(scene, 16, 0, means.at(""), "rotate_axis.xml");
}

}  // namespace
}  // namespace tessera
