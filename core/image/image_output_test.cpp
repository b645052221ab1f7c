#include "image/image_output.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>

namespace tessera {
namespace {

namespace fs = std::filesystem;

/// A fresh folder per test, removed afterwards.
class ImageOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("tessera-image-" + std::to_string(::getpid()) + "-" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path file(const std::string& name) const { return dir_ / name; }
  size_t files_in_dir() const {
    return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

RgbImage image_of(int width, int height, std::vector<float> rgb) {
  RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb = std::move(rgb);
  return image;
}

/// Pixels of a file as OIIO reads them, in the given type (no colour conversion).
template <typename T>
std::vector<T> oiio_pixels(const fs::path& path, OIIO::TypeDesc type, OIIO::ImageSpec* spec_out) {
  auto in = OIIO::ImageInput::open(path.string());
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  const OIIO::ImageSpec spec = in->spec();
  std::vector<T> pixels(size_t(spec.width) * spec.height * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, type, pixels.data())) << in->geterror();
  if (spec_out) *spec_out = spec;
  return pixels;
}

TEST_F(ImageOutputTest, ExrFloat32RoundTripIsBitExact) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-10.0f, 1000.0f);
  RgbImage image = image_of(17, 9, std::vector<float>(17 * 9 * 3));
  for (float& v : image.rgb) v = u(rng);
  image.rgb[0] = 1e30f;
  image.rgb[1] = std::numeric_limits<float>::denorm_min();
  image.rgb[2] = -0.0f;
  image.rgb[3] = std::numeric_limits<float>::max();
  image.rgb[4] = 1e9f;
  write_image(image, file("float.exr"));

