// Every BSDF and every light at its extremes, rendered the way `tessera-worker render` renders a
// scene file: the scene is written to a folder with its textures and environment maps, read by
// load_scene_file, its options resolved by resolve_job_options and rendered by render_job (the
// farm's tile, batch and merge path), then resolved to the image. Small images (16 x 16, 16 spp)
// so that the whole file takes seconds.
//
// What each test asks (docs/accuracy.md, "The extremes, each a test"): no NaN or Inf
// anywhere (none dropped, every pixel finite), every pixel positive where light must arrive, and
// where a closed form exists (a delta light on a diffuse floor at depth 2) the pixel equals it.
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
#include "render/texture/texture_test_images.h"
#include "scene/scene_loader.h"

namespace tessera {
namespace {

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

void write_file(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  ASSERT_TRUE(out.good()) << path;
}

/// An RGB float EXR of `width` x `height` texels (row-major from the top row).
void write_exr(const fs::path& path, int width, int height, const std::vector<float>& rgb) {
  write_file(path, test::encode_image(path.filename().string(), width, height, 3, rgb,
                                      OIIO::TypeDesc::FLOAT));
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

Rendered render_file(const fs::path& scene_file, int width, int height, int spp,
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
void expect_finite(const Rendered& r, const std::string& what, bool positive) {
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

// --- Materials ---------------------------------------------------------------------------------

/// The textures every material case may use, written beside the scene: a checkerboard; an
/// 8 x 8 normal map holding the extreme tangent-space directions (along the surface, straight
/// into it, the zero vector of mid-grey, along -u and -v) among ordinary ones; and an 8 x 8
/// height field with one-texel cliffs (a bump map with scale 100 tilts normals almost flat).
const char* kTextures = R"(
  "checker": {"type": "checkerboard", "color0": [0.9, 0.9, 0.9], "color1": [0.05, 0.05, 0.05],
              "to_uv": [[4, 0, 0], [0, 4, 0]]},
  "normals": {"type": "bitmap", "file": "normals.exr", "filter": "nearest"},
  "heights": {"type": "bitmap", "file": "heights.exr"},
  "opacity": {"type": "checkerboard", "color0": [1, 1, 1], "color1": [0, 0, 0],
              "to_uv": [[3, 0, 0], [0, 3, 0]]})";

void write_material_textures(const fs::path& dir) {
  // Texel = (m + 1) / 2 for a tangent-space direction m (need not be unit).
  const std::vector<glm::vec3> directions = {
      {0, 0, 1}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0},   {-1, 0, 0}, {0, -1, 0.001f},
      {0, 1, 0}, {1, 1, 1}, {0.3f, -0.2f, 0.9f}, {-0.99f, 0.1f, 0.01f}};
  std::vector<float> normals;
  for (int i = 0; i < 64; ++i) {
    const glm::vec3 m = directions[size_t(i * 7 + i / 8) % directions.size()];
    for (int c = 0; c < 3; ++c) normals.push_back(0.5f * (m[c] + 1.0f));
  }
  write_exr(dir / "normals.exr", 8, 8, normals);
  std::vector<float> heights;
  for (int i = 0; i < 64; ++i) {
    const float h = ((i * 37) % 11 == 0) ? 1.0f : ((i % 3 == 0) ? 0.5f : 0.0f);
    heights.insert(heights.end(), {h, h, h});
  }
  write_exr(dir / "heights.exr", 8, 8, heights);
}

struct MaterialCase {
  const char* name;
  const char* material;  ///< the JSON object of material "test"
  const char* extra = "";  ///< more materials, each `"name": {...},` (a `back` names one)
  /// A perturbed normal can turn a specular reflection or refraction below the surface, which
  /// counts as black (Mitsuba's normalmap and bumpmap adapters do the same): a pixel on such
  /// texels may be black, so only the image mean must be > 0.
  bool black_allowed = false;
  /// Samples per pixel of the stage render. 16 leaves a pixel black by chance where few
  /// directions get light back (a normal-mapped anisotropic conductor: at 16 spp 10 or 11 of
  /// seeds 1-16 gave a black pixel, by the sampler, at 64 spp none), so such a case takes more, asserting the same.
  int stage_spp = 16;
};

/// The stage: the test material on a sphere and on a tilted quad with uvs (for textures, normal
/// and bump maps), over a grey floor, lit by a quad light and a dim uniform environment (so that
/// every pixel receives light, whatever the material does with it). `floor` is the floor's
/// material ("test" for the grazing views).
std::string material_scene(const MaterialCase& c, const std::string& camera, const char* floor) {
  return std::string(R"({"tessera": 1,
  "camera": )") + camera + R"(,
  "textures": {)" + kTextures + R"(},
  "materials": {)" + c.extra + R"(
    "grey": {"type": "diffuse", "reflectance": [0.5, 0.5, 0.5]},
    "test": )" + c.material + R"(},
  "shapes": [
    {"type": "quad", "material": ")" + floor + R"(",
     "vertices": [[-20, 0, 20], [20, 0, 20], [20, 0, -20], [-20, 0, -20]]},
    {"type": "sphere", "center": [-0.55, 0.5, 0], "radius": 0.5, "material": "test"},
    {"type": "triangles", "material": "test",
     "vertices": [[0.1, 0.05, 0.3], [1.1, 0.05, 0.1], [1.1, 1.05, -0.2], [0.1, 1.05, 0]],
     "indices": [[0, 1, 2], [0, 2, 3]], "uvs": [[0, 1], [1, 1], [1, 0], [0, 0]]},
    {"type": "quad", "emission": [6, 6, 6],
     "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0.5, 3, 0.5], [-0.5, 3, 0.5]]}
  ],
  "lights": [{"type": "constant", "radiance": [0.3, 0.3, 0.3]}]
})";
}

// A camera that sees the stage, and one 2 mm above the floor looking along it (rays meet the
// floor at 0.04 to 0.6 degrees, and the sphere's silhouette edge-on).
const char* kStageCamera = R"({"position": [0.3, 1.4, 3.2], "look_at": [0, 0.45, 0], "fov": 45})";
const char* kGrazingCamera =
    R"({"position": [0, 0.002, 3], "look_at": [0, -0.01, 0], "fov": 1.2, "fov_axis": "y"})";

const MaterialCase kMaterials[] = {
    {"diffuse_white", R"({"type": "diffuse", "reflectance": [1, 1, 1]})"},
    {"diffuse_textured", R"({"type": "diffuse", "reflectance": {"texture": "checker"}})"},
    {"conductor_k0", R"({"type": "conductor", "eta": [1.5, 1.5, 1.5], "k": [0, 0, 0]})"},
    {"conductor_eta0_k0", R"({"type": "conductor", "eta": [0, 0, 0], "k": [0, 0, 0]})"},
    {"conductor_perfect", R"({"type": "conductor", "perfect": true})"},
    {"conductor_textured", R"({"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1],
                                "specular_reflectance": {"texture": "checker"}})"},
    {"roughconductor_ggx_alpha_1e-4",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1e-4, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]})"},
    {"roughconductor_ggx_alpha_1",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1, "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]})"},
    {"roughconductor_beckmann_alpha_1e-4",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha": 1e-4, "perfect": true})"},
    {"roughconductor_beckmann_alpha_1",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha": 1, "perfect": true})"},
    {"roughconductor_k0_alpha_1",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": 1, "eta": [1.5, 1.5, 1.5], "k": [0, 0, 0]})"},
    {"roughconductor_anisotropic",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha_u": 1e-4, "alpha_v": 1, "perfect": true})"},
    {"roughconductor_anisotropic_beckmann_unsampled",
     R"({"type": "rough_conductor", "distribution": "beckmann", "alpha_u": 1, "alpha_v": 1e-4,
         "sample_visible": false, "perfect": true})"},
    {"roughconductor_textured_alpha",
     R"({"type": "rough_conductor", "distribution": "ggx", "alpha": {"texture": "checker"}, "perfect": true})"},
    {"dielectric_eta_1.0001", R"({"type": "glass", "ior": 1.0001})"},
    {"dielectric_eta_10", R"({"type": "glass", "ior": 10})"},
    {"dielectric_eta_0.5", R"({"type": "glass", "ior": 0.5})"},
    {"dielectric_tinted", R"({"type": "glass", "ior": 1.5, "specular_reflectance": [0.5, 0.5, 0.5],
                              "specular_transmittance": {"texture": "checker"}})"},
    {"roughdielectric_eta_1.0001_alpha_1e-4",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.0001, "alpha": 1e-4})"},
    {"roughdielectric_eta_1.0001_alpha_1",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.0001, "alpha": 1})"},
    {"roughdielectric_eta_10_alpha_1e-4",
     R"({"type": "rough_glass", "distribution": "beckmann", "ior": 10, "alpha": 1e-4})"},
    {"roughdielectric_eta_10_alpha_1",
     R"({"type": "rough_glass", "distribution": "beckmann", "ior": 10, "alpha": 1})"},
    {"roughdielectric_anisotropic",
     R"({"type": "rough_glass", "distribution": "ggx", "ior": 1.5, "alpha_u": 1e-4, "alpha_v": 1})"},
    {"thindielectric", R"({"type": "thin_glass", "ior": 1.5})"},
    {"thindielectric_eta_1.0001", R"({"type": "thin_glass", "ior": 1.0001})"},
    {"thindielectric_eta_10", R"({"type": "thin_glass", "ior": 10})"},
    {"plastic", R"({"type": "plastic", "diffuse_reflectance": [0.8, 0.2, 0.1]})"},
    {"plastic_nonlinear_eta_10",
     R"({"type": "plastic", "ior": 10, "nonlinear": true, "diffuse_reflectance": [1, 1, 1]})"},
    {"plastic_eta_1.0001", R"({"type": "plastic", "ior": 1.0001, "diffuse_reflectance": [0.5, 0.5, 0.5]})"},
    {"roughplastic_alpha_1e-4",
     R"({"type": "rough_plastic", "distribution": "ggx", "alpha": 1e-4, "diffuse_reflectance": [0.8, 0.2, 0.1]})"},
    {"roughplastic_alpha_1",
     R"({"type": "rough_plastic", "distribution": "beckmann", "alpha": 1, "nonlinear": true,
         "diffuse_reflectance": {"texture": "checker"}})"},
    {"roughplastic_eta_1.0001_alpha_1",
     R"({"type": "rough_plastic", "distribution": "ggx", "ior": 1.0001, "alpha": 1, "diffuse_reflectance": [1, 1, 1]})"},
    {"twosided_diffuse", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "two_sided": true})"},
    {"twosided_conductor_with_diffuse_back",
     R"({"type": "rough_conductor", "alpha": 0.2, "perfect": true, "two_sided": true, "back": "back"})",
     R"("back": {"type": "diffuse", "reflectance": [0.2, 0.6, 0.2], "two_sided": true},)"},
    {"mask_0", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "opacity": 0})"},
    {"mask_0.5", R"({"type": "rough_conductor", "alpha": 0.3, "perfect": true, "opacity": 0.5})"},
    {"mask_1", R"({"type": "plastic", "opacity": 1})"},
    {"mask_textured", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "two_sided": true,
                          "opacity": {"texture": "opacity"}})"},
    {"normalmap_diffuse", R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "normal_map": "normals"})"},
    {"normalmap_conductor", R"({"type": "conductor", "perfect": true, "normal_map": "normals"})",
     "", true},
    {"normalmap_dielectric", R"({"type": "glass", "ior": 1.5, "normal_map": "normals"})", "", true},
    {"normalmap_anisotropic_roughconductor",
     R"({"type": "rough_conductor", "alpha_u": 0.05, "alpha_v": 0.8, "perfect": true, "normal_map": "normals"})",
     "", false, 64},
    {"bumpmap_diffuse",
     R"({"type": "diffuse", "reflectance": [0.7, 0.7, 0.7], "bump_map": "heights", "bump_scale": 100})"},
    {"bumpmap_roughdielectric",
     R"({"type": "rough_glass", "ior": 1.33, "alpha": 0.05, "bump_map": "heights", "bump_scale": 100})",
     "", true},
    {"bumpmap_roughplastic",
     R"({"type": "rough_plastic", "alpha": 1e-4, "bump_map": "heights", "bump_scale": 0.01})"},
};

