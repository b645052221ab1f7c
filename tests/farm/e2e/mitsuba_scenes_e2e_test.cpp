// Published Mitsuba 3 scenes (tests/data/mitsuba/, copied unchanged from mitsuba-data; see its
// README.md) rendered by Tessera locally (`tessera-worker render SCENE.xml`) and on the farm (ctest label
// `slow`: left out of the sanitizer run), and
// compared with Mitsuba 3 references made by tests/data/mitsuba/make_references.py
// (references/references.json holds each scene's size, spp, Mitsuba's own error at that spp and
// the noise factor of its pixel filter). No Mitsuba runs here.
//
// For each scene: farm and local images bit-identical; no NaN or Inf; every channel's image mean
// within 0.5 % of the reference's; RMSE at most 1.25 x Mitsuba's median RMSE over four seeds at
// the same spp, times the factor by which Mitsuba's noise grows with a box filter when the film
// has a tent or gaussian one (filter importance sampling gives each sample one pixel, as a box
// filter does; Mitsuba splats it over its neighbours). A border of `border` pixels is left out
// (Mitsuba truncates a splat's footprint at the image edge; docs/renderer.md).
#include <cmath>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

// The farm's headers (protobuf) before OpenImageIO's, whose byte-swap macros they trip on.
#include "farm_cluster.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <OpenImageIO/imagebuf.h>

