// The volume texture scene (tests/data/mitsuba/volume/scene.xml: grids on a floor, a sphere and
// two instances of one group, constants on a rough metal) rendered by Tessera against Mitsuba
// 3.9.1's image mean (mitsuba_volume_scene.py wrote mitsuba_volume_scene.txt).
#include <gtest/gtest.h>

#include <string>

#include "job/job_options.h"
#include "mitsuba_mean_test_support.h"
#include "scene/loader/scene_loader.h"

namespace tessera {
namespace {

TEST(VolumeRender, SceneMatchesMitsuba) {
  const std::string dir = std::string(TESSERA_SOURCE_DIR);
  const auto means =
      mitsuba_mean::read_mitsuba_means(dir + "/worker/render/texture/mitsuba_volume_scene.txt");
  ASSERT_EQ(means.count(""), 1u);
  const Scene scene = load_scene_file(dir + "/tests/data/mitsuba/volume/scene.xml");
  ASSERT_EQ(scene.textures.size(), 5u);
  const JobOptions options = resolve_job_options(scene, {});
  ASSERT_EQ(options.width, 64);
  ASSERT_EQ(options.height, 48);
  // The whole image, as mitsuba_volume_scene.py takes Mitsuba's mean.
  mitsuba_mean::expect_mean_matches_mitsuba(scene, 32, 0, means.at(""), "volume/scene.xml");
}

}  // namespace
}  // namespace tessera
