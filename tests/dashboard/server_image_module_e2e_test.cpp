// tessera-server's images go through its image module, loaded at the first image
// (core/image/image_module.h; label e2e): a bundle's texture is checked at submit (a broken one
// is refused with its name: SceneError thrown in the module reaches the server's handler), a
// good one is accepted, and the preview PNG is encoded. The module's absence from start-up is
// checked by server_start_libraries (tests/dashboard/start_libraries.sh).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "farm_cluster.h"

namespace tessera::e2e {
namespace {

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// tiny.json lit by an envmap from `sky`'s bytes, as a raw bundle (no client-side check).
v1::SubmitJobRequest envmap_job(const std::string& sky) {
  nlohmann::json scene = nlohmann::json::parse(read_bytes(source_dir() / "tests/farm/data/tiny.json"));
  scene["lights"] = nlohmann::json::array({{{"type", "envmap"}, {"file", "sky.exr"}}});
  v1::SubmitJobRequest request;
  request.mutable_bundle()->set_scene_file("envmap.json");
  auto* file = request.mutable_bundle()->add_files();
  file->set_path("envmap.json");
  file->set_data(scene.dump());
  file = request.mutable_bundle()->add_files();
  file->set_path("sky.exr");
  file->set_data(sky);
  return request;
}

TEST(ServerImageModule, TexturesAreCheckedAndPreviewsEncodedThroughIt) {
  FarmCluster farm("server-image-module");
  farm.start_server();
  {
    const auto context = FarmCluster::context();
    v1::SubmitJobResponse response;
    const grpc::Status status =
        farm.jobs().SubmitJob(context.get(), envmap_job("not an EXR at all"), &response);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << status.error_message();
    EXPECT_NE(status.error_message().find("sky.exr: cannot be read as an image"), std::string::npos)
        << status.error_message();
  }
  uint64_t id = 0;
  {
    const auto context = FarmCluster::context();
    v1::SubmitJobResponse response;
    const grpc::Status status = farm.jobs().SubmitJob(
        context.get(), envmap_job(read_bytes(source_dir() / "tests/data/mitsuba/sky.exr")),
        &response);
    ASSERT_TRUE(status.ok()) << status.error_message();
    id = response.job().id();
  }
  const auto context = FarmCluster::context();
  v1::GetImageRequest request;
  request.set_job_id(id);
  request.set_format(v1::IMAGE_FORMAT_PNG);
  v1::GetImageResponse image;
  const grpc::Status status = farm.jobs().GetImage(context.get(), request, &image);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(image.data().substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

}  // namespace
}  // namespace tessera::e2e
