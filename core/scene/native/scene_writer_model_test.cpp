// The native JSON writer over every field of the scene model: parse(write(scene)) == scene, bit
// for bit, and the model fields JSON cannot say refused.
#include "scene/native/scene_writer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "scene/native/json_value.h"
#include "scene/native/scene_writer_test_support.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

using testing::expect_same_scene;
using testing::round_trip;
using testing::memory_reader;

/// Every field of the scene model that the native format holds, each away from its default.
Scene full_model_scene() {
  Scene s;
  s.film.filter = {FilterKind::gaussian, 1.7000000000000002, 0.4};
  s.render.hide_emitters = true;
  s.render.rr_depth = 1000;
  Texture wood;
  wood.name = "wood";
  wood.file = "tex/wood.png";
  wood.filter = TextureFilter::nearest;
  wood.wrap = TextureWrap::mirror;
  wood.to_uv[0][0] = 2;    // u' = 2 u + 0.1 v + 0.25
  wood.to_uv[1][0] = 0.1;
  wood.to_uv[2][0] = 0.25;
  wood.to_uv[1][1] = -3;   // v' = -3 v + 1e-17
  wood.to_uv[2][1] = 1e-17;
  Texture height = wood;
  height.name = "height";
  height.file = "tex/height.exr";
  height.color_space = TextureColorSpace::linear;
  height.filter = TextureFilter::bilinear;
  height.wrap = TextureWrap::clamp;
  height.to_uv = glm::dmat3(1.0);
  Texture checks;
  checks.name = "checks";
  checks.kind = TextureKind::checkerboard;
  checks.color0 = {0.1, 0.2, 0.30000000000000004};
  checks.color1 = {1, 0, 0.5};
  Texture raw1;
  raw1.name = "raw1";
  raw1.kind = TextureKind::rawconstant;
  raw1.value = glm::dvec3(-0.30000000000000004);
  raw1.channels = 1;
  Texture raw3 = raw1;
  raw3.name = "raw3";
  raw3.value = {0.5, 1e-300, 7};
  raw3.channels = 3;
  s.textures = {wood, height, checks, raw1, raw3};

  auto material = [](const char* name, MaterialType type) {
    Material m;
    m.name = name;
    m.type = type;
    return m;
  };
  Material diffuse = material("diffuse", MaterialType::diffuse);
  diffuse.reflectance = {{1, 0.5, 2}, 0};
  diffuse.opacity = {0.7, 2};
  diffuse.normal_map = 1;
  diffuse.back = 9;
  Material mirror = material("mirror", MaterialType::mirror);
  mirror.bump_map = 1;
  mirror.bump_scale = -0.01;
  mirror.opacity = {0.25, -1};
  Material glass = material("glass", MaterialType::glass);
  glass.ior = 1.33;
  glass.specular_reflectance = {{0.5, 0.5, 0.5}, -1};
  glass.specular_transmittance = {{1, 1, 1}, 2};
  Material conductor = material("gold", MaterialType::conductor);
  conductor.eta = {0.143, 0.374, 1.442};
  conductor.k = {3.983, 2.385, 1.603};
  conductor.specular_reflectance = {{0.9, 0.8, 0.7}, -1};
  Material rough_conductor = material("brushed", MaterialType::rough_conductor);
  rough_conductor.perfect = true;
  rough_conductor.distribution = MicrofacetDistribution::ggx;
  rough_conductor.alpha_u = {0.05, -1};
  rough_conductor.alpha_v = {0.3, 1};
  rough_conductor.sample_visible = false;
  Material rough_glass = material("frosted", MaterialType::rough_glass);
  rough_glass.ior = 1.5046;
  rough_glass.alpha_u = rough_glass.alpha_v = {0.2, -1};
  Material thin = material("window", MaterialType::thin_glass);
  thin.ior = 1.52;
  Material plastic = material("plastic", MaterialType::plastic);
  plastic.reflectance = {{0.1, 0.2, 0.3}, -1};
  plastic.nonlinear = true;
  plastic.ior = 1.9;
  Material rough_plastic = material("rough plastic", MaterialType::rough_plastic);
  rough_plastic.reflectance = {{2, 2, 2}, 2};
  rough_plastic.alpha_u = rough_plastic.alpha_v = {0.4, -1};
  Material back = material("back", MaterialType::diffuse);
  back.two_sided = true;
  Material principled = material("principled", MaterialType::principled);
  principled.reflectance = {{0.2, 0.8, 0.1}, 0};
  principled.ior = 1.4142135623730951;
  principled.two_sided = true;
  PrincipledParameters& pp = principled.principled;
  pp.roughness = {0.15, -1};
  pp.anisotropic = {1, 2};
  pp.metallic = {0.3, -1};
  pp.spec_tint = {0.5, 0};
  pp.sheen = {0.6, -1};
  pp.sheen_tint = {0.7, -1};
  pp.flatness = {0.8, -1};
  pp.clearcoat = {0.9, 2};
  pp.clearcoat_gloss = {0.25, -1};
  pp.main_specular_sampling_rate = 2;
  pp.clearcoat_sampling_rate = 0.5;
  pp.diffuse_reflectance_sampling_rate = 0;
  Material transmissive = material("principled glass", MaterialType::principled);
  transmissive.principled.spec_trans = {0.75, -1};
  transmissive.ior = 0.8;
  Material leaf = material("leaf", MaterialType::principled_thin);
  leaf.reflectance = {{0.3, 0.7, 0.2}, -1};
  leaf.ior = 1.25;
  leaf.ior_texture = 2;
  PrincipledParameters& lp = leaf.principled;
  lp.roughness = {0.35, 0};
  lp.anisotropic = {0.5, -1};
  lp.spec_trans = {0.6, 2};
  lp.spec_tint = {0.1, -1};
  lp.sheen = {0.2, -1};
  lp.sheen_tint = {0.3, -1};
  lp.flatness = {0.4, -1};
  lp.diff_trans = {1.75, -1};
  lp.diffuse_reflectance_sampling_rate = 0.5;
  lp.specular_reflectance_sampling_rate = 1.5;
  lp.specular_transmittance_sampling_rate = 0;
  lp.diffuse_transmittance_sampling_rate = 3;
  Material pplastic = material("pplastic", MaterialType::pplastic);
  pplastic.reflectance = {{0.05, 0.03, 0.1}, -1};
  pplastic.specular_reflectance = {{0.5, 0.5, 0.5}, 0};
  pplastic.ior = 1.49;
  pplastic.distribution = MicrofacetDistribution::ggx;
  pplastic.alpha_u = {0.06, -1};
  pplastic.alpha_v = {0.2, 1};
  pplastic.two_sided = true;
  s.materials = {diffuse, mirror, glass, conductor, rough_conductor, rough_glass, thin,
                 plastic, rough_plastic, back, principled, transmissive, leaf, pplastic};
  Material blend = material("blend", MaterialType::blend);
  blend.blend_weight = {0.8, 2};
  Material inner = material("", MaterialType::blend);
  inner.blend_weight = {0.125, -1};
  inner.blend = {rough_glass, plastic};
  blend.blend = {inner, rough_conductor};
  for (Material& n : blend.blend) n.name = "";
  for (Material& n : blend.blend[0].blend) n.name = "";
  blend.two_sided = false;
  s.materials.push_back(blend);
  Material polarizer = material("polarizer", MaterialType::polarizer);
  polarizer.specular_transmittance = {{0.8, 0.5, 0.2}, 2};
  s.materials.push_back(polarizer);
  Material hair = material("hair", MaterialType::hair);
  hair.ior = 1.3;
  hair.hair.sigma_a = {{20, 0.25, 3}, 1};
  hair.hair.longitudinal_roughness = 0.15;
  hair.hair.azimuthal_roughness = 0.85;
  hair.hair.scale_tilt_deg = -4.5;
  s.materials.push_back(hair);

  Shape tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.uvs = {{0, 0}, {1.5, -0.0}, {1e-300, 1}};
  tri.indices = {{0, 1, 2}};
  tri.material = 0;
  Shape ball;
  ball.kind = Shape::Kind::sphere;
  ball.radius = 0.5;
  double c = std::cos(0.3), sn = std::sin(0.3);
  ball.frame = glm::dmat3(c, sn, 0, -sn, c, 0, 0, 0, 1);
  ball.material = 3;
  ShapeGroup group;
  group.name = "pair";
  group.shapes = {tri, ball};
  s.groups = {group};

  Shape instance;
  instance.kind = Shape::Kind::instance;
  instance.group = 0;
  instance.to_world = glm::dmat4(2.0);
  instance.to_world[3] = glm::dvec4(1, 2, 3, 1);
  Shape glowing = tri;
  glowing.material = 6;
  glowing.emission = {1, 1, 1};
  glowing.emission_texture = 2;
  Shape plain = ball;
  plain.material = 8;
  s.shapes = {instance, glowing, plain, instance};

  Light point;
  point.to_world[3] = glm::dvec4(0, 4, 0, 1);
  point.value = {10, 20, 30};
  Light spot = point;
  spot.kind = LightKind::spot;
  spot.to_world = glm::dmat4(glm::dmat3(c, 0, -sn, 0, 1, 0, sn, 0, c));
  spot.cutoff_angle_deg = 30;
  spot.beam_width_deg = 12.5;
  spot.texture = 2;  // projected over the cone
  Light sun;
  sun.kind = LightKind::directional;
  sun.value = {3, 3, 3};
  Light sky;
  sky.kind = LightKind::constant;
  sky.value = {0.1, 0.2, 0.4};
  Light env;
  env.kind = LightKind::envmap;
  env.file = "sky.exr";
  env.value = glm::dvec3(0.75);
  env.to_world = spot.to_world;
  Light slide;  // a projector has no cone: the spot's fields keep their defaults
  slide.kind = LightKind::projector;
  slide.origin = "lights[5]";
  slide.to_world = spot.to_world;
  slide.value = {0.5, 1.25, 2};
  slide.texture = 0;
  slide.fov_x_deg = 33.398488467987896;
  slide.aspect = 4.0 / 3.0;
  Light lamp = slide;  // a constant image
  lamp.texture = -1;
  lamp.aspect = 1;
  s.lights = {point, spot, sun, sky, env, slide, lamp};
  return s;
}