class MaterialExtremes : public ::testing::TestWithParam<MaterialCase> {};

TEST_P(MaterialExtremes, RenderFiniteAndLit) {
  const MaterialCase& c = GetParam();
  const SceneFolder dir(std::string("material_") + c.name);
  write_material_textures(dir.path());
  // Seen from above: every pixel sees the floor, the objects or the environment, each lit.
  write_file(dir / "stage.json", material_scene(c, kStageCamera, "grey"));
  const Rendered stage = render_file(dir / "stage.json", 16, 16, c.stage_spp);
  expect_finite(stage, std::string(c.name) + " (stage)", !c.black_allowed);
  EXPECT_GT(stage.mean_luminance(), 0.0) << c.name;
  // The floor made of the material, seen at grazing angles. Light arrives at every point of it,
  // but a specular floor may reflect only the (black) ground-level horizon: no positivity.
  write_file(dir / "grazing.json", material_scene(c, kGrazingCamera, "test"));
  expect_finite(render_file(dir / "grazing.json", 16, 16, 16), std::string(c.name) + " (grazing)",
                false);
}

INSTANTIATE_TEST_SUITE_P(Extremes, MaterialExtremes, ::testing::ValuesIn(kMaterials),
                         [](const auto& info) {
                           std::string name = info.param.name;
                           for (char& ch : name) {
                             if (ch == '.' || ch == '-') ch = '_';
                           }
                           return name;
                         });

