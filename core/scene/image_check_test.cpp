// check_image_bytes: images written here with OpenImageIO, then broken.
#include "scene/image_check.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "scene/scene_error.h"

namespace tessera {
namespace {

/// The bytes of a `width` x `height` RGB image of `pixels` in the format of `extension`.
std::string encode(const std::string& extension, int width, int height,
                   const std::vector<float>& pixels, OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT) {
  std::vector<unsigned char> buffer;
  OIIO::Filesystem::IOVecOutput out(buffer);
  std::unique_ptr<OIIO::ImageOutput> writer = OIIO::ImageOutput::create("x" + extension);
  EXPECT_TRUE(writer);
  OIIO::ImageSpec spec(width, height, 3, type);
  void* proxy = &out;
  spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  EXPECT_TRUE(writer->open("x" + extension, spec)) << writer->geterror();
  EXPECT_TRUE(writer->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  writer->close();
  return std::string(buffer.begin(), buffer.end());
}

std::string check_error(const std::string& path, const std::string& bytes) {
  try {
    check_image_bytes(path, bytes);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<float> ramp(int width, int height) {
  std::vector<float> pixels(size_t(width) * height * 3);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i % 7) / 7;
  return pixels;
}

TEST(ImageCheck, AcceptsGoodImagesAndReportsTheirSize) {
  ImageCheck exr = check_image_bytes("textures/a.exr", encode(".exr", 5, 3, ramp(5, 3)));
  EXPECT_EQ(exr.width, 5);
  EXPECT_EQ(exr.height, 3);
  EXPECT_EQ(exr.channels, 3);
  EXPECT_EQ(exr.format, "openexr");
  ImageCheck png =
      check_image_bytes("a.PNG", encode(".png", 4, 2, ramp(4, 2), OIIO::TypeDesc::UINT8));
  EXPECT_EQ(png.format, "png");
  EXPECT_EQ(png.width, 4);
  ImageCheck hdr = check_image_bytes("sky.hdr", encode(".hdr", 8, 4, ramp(8, 4)));
  EXPECT_EQ(hdr.format, "hdr");
}

/// A PFM file (Portable Float Map) as written by hand: header, then rows bottom to top.
std::string pfm(const char* header, const std::vector<float>& values, bool big_endian = false) {
  std::string bytes = header;
  for (float v : values) {
    char b[4];
    std::memcpy(b, &v, 4);
    if (big_endian) std::reverse(b, b + 4);  // this machine is little-endian (x86-64)
    bytes.append(b, 4);
  }
  return bytes;
}

// Public scenes light with .pfm environment maps (Mitsuba reads them as linear float images).
// OpenImageIO reads PFM from memory; its rows are stored bottom to top, so the first value
// stored is in the bottom row, as Mitsuba 3.9.1's Bitmap reads it too (mi.Bitmap of this 3 x 2
// file gives rows [9..17] then [0..8]).
TEST(ImageCheck, AcceptsPfmAndNamesPixelsTopDown) {
  std::vector<float> values(18);
  for (size_t i = 0; i < values.size(); ++i) values[i] = float(i);
  ImageCheck rgb = check_image_bytes("sky.pfm", pfm("PF\n3 2\n-1.0\n", values));
  EXPECT_EQ(rgb.width, 3);
  EXPECT_EQ(rgb.height, 2);
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.format, "pnm");
  ImageCheck grey =
      check_image_bytes("g.pfm", pfm("Pf\n3 2\n1.0\n", {0, 1, 2, 3, 4, 5}, true));
  EXPECT_EQ(grey.channels, 1);
  values[1] = std::numeric_limits<float>::quiet_NaN();  // stored first row: the bottom one
  std::string nan = check_error("sky.pfm", pfm("PF\n3 2\n-1.0\n", values));
  EXPECT_EQ(nan.rfind("sky.pfm: pixel (0, 1) channel ", 0), 0u) << nan;
  EXPECT_NE(nan.find(" is NaN"), std::string::npos) << nan;
  values[1] = -std::numeric_limits<float>::infinity();
  EXPECT_NE(check_error("sky.pfm", pfm("PF\n3 2\n-1.0\n", values)).find(" is infinite"),
            std::string::npos);
  values[1] = 1;
  std::string cut = check_error("sky.pfm", pfm("PF\n3 2\n-1.0\n", values).substr(0, 40));
  EXPECT_EQ(cut.rfind("sky.pfm: ", 0), 0u) << cut;
  EXPECT_NE(cut, "(no error)");
}

TEST(ImageCheck, RefusesBadValuesNamingThePixel) {
  std::vector<float> pixels = ramp(4, 3);
  pixels[(2 * 4 + 1) * 3 + 2] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(check_error("env.exr", encode(".exr", 4, 3, pixels)),
            "env.exr: pixel (1, 2) channel B is NaN (nan); images must hold finite values >= 0");
  pixels = ramp(4, 3);
  pixels[1] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(check_error("env.exr", encode(".exr", 4, 3, pixels)),
            "env.exr: pixel (0, 0) channel G is infinite (inf); images must hold finite values "
            ">= 0");
  pixels = ramp(4, 3);
  pixels[3 * 3] = -0.5f;
  EXPECT_EQ(check_error("env.exr", encode(".exr", 4, 3, pixels)),
            "env.exr: pixel (3, 0) channel R is negative (-0.500000); images must hold finite "
            "values >= 0");
}

// Rows 3.6 MB wide: the check decodes two rows at a time, and names a pixel of a later band by
// its row in the image.
TEST(ImageCheck, NamesThePixelInALaterBandOfRows) {
  const int width = 300'000;
  std::vector<float> pixels(size_t(width) * 3 * 3, 0.25f);
  pixels[(size_t(2) * width + 5) * 3 + 1] = -1.0f;
  EXPECT_EQ(check_error("wide.exr", encode(".exr", width, 3, pixels)),
            "wide.exr: pixel (5, 2) channel G is negative (-1.000000); images must hold finite "
            "values >= 0");
}

TEST(ImageCheck, RefusesMoreValuesThanTheLimitFromTheHeader) {
  const std::string exr = encode(".exr", 5, 3, ramp(5, 3));
  try {
    check_image_bytes("big.exr", exr, 44);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(std::string(e.what()), "big.exr: 5 x 3 x 3 values (at most 44)");
  }
  EXPECT_EQ(check_image_bytes("big.exr", exr, 45).width, 5);
  // The default takes a 16k environment map, RGB or RGBA.
  EXPECT_GE(kMaxImageValues, uint64_t(16384) * 8192 * 4);
}

TEST(ImageCheck, ProbeReadsTheHeaderAndEstimatesTheCheck) {
  const ImageHeader exr = probe_image_bytes("a.exr", encode(".exr", 5, 3, ramp(5, 3)));
  EXPECT_EQ(exr.width, 5);
  EXPECT_EQ(exr.height, 3);
  EXPECT_EQ(exr.channels, 3);
  EXPECT_EQ(exr.format, "openexr");
  EXPECT_EQ(exr.values(), 45u);
  const ImageHeader png =
      probe_image_bytes("a.png", encode(".png", 4, 2, ramp(4, 2), OIIO::TypeDesc::UINT8));
  EXPECT_EQ(png.bytes_per_value, 1);
  // PNG: the decoded image in its pixel type (24 bytes) and a band of 2 rows of floats.
  EXPECT_EQ(image_check_memory(png), 24u + 2 * 4 * 3 * 4);
  // A 16k RGB float environment map in EXR: the decoder's allowance and 8 MiB of rows.
  ImageHeader sky = exr;
  sky.width = 16384;
  sky.height = 8192;
  sky.bytes_per_value = 4;
  EXPECT_LT(image_check_memory(sky), uint64_t(80) << 20);
  sky.format = "png";
  EXPECT_GT(image_check_memory(sky), sky.values() * 4);
  std::string error;
  try {
    probe_image_bytes("t.png", "not an image");
  } catch (const SceneError& e) {
    error = e.what();
  }
  EXPECT_EQ(error.rfind("t.png: cannot be read as an image (", 0), 0u) << error;
}

TEST(ImageCheck, RefusesWhatIsNotAnImage) {
  EXPECT_EQ(check_error("a.png", ""), "a.png: empty file, not an image");
  std::string not_png = check_error("a.png", "this is text, not a PNG file");
  EXPECT_EQ(not_png.rfind("a.png: cannot be read as an image (", 0), 0u) << not_png;
  std::string unknown = check_error("a.xyz", "whatever");
  EXPECT_EQ(unknown.rfind("a.xyz: cannot be read as an image (", 0), 0u) << unknown;
  // Cut short: the header survives, the pixels do not.
  std::string exr = encode(".exr", 64, 64, ramp(64, 64));
  std::string cut = check_error("t.exr", exr.substr(0, exr.size() / 2));
  EXPECT_EQ(cut.rfind("t.exr: ", 0), 0u) << cut;
  EXPECT_NE(cut, "(no error)");
  std::string png = encode(".png", 64, 64, ramp(64, 64), OIIO::TypeDesc::UINT8);
  std::string cut_png = check_error("t.png", png.substr(0, png.size() / 2));
  EXPECT_EQ(cut_png.rfind("t.png: ", 0), 0u) << cut_png;
  EXPECT_NE(cut_png, "(no error)");
}

TEST(ImageCheck, SceneImageFilesAreTexturesAndEnvmaps) {
  Scene scene;
  Texture bitmap;
  bitmap.file = "tex/a.png";
  Texture checks;
  checks.kind = TextureKind::checkerboard;
  Texture again = bitmap;
  scene.textures = {bitmap, checks, again};
  Light env;
  env.kind = LightKind::envmap;
  env.file = "sky.exr";
  Light point;
  scene.lights = {point, env};
  scene.referenced_files = {"m.ply", "tex/a.png", "sky.exr"};
  EXPECT_EQ(scene_image_files(scene), (std::vector<std::string>{"tex/a.png", "sky.exr"}));
}

}  // namespace
}  // namespace tessera
