// tessera_xml_image_check: the image checks of the Mitsuba importer's end-to-end tests.
//
//   tessera_xml_image_check identical A.exr B.exr
//       passes when both images have the same size and every float is bit-identical (what
//       rendering an XML scene and its converted JSON must give);
//   tessera_xml_image_check mean IMAGE.exr REFERENCE.exr TOLERANCE
//       passes when each channel's image mean is within TOLERANCE (relative) of the
//       reference's (0.002 for the Cornell box against Mitsuba's reference).
// Exit status 0 on pass, 1 on failure (with one line saying why), 2 on bad usage.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "image/image_output.h"
#include "image_compare.h"

namespace {

int identical(const char* a_path, const char* b_path) {
  const tessera::RgbImage a = tessera::read_image(a_path);
  const tessera::RgbImage b = tessera::read_image(b_path);
  if (a.width != b.width || a.height != b.height) {
    std::printf("FAIL: sizes differ: %dx%d vs %dx%d\n", a.width, a.height, b.width, b.height);
    return 1;
  }
  size_t differing = 0, first = 0;
  for (size_t i = 0; i < a.rgb.size(); ++i) {
    if (std::memcmp(&a.rgb[i], &b.rgb[i], sizeof(float)) != 0) {
      if (differing++ == 0) first = i;
    }
  }
  if (differing > 0) {
    size_t pixel = first / 3;
    std::printf(
        "FAIL: %zu of %zu floats differ; first at pixel (%zu, %zu) channel %zu: %.9g vs "
        "%.9g\n",
        differing, a.rgb.size(), pixel % size_t(a.width), pixel / size_t(a.width), first % 3,
        a.rgb[first], b.rgb[first]);
    return 1;
  }
  std::printf("ok: %s and %s are bit-identical (%dx%d)\n", a_path, b_path, a.width, a.height);
  return 0;
}

int mean(const char* image_path, const char* reference_path, double tolerance) {
  const tessera::RgbImage image = tessera::read_image(image_path);
  const tessera::RgbImage reference = tessera::read_image(reference_path);
  const glm::dvec3 got = tessera::test::channel_means(image);
  const glm::dvec3 want = tessera::test::channel_means(reference);
  double error = image.width == reference.width && image.height == reference.height
                     ? tessera::test::rmse(image, reference)
                     : -1;
  bool pass = true;
  for (int c = 0; c < 3; ++c) pass = pass && std::abs(got[c] - want[c]) <= tolerance * want[c];
  std::printf(
      "%s: mean %.6f %.6f %.6f, reference %.6f %.6f %.6f (relative %+.4f%% %+.4f%% "
      "%+.4f%%, tolerance %.2f%%), RMSE %.5f\n",
      pass ? "ok" : "FAIL", got.x, got.y, got.z, want.x, want.y, want.z, 100 * (got.x / want.x - 1),
      100 * (got.y / want.y - 1), 100 * (got.z / want.z - 1), 100 * tolerance, error);
  return pass ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 4 && std::strcmp(argv[1], "identical") == 0) return identical(argv[2], argv[3]);
    if (argc == 5 && std::strcmp(argv[1], "mean") == 0) {
      return mean(argv[2], argv[3], std::atof(argv[4]));
    }
  } catch (const std::exception& e) {
    std::printf("FAIL: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr, "usage: %s identical A.exr B.exr | mean IMAGE.exr REFERENCE.exr TOLERANCE\n",
               argv[0]);
  return 2;
}
