// Each limit of docs/security.md refused at submit with its reason and flag, before anything is
// stored; and the triangle limit checked before a mesh is read.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "coordinator.h"
#include "fake_clock.h"
#include "farm_error.h"

namespace tessera::server {
namespace {

std::string tiny_scene() {
  std::ifstream in(std::string(TESSERA_TEST_DATA_DIR) + "/tiny.json");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A scene whose only shape is `mesh` (a file in the bundle), plus the tiny scene's light.
std::string mesh_scene(const std::string& mesh) {
  return R"({"tessera": 1, "camera": {"position": [0,0,3], "look_at": [0,0,0], "fov": 40},
    "film": {"width": 16, "height": 16}, "render": {"spp": 8},
    "materials": {"white": {"type": "diffuse", "reflectance": [0.5,0.5,0.5]}},
    "shapes": [{"type": "mesh", "file": ")" +
         mesh + R"(", "material": "white"},
               {"type": "quad", "vertices": [[-1,2,-1],[1,2,-1],[1,2,1],[-1,2,1]], "emission": [5,5,5]}]})";
}

/// An ASCII PLY strip of `faces` triangles over faces + 2 vertices.
std::string ply_strip(int faces) {
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\nelement vertex " << faces + 2
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << faces
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < faces + 2; ++i) out << 0.1 * i << " " << (i % 2) << " 0\n";
  for (int i = 0; i < faces; ++i) {
    if (i % 2 == 0)
      out << "3 " << i << " " << i + 1 << " " << i + 2 << "\n";
    else
      out << "3 " << i + 1 << " " << i << " " << i + 2 << "\n";
  }
  return out.str();
}

v1::SceneBundle bundle(const std::string& scene,
                       const std::vector<std::pair<std::string, std::string>>& extra = {}) {
  v1::SceneBundle b;
  b.set_scene_file("scene.json");
  auto* f = b.add_files();
  f->set_path("scene.json");
  f->set_data(scene);
  for (const auto& [path, data] : extra) {
    auto* e = b.add_files();
    e->set_path(path);
    e->set_data(data);
  }
  return b;
}

struct Farm {
  testing::FakeClock clock;
  std::unique_ptr<Coordinator> coordinator;

  explicit Farm(const FarmLimits& limits) {
    CoordinatorConfig config;
    config.db_path = ":memory:";
    config.limits = limits;
    coordinator = std::make_unique<Coordinator>(config, clock);
  }

  /// The refusal's message ("" when accepted); `code` gets its code.
  std::string refusal(const v1::SceneBundle& b, const v1::JobRequestOptions& options = {},
                      const std::string& client = "ipv4:127.0.0.1", ErrorCode* code = nullptr) {
    try {
      coordinator->submit(b, options, 0, client);
    } catch (const FarmError& e) {
      if (code) *code = e.code();
      return e.what();
    }
    return "";
  }
};