TEST(MaterialExtremes, EveryNamedMetalRendersFinite) {
  // Mitsuba's named conductors (some are dielectrics with k = 0 at some wavelengths, MgO, ThF4),
  // smooth and at alpha 1e-4 and 1, through the importer: one small sphere each.
  const char* metals[] = {"a-C",  "Ag",   "Al",   "AlAs", "AlAs_palik", "AlSb", "Au",   "Be",
                          "Cr",   "CsI",  "Cu",   "Cu2O", "CuO",        "d-C",  "Hg",   "HgTe",
                          "Ir",   "K",    "Li",   "MgO",  "Mo",         "Na_palik", "Nb", "Ni_palik",
                          "Rh",   "Se",   "Se-e", "SiC",  "SnTe",       "Ta",   "Te",   "Te-e",
                          "ThF4", "TiC",  "TiN",  "TiO2", "TiO2-e",     "VC",   "VN",   "W",
                          "none"};
  const SceneFolder dir("named_metals");
  std::string xml = R"(<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 0, 9" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>
  <shape type="rectangle">
    <transform name="to_world"><scale value="0.5"/><rotate x="1" angle="90"/><translate y="6"/></transform>
    <emitter type="area"><rgb name="radiance" value="20"/></emitter>
  </shape>
)";
  int i = 0;
  for (const char* metal : metals) {
    const char* kinds[] = {R"(<bsdf type="conductor">)",
                           R"(<bsdf type="roughconductor"><float name="alpha" value="0.0001"/>)",
                           R"(<bsdf type="roughconductor"><float name="alpha" value="1"/><string name="distribution" value="ggx"/>)"};
    const int kind = i % 3;
    const double x = -3.6 + 0.8 * (i % 10), y = -3.2 + 0.8 * (i / 10);
    xml += "  <shape type=\"sphere\"><point name=\"center\" value=\"" + std::to_string(x) + ", " +
           std::to_string(y) + ", 0\"/><float name=\"radius\" value=\"0.38\"/>" + kinds[kind] +
           "<string name=\"material\" value=\"" + metal + "\"/></bsdf></shape>\n";
    ++i;
  }
  xml += "</scene>\n";
  write_file(dir / "metals.xml", xml);
  expect_finite(render_file(dir / "metals.xml", 32, 32, 16), "named metals", true);
}

