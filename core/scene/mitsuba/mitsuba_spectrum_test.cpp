// Spectra as Mitsuba 3's RGB variants read them, against numbers Mitsuba 3.9.1 computed
// (core/scene/mitsuba/testdata/spectrum_reference.py prints them).
#include <gtest/gtest.h>

#include "scene/mitsuba/mitsuba_spectrum.h"
#include "scene/scene_test_support.h"

namespace tessera {
namespace {

glm::dvec3 rgb(const std::string& value, MitsubaColorRole role) {
  std::string error;
  std::optional<glm::dvec3> color = mitsuba_spectrum_to_rgb(value, role, error);
  EXPECT_TRUE(color) << error;
  return color.value_or(glm::dvec3(-1));
}

std::string spectrum_error(const std::string& value) {
  std::string error;
  EXPECT_FALSE(mitsuba_spectrum_to_rgb(value, MitsubaColorRole::reflectance, error));
  return error;
}

TEST(MitsubaSpectrum, ReflectancesMatchMitsuba) {
  constexpr MitsubaColorRole kRole = MitsubaColorRole::reflectance;
  testing::expect_near(rgb("400:0.1, 500:0.5, 600:0.9, 700:0.3", kRole),
                       {0.8547973036766052, 0.68753981590271, 0.26501521468162537}, 2e-5);
  testing::expect_near(rgb("360:0.5, 830:0.5", kRole),
                       {0.4994926452636719, 0.4994368553161621, 0.499400794506073}, 2e-5);
  testing::expect_near(rgb("450:0.2 550:0.8 650:0.4", kRole),
                       {0.4886581599712372, 0.7307813763618469, 0.11112229526042938}, 2e-5);
  EXPECT_EQ(rgb("0.5", kRole), glm::dvec3(0.5));
}

TEST(MitsubaSpectrum, EmissionHasNoD65Weighting) {
  constexpr MitsubaColorRole kRole = MitsubaColorRole::emission;
  testing::expect_near(rgb("360:0.5, 830:0.5", kRole),
                       {0.6024418473243713, 0.4741140902042389, 0.4546334147453308}, 2e-5);
  testing::expect_near(rgb("450:0.2 550:0.8 650:0.4", kRole),
                       {0.5874037742614746, 0.701065719127655, 0.08498766273260117}, 2e-5);
  testing::expect_near(rgb("0.5", kRole),
                       {0.6023969650268555, 0.4741455018520355, 0.4544580280780792}, 2e-5);
}

TEST(MitsubaSpectrum, ClampsAsMitsuba) {
  // A narrow band at 500 nm is outside sRGB's gamut: red goes negative before clamping.
  glm::dvec3 cyan = rgb("490:0, 500:1, 510:0", MitsubaColorRole::reflectance);
  EXPECT_EQ(cyan.x, 0);
  glm::dvec3 bright = rgb("400:5, 700:5", MitsubaColorRole::reflectance);
  EXPECT_EQ(bright, glm::dvec3(1));  // reflectances are bounded
  EXPECT_GT(rgb("400:5, 700:5", MitsubaColorRole::unbounded).y, 1);
}

TEST(MitsubaSpectrum, BadSpectraAreRefused) {
  EXPECT_NE(spectrum_error("400:0.1, 300:0.2").find("wavelengths must increase"), std::string::npos);
  EXPECT_NE(spectrum_error("500:0.5").find("at least two wavelength:value pairs"), std::string::npos);
  EXPECT_NE(spectrum_error("red").find("\"red\" is not a wavelength:value pair"), std::string::npos);
  EXPECT_NE(spectrum_error("400:x, 500:1").find("is not a wavelength:value pair"), std::string::npos);
}

}  // namespace
}  // namespace tessera