void expect_refused(const std::string& message, const std::string& flag) {
  EXPECT_NE(message.find(flag), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(Limits, BundleSizeAndFileCount) {
  FarmLimits limits;
  limits.max_bundle_bytes = 4096;
  limits.max_bundle_files = 3;
  Farm farm(limits);
  EXPECT_EQ(farm.refusal(bundle(tiny_scene())), "");
  ErrorCode code{};
  const std::string big =
      farm.refusal(bundle(tiny_scene(), {{"padding.bin", std::string(5000, 'x')}}), {}, "c", &code);
  expect_refused(big, "--max-bundle-mb");
  EXPECT_EQ(code, ErrorCode::invalid_argument);
  expect_refused(farm.refusal(bundle(tiny_scene(), {{"a", "1"}, {"b", "2"}, {"c", "3"}})),
                 "--max-bundle-files");
  EXPECT_EQ(farm.coordinator->jobs(100).size(), 1u);  // the refused ones stored nothing
}

TEST(Limits, ABundleCarriesOnlyTheFilesItsSceneNames) {
  Farm farm(FarmLimits{});
  const std::string stray =
      farm.refusal(bundle(tiny_scene(), {{"notes/unused.bin", std::string(100, 'x')}}));
  EXPECT_NE(stray.find("\"notes/unused.bin\", a file the scene never names"), std::string::npos)
      << stray;
  EXPECT_TRUE(farm.coordinator->jobs(100).empty());
  EXPECT_EQ(farm.refusal(bundle(tiny_scene())), "");
}

// Curve segments are primitives as triangles are: a curves shape cannot carry more than the
// limit past it.
TEST(Limits, CurveSegmentsCountWithTriangles) {
  FarmLimits limits;
  limits.max_triangles = 12;
  Farm farm(limits);
  auto curves = [](const std::string& basis, int points) {
    std::string cps;
    for (int i = 0; i < points; ++i) cps += (i ? ", [" : "[") + std::to_string(0.1 * i) + ", 0, 0, 0.01]";
    return R"({"tessera": 1, "camera": {"position": [0,0,3], "look_at": [0,0,0], "fov": 40},
      "film": {"width": 16, "height": 16}, "render": {"spp": 8},
      "materials": {"white": {"type": "diffuse", "reflectance": [0.5,0.5,0.5]}},
      "shapes": [{"type": "curves", "basis": ")" + basis + R"(", "control_points": [)" + cps +
           R"(], "material": "white"},
        {"type": "quad", "vertices": [[-1,2,-1],[1,2,-1],[1,2,1],[-1,2,1]], "emission": [5,5,5]}]})";
  };
  // The light quad's 2 triangles + 10 linear segments (11 points) = 12: within the limit.
  EXPECT_EQ(farm.refusal(bundle(curves("linear", 11), {})), "");
  const std::string linear = farm.refusal(bundle(curves("linear", 12), {}));
  expect_refused(linear, "--max-triangles");
  EXPECT_NE(linear.find("scene: triangle and curve segment count 13"), std::string::npos) << linear;
  // A B-spline of n points has n - 3 segments.
  EXPECT_EQ(farm.refusal(bundle(curves("bspline", 13), {})), "");
  expect_refused(farm.refusal(bundle(curves("bspline", 14), {})), "--max-triangles");
}

// An SDF grid counts its voxels that can hold the surface (the renderer's primitives), a
// group's grid once.
TEST(Limits, SdfGridSurfaceVoxelsCountWithTriangles) {
  FarmLimits limits;
  limits.max_triangles = 10;
  Farm farm(limits);
  // n x 1 x 1 voxels (2 samples along y and z), the surface crossing each of the first k.
  auto grid = [](int n, int k) {
    std::string values;
    for (int z = 0; z < 2; ++z) {
      for (int y = 0; y < 2; ++y) {
        for (int x = 0; x <= n; ++x) values += std::string(values.empty() ? "" : ", ") + (x <= k && x % 2 ? "-1" : "1");
      }
    }
    return R"({"tessera": 1, "camera": {"position": [0,0,3], "look_at": [0,0,0], "fov": 40},
      "film": {"width": 16, "height": 16}, "render": {"spp": 8},
      "materials": {"white": {"type": "diffuse", "reflectance": [0.5,0.5,0.5]}},
      "shapes": [{"type": "sdfgrid", "resolution": [)" + std::to_string(n + 1) + R"(, 2, 2], "values": [)" +
           values + R"(], "material": "white"},
        {"type": "quad", "vertices": [[-1,2,-1],[1,2,-1],[1,2,1],[-1,2,1]], "emission": [5,5,5]}]})";
  };
  // The light quad's 2 triangles + 8 of 20 voxels (samples 1, 3, 5, 7 negative) = 10.
  EXPECT_EQ(farm.refusal(bundle(grid(20, 7), {})), "");
  const std::string over = farm.refusal(bundle(grid(20, 9), {}));
  expect_refused(over, "--max-triangles");
  EXPECT_NE(over.find("scene: triangle and SDF surface voxel count 12"), std::string::npos) << over;
}