// --- Lights ------------------------------------------------------------------------------------

TEST(LightExtremes, PointAndSpotLightsLyingOnASurfaceStillLightTheScene) {
  // A spot (and a point light) placed exactly on the floor, the spot shining up at a sphere:
  // every shadow ray from the sphere ends at the light's position, which the floor passes
  // through. Shadow rays to delta lights stop short of it (kDeltaShadowEnd, as Mitsuba's
  // spawn_ray_to), so the sphere is lit; ending at the light itself left the image black
  // (langevin-mc-rendering's scene_directional.xml).
  for (const char* light : {R"(<emitter type="spot"><float name="cutoff_angle" value="60"/>
      <rgb name="intensity" value="10"/>
      <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>
    </emitter>)",
                            R"(<emitter type="point"><point name="position" value="0, 0, 0"/>
      <rgb name="intensity" value="10"/></emitter>)"}) {
    const SceneFolder dir("light_on_floor");
    write_file(dir / "scene.xml", std::string(R"(<scene version="3.0.0">
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, -6, 2" target="0, 0, 1" up="0, 0, 1"/></transform>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
  </sensor>
  <shape type="rectangle"><transform name="to_world"><scale value="4"/></transform></shape>
  <shape type="sphere"><point name="center" value="0, 0, 1.5"/><float name="radius" value="0.5"/></shape>
  )") + light + "\n</scene>\n");
    const Rendered r = render_file(dir / "scene.xml", 16, 16, 4);
    expect_finite(r, "light on the floor", false);
    EXPECT_GT(r.mean_luminance(), 1e-3) << light;
  }
}