namespace tessera::e2e {
namespace {

const std::filesystem::path kData = source_dir() / "tests" / "data" / "mitsuba";

nlohmann::json references() {
  std::ifstream in(kData / "references" / "references.json");
  return nlohmann::json::parse(in);
}

struct Image {
  int width = 0, height = 0;
  std::vector<float> rgb;  ///< 3 floats per pixel, row-major
};

Image read_rgb(const std::filesystem::path& path) {
  OIIO::ImageBuf buf(path.string());
  Image img;
  if (!buf.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    ADD_FAILURE() << path << ": " << buf.geterror();
    return img;
  }
  const OIIO::ImageSpec& spec = buf.spec();
  img.width = spec.width;
  img.height = spec.height;
  img.rgb.resize(size_t(img.width) * img.height * 3);
  buf.get_pixels(OIIO::ROI(0, img.width, 0, img.height, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT,
                 img.rgb.data());
  return img;
}

class PublishedMitsubaScene : public ::testing::TestWithParam<std::string> {};

TEST_P(PublishedMitsubaScene, MatchesMitsubaLocallyAndOnTheFarm) {
  const std::string name = GetParam();
  const nlohmann::json table = references();
  const nlohmann::json& ref_info = table.at("scenes").at(name);
  // The table's size, or the scene's own where its film has another aspect ratio.
  const int width = ref_info.value("width", table.at("width").get<int>());
  const int height = ref_info.value("height", table.at("height").get<int>());
  const int border = table.at("border");
  const int spp = ref_info.at("spp");
  const std::string scene = (kData / "docs" / "scenes" / (name + ".xml")).string();
  const std::vector<std::string> options = {"--width", std::to_string(width), "--height",
                                            std::to_string(height), "--spp", std::to_string(spp),
                                            "--tile", "32"};

  FarmCluster farm("mitsuba-" + name);
  farm.start_server();
  farm.start_worker();
  farm.start_worker();
  const auto local = farm.dir() / "local.exr";
  std::vector<std::string> args = {scene, "-q", "-o", local.string()};
  args.insert(args.end(), options.begin(), options.end());
  const CommandResult r = farm.local_render(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  std::vector<std::string> submit = {scene};
  submit.insert(submit.end(), options.begin(), options.end());
  const uint64_t id = farm.submit(submit);
  ASSERT_NE(id, 0u);
  const v1::JobInfo job = farm.wait_final(id);
  ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
  EXPECT_TRUE(same_pixels(job.output_exr(), local)) << "the farm's image differs from the local one";

  const Image img = read_rgb(local);
  const Image ref = read_rgb(kData / "references" / (name + ".exr"));
  ASSERT_EQ(img.width, ref.width);
  ASSERT_EQ(img.height, ref.height);
  double sum[3] = {0, 0, 0}, ref_sum[3] = {0, 0, 0}, se = 0;
  size_t n = 0, bad = 0;
  for (int y = border; y < img.height - border; ++y) {
    for (int x = border; x < img.width - border; ++x) {
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * img.width + x) * 3 + c;
        if (!std::isfinite(img.rgb[i])) ++bad;
        sum[c] += img.rgb[i];
        ref_sum[c] += ref.rgb[i];
        se += double(img.rgb[i] - ref.rgb[i]) * double(img.rgb[i] - ref.rgb[i]);
      }
      ++n;
    }
  }
  EXPECT_EQ(bad, 0u) << "NaN or Inf values";
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(sum[c] / n, ref_sum[c] / n, 0.005 * ref_sum[c] / n) << "channel " << c << " mean";
  }
  const double rmse = std::sqrt(se / double(3 * n));
  const double bar = 1.25 * ref_info.at("mitsuba_rmse").get<double>() * ref_info.at("box_factor").get<double>();
  EXPECT_LE(rmse, bar) << "RMSE " << rmse << " against Mitsuba's " << ref_info.at("mitsuba_rmse")
                       << " (box factor " << ref_info.at("box_factor") << ")";
  RecordProperty("rmse", std::to_string(rmse));
  std::cerr << name << ": RMSE " << rmse << " (bar " << bar << "), mean "
            << sum[0] / n << " " << sum[1] / n << " " << sum[2] / n << " vs " << ref_sum[0] / n << " "
            << ref_sum[1] / n << " " << ref_sum[2] / n << "\n";
}

std::vector<std::string> scene_names() {
  std::vector<std::string> names;
  const nlohmann::json table = references();
  for (const auto& [name, info] : table.at("scenes").items()) names.push_back(name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Mitsuba3, PublishedMitsubaScene, ::testing::ValuesIn(scene_names()),
                         [](const auto& info) { return info.param; });

/// A scene with a bitmap texture, an environment map and a gaussian filter gives the same bits
/// on 1 and 3 workers as locally.
TEST(PublishedMitsubaSceneFarm, TextureEnvmapGaussianBitIdenticalWith1And3Workers) {
  const std::string scene = (kData / "docs" / "scenes" / "bsdf_diffuse_textured.xml").string();
  const std::vector<std::string> options = {"--width", "48", "--height", "36", "--spp", "16",
                                            "--tile", "16", "--batch", "4"};
  FarmCluster farm("mitsuba-workers");
  farm.start_server();
  const auto local = farm.dir() / "local.exr";
  std::vector<std::string> args = {scene, "-q", "-o", local.string()};
  args.insert(args.end(), options.begin(), options.end());
  ASSERT_EQ(farm.local_render(args).exit_code, 0);
  farm.start_worker();
  for (int workers : {1, 3}) {
    SCOPED_TRACE(std::to_string(workers) + " worker(s)");
    if (workers == 3) {
      farm.start_worker();
      farm.start_worker();
    }
    std::vector<std::string> submit = {scene};
    submit.insert(submit.end(), options.begin(), options.end());
    const uint64_t id = farm.submit(submit);
    ASSERT_NE(id, 0u);
    const v1::JobInfo job = farm.wait_final(id);
    ASSERT_EQ(job.state(), v1::JOB_STATE_DONE) << job.error();
    EXPECT_TRUE(same_pixels(job.output_exr(), local));
  }
}

/// Images with a NaN, infinite or negative value, sent straight to the server with SubmitJob as
/// a client that skips the CLI's own check would (tests/xml/CMakeLists.txt checks `tessera
/// submit` and `tessera-worker render`): each bundle is refused at submit with INVALID_ARGUMENT,
/// one line naming the scene file, line and element, the image and its first bad pixel, and
/// nothing is stored.
TEST(PublishedMitsubaSceneFarm, ServerRefusesNanInfiniteAndNegativeTexelsAtSubmit) {
  struct Case {
    std::string scene, image, reason;
  };
  const std::vector<Case> cases = {
      {"nan_envmap.xml", "nan_texel.exr",
       R"(nan_envmap\.xml: line 6: <emitter type="envmap">: nan_texel\.exr: pixel \(2, 1\) channel B is NaN)"},
      {"inf_envmap.xml", "inf_texel.exr",
       R"(inf_envmap\.xml: line 6: <emitter type="envmap">: inf_texel\.exr: pixel \(3, 0\) channel R is infinite)"},
      {"negative_texture.xml", "negative_texel.exr",
       R"(negative_texture\.xml: line 7: <texture type="bitmap" name="reflectance">: negative_texel\.exr: pixel \(1, 1\) channel G is negative)"},
      {"nan_texture_radiance.xml", "nan_texel.exr",
       R"(nan_texture_radiance\.xml: line 7: <texture type="bitmap" name="radiance">: nan_texel\.exr: pixel \(2, 1\) channel B is NaN)"},
  };
  FarmCluster farm("mitsuba-bad-texels");
  farm.start_server();
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    v1::SubmitJobRequest request;
    request.mutable_bundle()->set_scene_file(c.scene);
    for (const std::string& file : {c.scene, std::string("sensor.xml"), c.image}) {
      auto* f = request.mutable_bundle()->add_files();
      f->set_path(file);
      f->set_data(read_text(kData / file));
    }
    v1::SubmitJobResponse response;
    const grpc::Status status =
        farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_TRUE(std::regex_search(status.error_message(), std::regex(c.reason)))
        << status.error_message();
    EXPECT_EQ(status.error_message().find('\n'), std::string::npos) << status.error_message();
  }
  const CommandResult list = farm.cli({"list", "--json"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(nlohmann::json::parse(list.out).empty()) << list.out;
}

/// A scene whose BSDF contains itself through <ref>, sent straight to the server with SubmitJob:
/// the server parses what clients send, so it refuses the cycle naming the line and the id, and
/// stays up (a scene of 300 bytes like this one once killed it).
TEST(PublishedMitsubaSceneFarm, ServerRefusesABsdfThatContainsItselfAndStaysUp) {
  FarmCluster farm("mitsuba-bsdf-cycle");
  farm.start_server();
  v1::SubmitJobRequest request;
  request.mutable_bundle()->set_scene_file("self_referencing_bsdf.xml");
  auto* file = request.mutable_bundle()->add_files();
  file->set_path("self_referencing_bsdf.xml");
  file->set_data(read_text(kData / "self_referencing_bsdf.xml"));
  v1::SubmitJobResponse response;
  const grpc::Status status =
      farm.jobs().SubmitJob(FarmCluster::context().get(), request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
  EXPECT_NE(status.error_message().find(
                "self_referencing_bsdf.xml: line 5: <bsdf type=\"twosided\" id=\"a\">: "
                "contains itself through <ref> (\"a\" -> \"a\")"),
            std::string::npos)
      << status.error_message();
  const CommandResult list = farm.cli({"list", "--json"});
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(nlohmann::json::parse(list.out).empty()) << list.out;
}

}  // namespace
}  // namespace tessera::e2e