TEST(Limits, TrianglesCountedFromHeadersBeforeParsing) {
  FarmLimits limits;
  limits.max_triangles = 12;
  Farm farm(limits);
  // 8 mesh triangles + the light quad's 2.
  EXPECT_EQ(farm.refusal(bundle(mesh_scene("strip.ply"), {{"strip.ply", ply_strip(8)}})), "");
  const std::string over =
      farm.refusal(bundle(mesh_scene("strip.ply"), {{"strip.ply", ply_strip(13)}}));
  expect_refused(over, "--max-triangles");
  EXPECT_NE(over.find("strip.ply: declared faces 13"), std::string::npos) << over;
  // Within the limit in the file, over it with the rest of the scene: the parsed scene's count.
  const std::string scene =
      farm.refusal(bundle(mesh_scene("strip.ply"), {{"strip.ply", ply_strip(11)}}));
  expect_refused(scene, "--max-triangles");
  EXPECT_NE(scene.find("scene: triangle count 13"), std::string::npos) << scene;
  // An OBJ file's face lines count the same way.
  std::string obj;
  for (int i = 0; i < 15; ++i)
    obj += "v " + std::to_string(i) + " " + std::to_string(i % 2) + " 0\n";
  for (int i = 1; i <= 13; ++i)
    obj +=
        "f " + std::to_string(i) + " " + std::to_string(i + 1) + " " + std::to_string(i + 2) + "\n";
  expect_refused(farm.refusal(bundle(mesh_scene("m.obj"), {{"m.obj", obj}})), "--max-triangles");
}

TEST(Limits, AHeaderDeclaringAHundredMillionFacesIsRefusedWithoutAllocating) {
  Farm farm(FarmLimits{});  // default limits (50 M triangles)
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 100000000\n"
      "property list uchar int vertex_indices\nend_header\n";
  const std::string message =
      farm.refusal(bundle(mesh_scene("huge.ply"), {{"huge.ply", header + std::string(36, '\0')}}));
  EXPECT_NE(message.find("huge.ply"), std::string::npos) << message;
  // Even with the data there, a declared count over the limit is refused from the header alone:
  // 100 M faces of 13 bytes would be 1.3 GB; a small limit shows the same rule on a small file.
  FarmLimits small;
  small.max_triangles = 1000;
  Farm strict(small);
  expect_refused(strict.refusal(bundle(mesh_scene("s.ply"), {{"s.ply", ply_strip(1001)}})),
                 "--max-triangles");
}

TEST(Limits, ImageSizeSppAndTile) {
  FarmLimits limits;
  limits.job.max_dimension = 64;
  limits.job.max_spp = 100;
  limits.job.max_tile = 32;
  Farm farm(limits);
  v1::JobRequestOptions wide;
  wide.set_width(65);
  expect_refused(farm.refusal(bundle(tiny_scene()), wide), "--width: must be in [1, 64]");
  v1::JobRequestOptions tall;
  tall.set_height(1000);
  expect_refused(farm.refusal(bundle(tiny_scene()), tall), "--height: must be in [1, 64]");
  v1::JobRequestOptions spp;
  spp.set_spp(101);
  expect_refused(farm.refusal(bundle(tiny_scene()), spp), "--spp: must be in [1, 100]");
  v1::JobRequestOptions tile;
  tile.set_tile_size(33);
  expect_refused(farm.refusal(bundle(tiny_scene()), tile), "--tile: must be in [1, 32]");
  EXPECT_TRUE(farm.coordinator->jobs(100).empty());
}

// The largest job: 32x32 at 2147483647 spp is about 2.1 million units (1 tile x the progressive
// schedule); refused with one line giving the count and the cap, before anything is stored.
TEST(Limits, WorkUnitsPerJob) {
  Farm farm(FarmLimits{});  // default: 1,000,000
  v1::JobRequestOptions huge;
  huge.set_width(32);
  huge.set_height(32);
  huge.set_spp(2147483647);
  const std::string why = farm.refusal(bundle(tiny_scene()), huge);
  EXPECT_EQ(why,
            "job has 2097162 work units (1 tiles x 2097162 batches), over the farm's limit of "
            "1000000 (server flag --max-units): use fewer spp, a larger --tile or --batch");
  EXPECT_TRUE(farm.coordinator->jobs(100).empty());
  FarmLimits small;
  small.max_units_per_job = 4;
  Farm capped(small);
  v1::JobRequestOptions four;  // 16x16 tiny scene in one tile: 8 spp = batches 1, 1, 2, 4
  four.set_spp(8);
  EXPECT_EQ(capped.refusal(bundle(tiny_scene()), four), "");
  four.set_spp(9);  // a fifth batch
  expect_refused(capped.refusal(bundle(tiny_scene()), four), "--max-units");
}