struct LightCase {
  const char* name;
  const char* shapes;  ///< extra shapes (area emitters), each `{...},`
  const char* lights;  ///< the "lights" array's contents
  /// Where light must arrive. A surface lit only from one side of the sky may reflect black
  /// (a rough metal facing away), so only an environment all around lights every pixel.
  enum class Lit {
    every_pixel,  ///< an environment all around: every pixel > 0
    floor_row,    ///< the bottom row sees the floor in front, directly lit: those pixels > 0
    mean,         ///< the light reaches some of what the camera sees: the image mean > 0
    none,         ///< the light emits nothing: the image is exactly black
    /// the lit patch is far smaller than a pixel and 16 samples miss it (DeltaLightExtremes
    /// aims at it instead): finite only
    finite,
  } lit = Lit::mean;
};
using Lit = LightCase::Lit;

/// The stage for the lights: a floor and a wall, with a diffuse, a rough-conductor, a rough
/// glass and a plastic sphere (every sampling strategy and multiple importance sampling), lit
/// by the case's lights alone.
std::string light_scene(const LightCase& c, const std::string& camera) {
  return std::string(R"({"tessera": 1,
  "camera": )") + camera + R"(,
  "textures": {
    "checker": {"type": "checkerboard", "color0": [1, 1, 1], "color1": [0.01, 0.01, 0.01],
                "to_uv": [[5, 0, 0], [0, 5, 0]]},
    "spots": {"type": "bitmap", "file": "spots.exr"}
  },
  "materials": {
    "grey": {"type": "diffuse", "reflectance": [0.5, 0.5, 0.5]},
    "metal": {"type": "rough_conductor", "distribution": "ggx", "alpha": 0.05,
              "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.1]},
    "glass": {"type": "rough_glass", "alpha": 0.1, "ior": 1.5},
    "plastic": {"type": "plastic", "diffuse_reflectance": [0.2, 0.4, 0.8]}
  },
  "shapes": [)" + c.shapes + R"(
    {"type": "quad", "material": "grey",
     "vertices": [[-20, 0, 20], [20, 0, 20], [20, 0, -20], [-20, 0, -20]]},
    {"type": "quad", "material": "grey",
     "vertices": [[-20, 0, -2], [20, 0, -2], [20, 20, -2], [-20, 20, -2]]},
    {"type": "sphere", "center": [-1.2, 0.4, 0], "radius": 0.4, "material": "grey"},
    {"type": "sphere", "center": [-0.4, 0.4, 0], "radius": 0.4, "material": "metal"},
    {"type": "sphere", "center": [0.4, 0.4, 0], "radius": 0.4, "material": "glass"},
    {"type": "sphere", "center": [1.2, 0.4, 0], "radius": 0.4, "material": "plastic"}
  ],
  "lights": [)" + c.lights + R"(]
})";
}