  OIIO::ImageSpec spec;
  oiio_pixels<float>(file("float.exr"), OIIO::TypeDesc::FLOAT, &spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(spec.nchannels, 3);
  const RgbImage back = read_image(file("float.exr"));
  ASSERT_EQ(back.width, 17);
  ASSERT_EQ(back.height, 9);
  ASSERT_EQ(back.rgb.size(), image.rgb.size());
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    EXPECT_EQ(std::bit_cast<uint32_t>(back.rgb[i]), std::bit_cast<uint32_t>(image.rgb[i])) << i;
  }
}

TEST_F(ImageOutputTest, NanAndInfAreWrittenAsZero) {
  const float inf = std::numeric_limits<float>::infinity();
  const RgbImage image =
      image_of(2, 1, {std::numeric_limits<float>::quiet_NaN(), inf, -inf, 0.5f, -2.0f, 3.0f});
  for (bool half : {false, true}) {
    ImageWriteOptions options;
    options.half = half;
    write_image(image, file("nan.exr"), options);
    const RgbImage back = read_image(file("nan.exr"));
    const std::vector<float> expected = {0.0f, 0.0f, 0.0f, 0.5f, -2.0f, 3.0f};
    EXPECT_EQ(back.rgb, expected) << "half " << half;
  }
}

TEST_F(ImageOutputTest, ExrHalfClampsToFiniteRange) {
  const RgbImage image = image_of(2, 2,
                                  {1e9f, -1e9f, 65519.0f, 70000.0f, 65504.0f, 1.0f, 0.25f,
                                   -65520.0f, 1e-3f, 3e38f, 100.0f, 0.0f});
  ImageWriteOptions options;
  options.half = true;
  write_image(image, file("half.exr"), options);

  OIIO::ImageSpec spec;
  oiio_pixels<float>(file("half.exr"), OIIO::TypeDesc::FLOAT, &spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::HALF);
  const RgbImage back = read_image(file("half.exr"));
  for (float v : back.rgb) EXPECT_TRUE(std::isfinite(v)) << v;
  EXPECT_EQ(back.rgb[0], 65504.0f);
  EXPECT_EQ(back.rgb[1], -65504.0f);
  EXPECT_EQ(back.rgb[2], 65504.0f);
  EXPECT_EQ(back.rgb[3], 65504.0f);
  EXPECT_EQ(back.rgb[4], 65504.0f);
  EXPECT_EQ(back.rgb[5], 1.0f);
  EXPECT_EQ(back.rgb[6], 0.25f);
  EXPECT_EQ(back.rgb[7], -65504.0f);
  EXPECT_NEAR(back.rgb[8], 1e-3f, 1e-6f);
  EXPECT_EQ(back.rgb[9], 65504.0f);
}

TEST_F(ImageOutputTest, LinearToSrgbTransfer) {
  EXPECT_EQ(linear_to_srgb(0.0f), 0.0f);
  EXPECT_NEAR(linear_to_srgb(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(linear_to_srgb(0.0031308f), 0.0404500f, 1e-6f);  // where the two pieces meet
  EXPECT_NEAR(linear_to_srgb(0.001f), 0.01292f, 1e-7f);        // linear segment
  EXPECT_NEAR(linear_to_srgb(0.18f), 0.461356f, 1e-5f);
}

TEST_F(ImageOutputTest, PngIsSrgbRoundedAndClamped) {
  const RgbImage image = image_of(3, 2,
                                  {0.0f, 0.5f, 1.0f,                                           //
                                   2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),       //
                                   0.0031308f, 0.18f, std::numeric_limits<float>::infinity(),  //
                                   0.212f, 0.216f, 1e-4f,                                      //
                                   0.99f, 0.999f, 0.001f,                                      //
                                   0.05f, 0.25f, 0.75f});
  write_image(image, file("srgb.png"));
  OIIO::ImageSpec spec;
  const std::vector<uint8_t> codes =
      oiio_pixels<uint8_t>(file("srgb.png"), OIIO::TypeDesc::UINT8, &spec);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  ASSERT_EQ(codes.size(), 18u);
  const std::vector<uint8_t> expected = {
      0,   188, 255,  // 0.5 -> 0.735357 * 255 = 187.52 -> 188
      255, 0,   0,    // clamped, clamped, NaN -> 0
      10,  118, 0,    // 0.04045 * 255 = 10.31; 0.461356 * 255 = 117.65; Inf -> 0
      127, 128, 0,    // 126.94 -> 127; 128.04 -> 128; 1e-4 -> 0.33 -> 0
      254, 255, 3,    // 0.99 -> 253.88; 0.999 -> 254.89; 0.001 -> 3.29
      63,  137, 225,  // 0.05 -> 63.19; 0.25 -> 136.96; 0.75 -> 224.61
  };
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(int(codes[i]), int(expected[i])) << i;

  // read_image undoes the sRGB encoding: back to linear, within one 8-bit step.
  const RgbImage back = read_image(file("srgb.png"));
  EXPECT_EQ(back.rgb[0], 0.0f);
  EXPECT_NEAR(back.rgb[1], 0.5f, 0.004f);
  EXPECT_EQ(back.rgb[2], 1.0f);
}

/// FLEVEL of the zlib stream in a PNG's first IDAT chunk (RFC 1950: bits 6-7 of the second byte;
/// 0 = the fastest levels, 0-1; 2 = the default, 6), or -1 when there is none.
int png_zlib_flevel(const std::string& png) {
  size_t at = 8;  // past the signature; then chunks: u32 length (big-endian), type, data, CRC
  while (at + 8 <= png.size()) {
    const auto byte = [&](size_t i) { return uint32_t(uint8_t(png[i])); };
    const uint32_t length = byte(at) << 24 | byte(at + 1) << 16 | byte(at + 2) << 8 | byte(at + 3);
    if (png.compare(at + 4, 4, "IDAT") == 0) {
      return length >= 2 && at + 10 <= png.size() ? int(byte(at + 9) >> 6) : -1;
    }
    at += 12 + size_t(length);
  }
  return -1;
}

// The PNG beside each farm job's EXR is deflated at zlib's fastest level (oiio_image_io.cpp,
// kPngZlibLevel): 5x less CPU than OIIO's default 6 for 17 % more bytes on a render.
TEST_F(ImageOutputTest, PngIsDeflatedAtZlibsFastestLevel) {
  std::vector<float> rgb(64 * 64 * 3);
  std::mt19937 noise(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (float& v : rgb) v = u(noise);
  const RgbImage image = image_of(64, 64, rgb);
  write_image(image, file("fast.png"));
  std::ifstream in(file("fast.png"), std::ios::binary);
  const std::string written((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(png_zlib_flevel(written), 0);
  EXPECT_EQ(png_zlib_flevel(encode_image(image, "png")), 0);  // previews too
  // Still lossless: every 8-bit code comes back.
  const RgbImage back = read_image(file("fast.png"));
  for (size_t i = 0; i < rgb.size(); ++i) {
    ASSERT_NEAR(back.rgb[i], rgb[i], 0.02f) << i;
  }
}

TEST_F(ImageOutputTest, MetadataReadableFromExrHeaderAndPngText) {
  ImageWriteOptions options;
  options.metadata = {{"tessera:scene_sha256", std::string(64, 'a')},
                      {"tessera:spp", "256"},
                      {"tessera:renderer_version", "0.1.0 (isa avx2)"}};
  const RgbImage image = image_of(1, 1, {0.1f, 0.2f, 0.3f});
  for (const char* name : {"meta.exr", "meta.png"}) {
    write_image(image, file(name), options);
    auto in = OIIO::ImageInput::open(file(name).string());
    ASSERT_TRUE(in) << OIIO::geterror();
    for (const auto& [key, value] : options.metadata) {
      EXPECT_EQ(in->spec().get_string_attribute(key), value) << name << " " << key;
    }
  }
}

TEST_F(ImageOutputTest, UnknownExtensionNamesFileAndSupportedExtensions) {
  const RgbImage image = image_of(1, 1, {0.1f, 0.2f, 0.3f});
  for (const char* name : {"render.tif", "render", "render.exr.bak"}) {
    try {
      write_image(image, file(name));
      FAIL() << "no error for " << name;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(file(name).string()), std::string::npos) << message;
      EXPECT_NE(message.find(".exr"), std::string::npos) << message;
      EXPECT_NE(message.find(".png"), std::string::npos) << message;
    }
  }
  EXPECT_EQ(files_in_dir(), 0u);
  EXPECT_THROW(encode_image(image, "tiff"), std::runtime_error);
}

TEST_F(ImageOutputTest, ExtensionIsCaseInsensitive) {
  write_image(image_of(1, 1, {0.1f, 0.2f, 0.3f}), file("UPPER.EXR"));
  EXPECT_EQ(read_image(file("UPPER.EXR")).rgb[1], 0.2f);
}

TEST_F(ImageOutputTest, WritesAtomicallyAndLeavesNoTemporaryFile) {
  write_image(image_of(1, 1, {1.0f, 2.0f, 3.0f}), file("out.exr"));
  write_image(image_of(1, 1, {4.0f, 5.0f, 6.0f}), file("out.exr"));  // replaces it
  EXPECT_EQ(read_image(file("out.exr")).rgb, (std::vector<float>{4.0f, 5.0f, 6.0f}));
  EXPECT_EQ(files_in_dir(), 1u);

  // A failed write names the file and leaves nothing behind.
  const fs::path missing = file("no-such-folder") / "out.exr";
  try {
    write_image(image_of(1, 1, {1.0f, 2.0f, 3.0f}), missing);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(files_in_dir(), 1u);
}

TEST_F(ImageOutputTest, RejectsImageWhosePixelsDoNotMatchItsSize) {
  EXPECT_THROW(write_image(image_of(2, 2, {1.0f, 2.0f, 3.0f}), file("bad.exr")),
               std::runtime_error);
  EXPECT_THROW(write_image(image_of(0, 0, {}), file("empty.png")), std::runtime_error);
  EXPECT_EQ(files_in_dir(), 0u);
}

std::string file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Rows [y0, y0 + rows) of `image` (and of each extra channel).
RgbImage band_of(const RgbImage& image, int y0, int rows) {
  const size_t row = size_t(image.width) * 3;
  return image_of(image.width, rows,
                  std::vector<float>(image.rgb.begin() + ptrdiff_t(row * size_t(y0)),
                                     image.rgb.begin() + ptrdiff_t(row * size_t(y0 + rows))));
}

// The server writes a job's files a row of tiles at a time (server/job_output.cpp): whatever the
// bands, the file is the one write_image gives for the whole image, byte for byte, the EXR's
// extra channel and the metadata included, and so are the bytes encoded in memory; 37 rows in
// bands of 16 and 5 also cut OpenEXR's 16-line zip blocks in the middle.
TEST_F(ImageOutputTest, AFileWrittenInBandsIsTheWholeImagesByteForByte) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(-0.5f, 3.0f);
  const int width = 29, height = 37;
  RgbImage image = image_of(width, height, std::vector<float>(size_t(width) * height * 3));
  for (float& v : image.rgb) v = value(random);
  image.rgb[5] = std::numeric_limits<float>::quiet_NaN();
  ImageWriteOptions options;
  // A fixed date: OpenImageIO writes the time of the write into an EXR (capDate) unless told.
  options.metadata = {{"tessera:job_id", "12"}, {"tessera:scene_file", "x.json"}, {"DateTime", "2026:12:05 12:00:00"}};
  options.extra_channels = {{"spp", std::vector<float>(size_t(width) * height)}};
  for (size_t p = 0; p < options.extra_channels[0].values.size(); ++p) {
    options.extra_channels[0].values[p] = float(p % 7);
  }
  for (const std::string ext : {".exr", ".png"}) {
    write_image(image, file("whole" + ext), options);
    if (ext == ".exr") {
      EXPECT_NE(file_bytes(file("whole.exr")).find("2026:12:05 12:00:00"), std::string::npos);
    }
    for (const int band : {1, 5, 16, 36}) {
      const fs::path path = file("bands" + std::to_string(band) + ext);
      ImageWriteOptions names = options;
      names.extra_channels[0].values.clear();  // the stream reads the names only
      // The image's rows `band` at a time, each band with its values of the spp channel.
      const auto write_bands = [&](ImageFileStream& stream) {
        const std::vector<float>& spp = options.extra_channels[0].values;
        for (int y0 = 0; y0 < height; y0 += band) {
          const int rows = std::min(band, height - y0);
          stream.write_rows(band_of(image, y0, rows),
                            {{"spp", std::vector<float>(spp.begin() + ptrdiff_t(y0 * width),
                                                        spp.begin() + ptrdiff_t((y0 + rows) * width))}});
          EXPECT_FALSE(fs::exists(path)) << "in place before finish()";
        }
        stream.finish();
      };
      ImageFileStream stream(path, width, height, names);
      write_bands(stream);
      EXPECT_EQ(file_bytes(path), file_bytes(file("whole" + ext))) << path;

      // The same bands into memory (the server's previews) give the same bytes.
      fs::remove(path);
      ImageFileStream memory = ImageFileStream::in_memory(ext.substr(1), width, height, names);
      write_bands(memory);
      EXPECT_EQ(memory.take_bytes(), file_bytes(file("whole" + ext))) << ext << " in memory, bands of " << band;
    }
    EXPECT_EQ(encode_image(image, ext.substr(1), options), file_bytes(file("whole" + ext))) << ext;
  }
}

TEST_F(ImageOutputTest, AStreamRefusesBandsThatDoNotFitAndLeavesNothingUnfinished) {
  const fs::path path = file("out.exr");
  {
    ImageFileStream stream(path, 4, 3, {});
    stream.write_rows(image_of(4, 2, std::vector<float>(24, 0.5f)));
    try {
      stream.write_rows(image_of(4, 2, std::vector<float>(24, 0.5f)));  // 4 rows of 3
      FAIL() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("does not fit a 4x3 image"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
    EXPECT_THROW(stream.write_rows(image_of(3, 1, std::vector<float>(9, 0.5f))), std::runtime_error);
    try {
      stream.finish();  // a row short
      FAIL() << "no error";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("2 of 3 rows written"), std::string::npos) << e.what();
    }
  }
  // Destroyed unfinished: no file in place, no temporary file left.
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(files_in_dir(), 0u);
  EXPECT_THROW(ImageFileStream(file("out.tiff"), 4, 3, {}), std::runtime_error);
  EXPECT_THROW(ImageFileStream(file("out.png"), 0, 3, {}), std::runtime_error);
  EXPECT_EQ(files_in_dir(), 0u);
}

TEST_F(ImageOutputTest, EncodeImageProducesBytesOiioReads) {
  const RgbImage image = image_of(2, 1, {0.0f, 0.5f, 1.0f, 0.25f, 2.0f, -1.0f});
  ImageWriteOptions options;
  options.metadata = {{"tessera:job", "j-42"}};

  const std::string exr = encode_image(image, "exr", options);
  ASSERT_GE(exr.size(), 4u);
  EXPECT_EQ(exr.substr(0, 4), std::string("\x76\x2f\x31\x01", 4));  // OpenEXR magic
  const std::string png = encode_image(image, "png", options);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  struct Case {
    std::string bytes, name;
  };
  for (const Case& c : {Case{exr, "memory.exr"}, Case{png, "memory.png"}}) {
    OIIO::Filesystem::IOMemReader reader(c.bytes.data(), c.bytes.size());
    auto in = OIIO::ImageInput::open(c.name, nullptr, &reader);
    ASSERT_TRUE(in) << c.name << ": " << OIIO::geterror();
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.width, 2);
    EXPECT_EQ(spec.height, 1);
    EXPECT_EQ(spec.get_string_attribute("tessera:job"), "j-42") << c.name;
    std::vector<float> pixels(6);
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data())) << in->geterror();
    if (c.name == "memory.exr") {
      EXPECT_EQ(pixels, image.rgb);
    } else {
      EXPECT_EQ(pixels[0], 0.0f);
      EXPECT_EQ(pixels[1], 188.0f / 255.0f);
      EXPECT_EQ(pixels[2], 1.0f);
      EXPECT_EQ(pixels[4], 1.0f);
      EXPECT_EQ(pixels[5], 0.0f);
    }
  }
  // The same image gives the same bytes as a file written by write_image.
  write_image(image, file("same.exr"), options);
  EXPECT_EQ(read_image(file("same.exr")).rgb, image.rgb);
}

TEST_F(ImageOutputTest, ReadImageReplicatesSingleChannel) {
  const fs::path path = file("grey.exr");
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    const OIIO::ImageSpec spec(2, 1, 1, OIIO::TypeDesc::FLOAT);
    ASSERT_TRUE(out->open(path.string(), spec));
    const float grey[2] = {0.25f, 3.0f};
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, grey));
    ASSERT_TRUE(out->close());
  }
  const RgbImage image = read_image(path);
  EXPECT_EQ(image.rgb, (std::vector<float>{0.25f, 0.25f, 0.25f, 3.0f, 3.0f, 3.0f}));
}

TEST_F(ImageOutputTest, ReadImageKeepsFirstThreeOfFourChannels) {
  const fs::path path = file("rgba.exr");
  {
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    const OIIO::ImageSpec spec(1, 1, 4, OIIO::TypeDesc::FLOAT);
    ASSERT_TRUE(out->open(path.string(), spec));
    const float rgba[4] = {0.1f, 0.2f, 0.3f, 0.5f};
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, rgba));
    ASSERT_TRUE(out->close());
  }
  EXPECT_EQ(read_image(path).rgb, (std::vector<float>{0.1f, 0.2f, 0.3f}));
}

TEST_F(ImageOutputTest, ReadImageOfMissingFileNamesIt) {
  try {
    read_image(file("missing.exr"));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.exr"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tessera