TEST(SceneWriter, EveryFieldOfTheModelRoundTripsExactly) {
  Scene s = full_model_scene();
  std::string json = write_scene_json(s);
  Scene back = parse_scene(json, memory_reader({}));
  expect_same_scene(s, back);
  EXPECT_EQ(back.referenced_files,
            (std::vector<std::string>{"tex/wood.png", "tex/height.exr", "sky.exr"}));
  EXPECT_EQ(write_scene_json(back), json);
  for (FilterKind kind : {FilterKind::box, FilterKind::tent}) {
    s.film.filter = {kind, kind == FilterKind::box ? 0.5 : 1.25, 0.5};
    expect_same_scene(s, round_trip(s));
  }
  s.film.filter = {FilterKind::mitchell, 2.0, 0.5, 0.1 + 0.2, -0.25};
  expect_same_scene(s, round_trip(s));
  s.film.filter = {FilterKind::lanczos, 5.0, 0.5};
  expect_same_scene(s, round_trip(s));
  s.camera.fov_axis = FovAxis::diagonal;  // a Mitsuba sensor's diagonal angle or focal length
  expect_same_scene(s, round_trip(s));
  // The orthographic camera has no lens: the writer leaves the lens keys out.
  s.camera.projection = Projection::orthographic;
  s.camera.view_size = {0.1 + 0.2, 1e-300};
  s.camera.fov_deg = 39.3;
  s.camera.fov_axis = FovAxis::x;
  s.camera.aperture_radius = 0;
  s.camera.focus_distance = 1;
  expect_same_scene(s, round_trip(s));
  // A Mitsuba sensor's view, whose height follows the image's aspect.
  s.camera.view_aspect = 200.0 / 120.0;
  expect_same_scene(s, round_trip(s));
}

TEST(SceneWriter, RefusesModelFieldsJsonCannotSay) {
  Scene s = full_model_scene();
  s.materials[8].alpha_v = {0.5, -1};  // rough plastic is isotropic
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = full_model_scene();
  s.lights[4].value = {1, 2, 3};  // an envmap's scale is one number
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = full_model_scene();
  s.groups[0].shapes[0].uvs.pop_back();
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = full_model_scene();
  s.materials[0].reflectance.texture = 7;
  EXPECT_THROW(write_scene_json(s), SceneError);
}

TEST(SceneWriter, AnEmptySceneIsValid) {
  Scene s;
  expect_same_scene(s, round_trip(s));
}

// Before, a material native JSON cannot express was written as "{}" and read back as diffuse.

}  // namespace
}  // namespace tessera