/// Textures of the light cases: a 16 x 8 map that is black but for one texel of 1e5 (light from
/// a single small patch of sky), an all-zero map, and an area emitter's radiance texture.
void write_light_textures(const fs::path& dir) {
  std::vector<float> bright(16 * 8 * 3, 0.0f);
  bright[(2 * 16 + 5) * 3 + 0] = 1e5f;  // row 2 of 8: 56 degrees above the horizon
  bright[(2 * 16 + 5) * 3 + 1] = 1e5f;
  bright[(2 * 16 + 5) * 3 + 2] = 0.5e5f;
  write_exr(dir / "bright_texel.exr", 16, 8, bright);
  write_exr(dir / "black.exr", 4, 2, std::vector<float>(4 * 2 * 3, 0.0f));
  std::vector<float> spots(8 * 8 * 3, 0.0f);
  for (int i = 0; i < 64; i += 9) spots[size_t(i) * 3] = spots[size_t(i) * 3 + 1] = 50.0f;
  write_exr(dir / "spots.exr", 8, 8, spots);
}

const char* kLightCamera = R"({"position": [0, 1.6, 4], "look_at": [0, 0.4, 0], "fov": 50})";

const LightCase kLights[] = {
    {"area_quad", R"({"type": "quad", "emission": [5, 5, 5],
       "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0.5, 3, 0.5], [-0.5, 3, 0.5]]},)", "", Lit::floor_row},
    {"area_quad_textured", R"({"type": "triangles", "emission": {"texture": "checker", "scale": 5},
       "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0.5, 3, 0.5], [-0.5, 3, 0.5]],
       "indices": [[0, 1, 2], [0, 2, 3]], "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]]},)", "", Lit::floor_row},
    {"area_bitmap_radiance_mostly_black", R"({"type": "triangles", "emission": {"texture": "spots"},
       "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0.5, 3, 0.5], [-0.5, 3, 0.5]],
       "indices": [[0, 1, 2], [0, 2, 3]], "uvs": [[0, 0], [1, 0], [1, 1], [0, 1]]},)", "", Lit::floor_row},
    {"area_sphere", R"({"type": "sphere", "center": [0.5, 2.5, 1], "radius": 0.3, "emission": [8, 8, 8]},)",
     "", Lit::floor_row},
    {"area_sphere_tiny", R"({"type": "sphere", "center": [0.5, 2.5, 1], "radius": 1e-4, "emission": [1e8, 1e8, 1e8]},)",
     "", Lit::floor_row},
    {"area_sphere_textured", R"({"type": "sphere", "center": [0.5, 2.5, 1], "radius": 0.3,
       "emission": {"texture": "checker", "scale": [8, 6, 4]}},)", "", Lit::floor_row},
    {"area_triangle", R"({"type": "triangles", "emission": [10, 10, 10], "two_sided": true,
       "vertices": [[-0.5, 3, -0.5], [0.5, 3, -0.5], [0, 3, 0.5]], "indices": [[0, 1, 2]]},)", "",
     Lit::floor_row},
    {"area_needle_triangle", R"({"type": "triangles", "emission": [1e4, 1e4, 1e4],
       "vertices": [[-2, 3, 0], [2, 3, 0], [2, 3, 1e-4]], "indices": [[0, 1, 2]]},)", "", Lit::floor_row},
    {"point", "", R"({"type": "point", "intensity": 8, "transform": {"translate": [0.3, 2.5, 1]}})",
     Lit::floor_row},
    {"spot_beam_equals_cutoff", "",
     R"({"type": "spot", "intensity": 20, "cutoff_angle": 40, "beam_width": 40,
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 3, 0]}]})"},
    {"spot_tiny_cutoff", "",
     R"({"type": "spot", "intensity": 20, "cutoff_angle": 0.05, "beam_width": 0.01,
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 3, 0]}]})",
     Lit::finite},
    {"spot_cutoff_90", "",
     R"({"type": "spot", "intensity": 5, "cutoff_angle": 90,
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": 60}}, {"translate": [0, 3, 1]}]})"},
    // Light travels along the transform's +z: turned 110 degrees about x it falls at 70 degrees
    // from behind the camera (from the other side the wall would shadow the floor in front).
    {"directional", "",
     R"({"type": "directional", "irradiance": 3,
         "transform": {"rotate": {"axis": [1, 0, 0], "angle": 110}}})", Lit::floor_row},
    {"directional_grazing", "",  // 0.01 degree above the horizon
     R"({"type": "directional", "irradiance": 3,
         "transform": {"rotate": {"axis": [1, 0, 0], "angle": 179.99}}})"},
    {"constant", "", R"({"type": "constant", "radiance": [1, 0.8, 0.6]})", Lit::every_pixel},
    {"envmap_one_bright_texel", "", R"({"type": "envmap", "file": "bright_texel.exr"})"},
    {"envmap_all_zero", "", R"({"type": "envmap", "file": "black.exr"})", Lit::none},
    {"envmap_scale_0", "", R"({"type": "envmap", "file": "bright_texel.exr", "scale": 0})", Lit::none},
    {"everything_at_once",
     R"({"type": "sphere", "center": [0.5, 2.5, 1], "radius": 1e-3, "emission": [1e6, 1e6, 1e6]},)",
     R"({"type": "envmap", "file": "bright_texel.exr", "transform": {"rotate": {"axis": [0, 1, 0], "angle": 30}}},
        {"type": "envmap", "file": "black.exr"},
        {"type": "point", "intensity": 1e-6, "transform": {"translate": [0, 0.01, 0.8]}},
        {"type": "spot", "intensity": 1e6, "cutoff_angle": 1, "beam_width": 1,
         "transform": [{"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0.4, 3, 0]}]},
        {"type": "constant", "radiance": 1e-3})",
     Lit::every_pixel},
};

class LightExtremes : public ::testing::TestWithParam<LightCase> {};

TEST_P(LightExtremes, RenderFiniteAndLit) {
  const LightCase& c = GetParam();
  const SceneFolder dir(std::string("light_") + c.name);
  write_light_textures(dir.path());
  write_file(dir / "stage.json", light_scene(c, kLightCamera));
  const Rendered stage = render_file(dir / "stage.json", 16, 16, 16);
  expect_finite(stage, std::string(c.name) + " (stage)", c.lit == Lit::every_pixel);
  if (c.lit == Lit::none) {
    for (float v : stage.image.rgb) ASSERT_EQ(v, 0.0f) << c.name << ": light from a black emitter";
  } else if (c.lit != Lit::finite) {
    EXPECT_GT(stage.mean_luminance(), 0.0) << c.name;
  }
  if (c.lit == Lit::floor_row) {
    for (int x = 0; x < stage.image.width; ++x) {
      EXPECT_GT(stage.luminance(x, stage.image.height - 1), 0.0) << c.name << ": floor pixel " << x;
    }
  }
  // Grazing: 2 mm above the floor, along it, towards the wall and the spheres.
  write_file(dir / "grazing.json", light_scene(c, kGrazingCamera));
  expect_finite(render_file(dir / "grazing.json", 16, 16, 16), std::string(c.name) + " (grazing)",
                false);
}

INSTANTIATE_TEST_SUITE_P(Extremes, LightExtremes, ::testing::ValuesIn(kLights),
                         [](const auto& info) { return std::string(info.param.name); });

// --- Delta lights against their closed forms ----------------------------------------------------

/// A diffuse floor (albedo rho) lit by `light` alone, seen through a 1-pixel, 1e-4-degree camera
/// aimed at `target` on it, at depth 2 (direct light only): a delta light's estimate has no
/// randomness there, so the pixel is rho / pi * E(target) to float rounding.
double floor_pixel(const std::string& name, const std::string& light, glm::dvec3 target,
                   double rho, bool lit = true) {
  const SceneFolder dir("closed_form_" + name);
  char camera[256];
  std::snprintf(camera, sizeof camera,
                R"({"position": [%.17g, 1.3, %.17g], "look_at": [%.17g, 0, %.17g], "fov": 1e-4})",
                target.x + 0.7, target.z + 1.1, target.x, target.z);
  char floor_material[128];
  std::snprintf(floor_material, sizeof floor_material,
                R"({"type": "diffuse", "reflectance": [%.17g, %.17g, %.17g]})", rho, rho, rho);
  write_file(dir / "floor.json", std::string(R"({"tessera": 1, "camera": )") + camera +
                                     R"(, "materials": {"floor": )" + floor_material + R"(},
    "shapes": [{"type": "quad", "material": "floor",
                "vertices": [[-50, 0, 50], [50, 0, 50], [50, 0, -50], [-50, 0, -50]]}],
    "lights": [)" + light + "]}");
  const Rendered r = render_file(dir / "floor.json", 1, 1, 4, 2);
  expect_finite(r, name, lit);
  return r.luminance(0, 0);
}