// A worker finishes the unit in hand on its first SIGTERM, so one unit's samples are capped
// (--max-unit-samples, default 2^28): a full tile's pixels x the largest batch's spp, the
// progressive schedule's cap included; the tile at the image's edge does not lower it.
TEST(Limits, SamplesPerWorkUnit) {
  Farm farm(FarmLimits{});
  v1::JobRequestOptions huge;
  huge.set_width(32);
  huge.set_height(32);
  huge.set_spp(2147483647);
  huge.set_batch_spp(2147483647);
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), huge),
            "a work unit of this job has 2199023254528 samples (32 x 32 tile pixels x 2147483647 "
            "samples per pixel per batch), over the farm's limit of 268435456 (server flag "
            "--max-unit-samples): use a smaller --batch or --tile");
  EXPECT_TRUE(farm.coordinator->jobs(100).empty());
  FarmLimits small;
  small.max_unit_samples = 16 * 16 * 4;  // the tiny scene is 16 x 16: one tile
  Farm capped(small);
  v1::JobRequestOptions options;
  options.set_spp(8);  // progressive: batches 1, 1, 2, 4
  EXPECT_EQ(capped.refusal(bundle(tiny_scene()), options), "");
  options.set_spp(16);  // batches 1, 1, 2, 4, 8: 2048 samples in the last unit
  expect_refused(capped.refusal(bundle(tiny_scene()), options), "--max-unit-samples");
  options.set_batch_spp(4);  // fixed batches of 4
  EXPECT_EQ(capped.refusal(bundle(tiny_scene()), options), "");
  options.set_batch_spp(5);
  options.set_tile_size(8);  // 8 x 8 tiles: 320 samples a unit
  EXPECT_EQ(capped.refusal(bundle(tiny_scene()), options), "");
  options.set_tile_size(15);  // 15 x 15 tiles (the edge ones 1 wide): 1125
  expect_refused(capped.refusal(bundle(tiny_scene()), options), "--max-unit-samples");
}

// The server holds a job's whole image when it writes it and when it answers a preview, so the
// pixels per job are capped (--max-pixels, default 8192 x 8192): the largest image the flags
// allow (32768 x 32768) is refused at submit with one line, before anything is stored.
TEST(Limits, PixelsPerJob) {
  Farm farm(FarmLimits{});
  v1::JobRequestOptions largest;
  largest.set_width(32768);
  largest.set_height(32768);
  largest.set_spp(1);
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), largest),
            "job has 1073741824 pixels (32768 x 32768), over the farm's limit of 67108864 "
            "(server flag --max-pixels): render a smaller image");
  EXPECT_TRUE(farm.coordinator->jobs(100).empty());
  FarmLimits small;
  small.max_pixels_per_job = 16 * 16;
  Farm capped(small);
  v1::JobRequestOptions size;
  size.set_width(16);
  size.set_height(16);
  EXPECT_EQ(capped.refusal(bundle(tiny_scene()), size), "");
  size.set_height(17);
  expect_refused(capped.refusal(bundle(tiny_scene()), size), "--max-pixels");
}

TEST(Limits, UnfinishedJobsPerClient) {
  FarmLimits limits;
  limits.max_queued_jobs_per_client = 2;
  Farm farm(limits);
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), {}, "ipv4:10.0.0.1"), "");
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), {}, "ipv4:10.0.0.1"), "");
  ErrorCode code{};
  const std::string third = farm.refusal(bundle(tiny_scene()), {}, "ipv4:10.0.0.1", &code);
  expect_refused(third, "--max-queued-jobs");
  EXPECT_EQ(code, ErrorCode::resource_exhausted);
  // Another client is not affected; a finished (cancelled) job frees a place.
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), {}, "ipv4:10.0.0.2"), "");
  farm.coordinator->cancel(farm.coordinator->jobs(100).back().id);
  EXPECT_EQ(farm.refusal(bundle(tiny_scene()), {}, "ipv4:10.0.0.1"), "");
}

}  // namespace
}  // namespace tessera::server
