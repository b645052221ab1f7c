// Every light at its extremes, rendered the way `tessera-worker render` renders a scene file
// (worker/extremes_test_support.h). Small images (16 x 16, 16 spp) so that the whole file takes
// seconds.
//
// What each test asks (docs/accuracy.md, "The extremes, each a test"): no NaN or Inf anywhere
// (none dropped, every pixel finite), every pixel positive where light must arrive, and where a
// closed form exists (a delta light on a diffuse floor at depth 2) the pixel equals it.
#include "extremes_test_support.h"
#include "render/texture/texture_test_images.h"

namespace tessera {
namespace {

using namespace extremes_test;

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
  test::write_exr(dir / "bright_texel.exr", 16, 8, bright);
  test::write_exr(dir / "black.exr", 4, 2, std::vector<float>(4 * 2 * 3, 0.0f));
  std::vector<float> spots(8 * 8 * 3, 0.0f);
  for (int i = 0; i < 64; i += 9) spots[size_t(i) * 3] = spots[size_t(i) * 3 + 1] = 50.0f;
  test::write_exr(dir / "spots.exr", 8, 8, spots);
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