/// A spot 3 above (0.2, 0, -0.3) (+ `offset` in z) shining straight down.
std::string spot_down(double cutoff, double beam, double offset = 0) {
  char light[320];
  std::snprintf(light, sizeof light,
                R"({"type": "spot", "intensity": 20, "cutoff_angle": %.17g, "beam_width": %.17g,
                    "transform": [{"rotate": {"axis": [1, 0, 0], "angle": 90}},
                                  {"translate": [0.2, 3, %.17g]}]})",
                cutoff, beam, -0.3 + offset);
  return light;
}

TEST(DeltaLightExtremes, PointSpotAndDirectionalMatchTheirClosedForms) {
  const double rho = 0.6, tol = 1e-4;  // float rounding of the path, relative
  const glm::dvec3 p(0.2, 0, -0.3);
  {  // point light of intensity 8, 2 above a point 0.4 to the side of p
    const glm::dvec3 light(0.6, 2.0, -0.3);
    const double d = glm::length(light - p), cos = light.y / d;
    const double expected = rho / M_PI * 8.0 * cos / (d * d);
    EXPECT_NEAR(floor_pixel("point", R"({"type": "point", "intensity": 8,
        "transform": {"translate": [0.6, 2, -0.3]}})", p, rho), expected, tol * expected);
  }
  // Spots straight down from 3 above p: the centre of the beam gets the full intensity I / 9,
  // with beam = cutoff, and with a cutoff of 0.05 degree (a beam 5 mm across at the floor).
  const double spot_expected = rho / M_PI * 20.0 / 9.0;
  for (const auto& [cutoff, beam] : {std::pair{30.0, 30.0}, {0.05, 0.05}, {0.05, 0.0375}}) {
    EXPECT_NEAR(floor_pixel("spot", spot_down(cutoff, beam), p, rho), spot_expected,
                tol * spot_expected)
        << "cutoff " << cutoff << ", beam " << beam;
  }
  // 1 cm off the axis of a 0.05-degree spot (radius 2.6 mm at the floor): black.
  EXPECT_EQ(floor_pixel("spot_outside", spot_down(0.05, 0.05, 0.01), p, rho, false), 0.0);
  // A cutoff of 0.01 degree: cos(cutoff) rounds to 1 in float, so no direction is strictly inside
  // the cone and the spot is black everywhere, as Mitsuba's (spot.cpp: local_dir.z() >
  // m_cos_cutoff_angle, in float). It must stay finite.
  floor_pixel("spot_0.01", spot_down(0.01, 0.01), p, rho, false);
  // Directional light at 20 and 0.01 degrees above the horizon: rho / pi * E * cos.
  for (double angle : {20.0, 0.01}) {
    const std::string light = R"({"type": "directional", "irradiance": 3,
        "transform": {"rotate": {"axis": [1, 0, 0], "angle": )" + std::to_string(angle) + "}}}";
    const double expected = rho / M_PI * 3.0 * std::sin(angle * M_PI / 180.0);
    EXPECT_NEAR(floor_pixel("directional", light, p, rho), expected, tol * expected)
        << "at " << angle << " degrees above the horizon";
  }
}

}  // namespace
}  // namespace tessera
