// The native JSON writer: parse(write(scene)) == scene, bit for bit.
#include "scene/native/scene_writer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"
#include "scene/mitsuba/mitsuba_test_support.h"

namespace tessera {
namespace {

using testing::kSourceDir;
using testing::memory_reader;

bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

::testing::AssertionResult same_bits(const glm::dvec3& a, const glm::dvec3& b) {
  for (int i = 0; i < 3; ++i) {
    if (!same_bits(a[i], b[i])) {
      return ::testing::AssertionFailure()
             << "component " << i << ": " << format_number(a[i]) << " vs " << format_number(b[i]);
    }
  }
  return ::testing::AssertionSuccess();
}

bool same_bits(const glm::dmat3& a, const glm::dmat3& b) {
  for (int c = 0; c < 3; ++c) {
    if (!same_bits(a[c], b[c])) return false;
  }
  return true;
}

bool same_bits(const glm::dmat4& a, const glm::dmat4& b) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!same_bits(a[c][r], b[c][r])) return false;
    }
  }
  return true;
}

void expect_same(const TexturedColor& a, const TexturedColor& b) {
  EXPECT_TRUE(same_bits(a.value, b.value));
  EXPECT_EQ(a.texture, b.texture);
}

void expect_same(const TexturedFloat& a, const TexturedFloat& b) {
  EXPECT_TRUE(same_bits(a.value, b.value));
  EXPECT_EQ(a.texture, b.texture);
}

void expect_same_material(const Material& x, const Material& y) {
  SCOPED_TRACE(x.name);
  EXPECT_EQ(x.name, y.name);
  EXPECT_EQ(x.type, y.type);
  expect_same(x.reflectance, y.reflectance);
  EXPECT_TRUE(same_bits(x.ior, y.ior));
  EXPECT_EQ(x.two_sided, y.two_sided);
  EXPECT_EQ(x.ior_texture, y.ior_texture);
  if (x.type != MaterialType::diffuse && x.type != MaterialType::mirror &&
      x.type != MaterialType::principled && x.type != MaterialType::principled_thin) {
    expect_same(x.specular_reflectance, y.specular_reflectance);
  }
  expect_same(x.specular_transmittance, y.specular_transmittance);
  EXPECT_TRUE(same_bits(x.eta, y.eta));
  EXPECT_TRUE(same_bits(x.k, y.k));
  EXPECT_EQ(x.perfect, y.perfect);
  EXPECT_EQ(x.distribution, y.distribution);
  expect_same(x.alpha_u, y.alpha_u);
  expect_same(x.alpha_v, y.alpha_v);
  EXPECT_EQ(x.sample_visible, y.sample_visible);
  EXPECT_EQ(x.nonlinear, y.nonlinear);
  EXPECT_EQ(x.back, y.back);
  expect_same(x.opacity, y.opacity);
  EXPECT_EQ(x.normal_map, y.normal_map);
  EXPECT_EQ(x.bump_map, y.bump_map);
  EXPECT_TRUE(same_bits(x.bump_scale, y.bump_scale));
  const PrincipledParameters &p = x.principled, &q = y.principled;
  for (auto member : {&PrincipledParameters::roughness, &PrincipledParameters::anisotropic,
                      &PrincipledParameters::metallic, &PrincipledParameters::spec_trans,
                      &PrincipledParameters::spec_tint, &PrincipledParameters::sheen,
                      &PrincipledParameters::sheen_tint, &PrincipledParameters::flatness,
                      &PrincipledParameters::clearcoat, &PrincipledParameters::clearcoat_gloss,
                      &PrincipledParameters::diff_trans}) {
    expect_same(p.*member, q.*member);
  }
  EXPECT_TRUE(same_bits(p.specular_reflectance_sampling_rate, q.specular_reflectance_sampling_rate));
  EXPECT_TRUE(
      same_bits(p.specular_transmittance_sampling_rate, q.specular_transmittance_sampling_rate));
  EXPECT_TRUE(
      same_bits(p.diffuse_transmittance_sampling_rate, q.diffuse_transmittance_sampling_rate));
  EXPECT_TRUE(same_bits(p.main_specular_sampling_rate, q.main_specular_sampling_rate));
  EXPECT_TRUE(same_bits(p.clearcoat_sampling_rate, q.clearcoat_sampling_rate));
  EXPECT_TRUE(same_bits(p.diffuse_reflectance_sampling_rate, q.diffuse_reflectance_sampling_rate));
  expect_same(x.blend_weight, y.blend_weight);
  expect_same(x.hair.sigma_a, y.hair.sigma_a);
  EXPECT_TRUE(same_bits(x.hair.longitudinal_roughness, y.hair.longitudinal_roughness));
  EXPECT_TRUE(same_bits(x.hair.azimuthal_roughness, y.hair.azimuthal_roughness));
  EXPECT_TRUE(same_bits(x.hair.scale_tilt_deg, y.hair.scale_tilt_deg));
  ASSERT_EQ(x.blend.size(), y.blend.size());
  for (size_t i = 0; i < x.blend.size(); ++i) {
    Material a = x.blend[i], b = y.blend[i];
    a.name = b.name = "";  // nested materials have no names of their own in JSON
    expect_same_material(a, b);
  }
}

void expect_same_shape(const Shape& x, const Shape& y) {
  SCOPED_TRACE(x.origin);
  ASSERT_EQ(x.kind, y.kind);
  if (x.kind == Shape::Kind::instance) {
    EXPECT_EQ(x.group, y.group);
    EXPECT_TRUE(same_bits(x.to_world, y.to_world));
    return;
  }
  EXPECT_EQ(x.material, y.material);
  EXPECT_TRUE(same_bits(x.emission, y.emission));
  EXPECT_EQ(x.emission_texture, y.emission_texture);
  EXPECT_EQ(x.two_sided_emission, y.two_sided_emission);
  if (x.kind == Shape::Kind::curves) {
    EXPECT_EQ(x.curve_basis, y.curve_basis);
    EXPECT_EQ(x.curve_sizes, y.curve_sizes);
    ASSERT_EQ(x.control_points.size(), y.control_points.size());
    for (size_t k = 0; k < x.control_points.size(); ++k) {
      for (int c = 0; c < 4; ++c) {
        ASSERT_TRUE(same_bits(x.control_points[k][c], y.control_points[k][c])) << "point " << k;
      }
    }
    return;
  }
  if (x.kind == Shape::Kind::sphere) {
    EXPECT_TRUE(same_bits(x.center, y.center));
    EXPECT_TRUE(same_bits(x.radius, y.radius));
    EXPECT_TRUE(same_bits(x.frame, y.frame));
    EXPECT_EQ(x.flip_normals, y.flip_normals);
    return;
  }
  ASSERT_EQ(x.positions.size(), y.positions.size());
  for (size_t k = 0; k < x.positions.size(); ++k) {
    ASSERT_TRUE(same_bits(x.positions[k], y.positions[k])) << "vertex " << k;
  }
  ASSERT_EQ(x.normals.size(), y.normals.size());
  for (size_t k = 0; k < x.normals.size(); ++k) {
    ASSERT_TRUE(same_bits(x.normals[k], y.normals[k])) << "normal " << k;
  }
  ASSERT_EQ(x.uvs.size(), y.uvs.size());
  for (size_t k = 0; k < x.uvs.size(); ++k) {
    ASSERT_TRUE(same_bits(x.uvs[k].x, y.uvs[k].x) && same_bits(x.uvs[k].y, y.uvs[k].y))
        << "uv " << k;
  }
  EXPECT_EQ(x.indices, y.indices);
}

/// Every field the renderer reads, compared bit for bit. Not compared: Shape::origin,
/// dropped_triangles and referenced_files (the JSON keeps no such thing) and flip_normals of
/// triangle shapes (applied to their winding).
void expect_same_scene(const Scene& a, const Scene& b) {
  EXPECT_TRUE(same_bits(a.camera.position, b.camera.position));
  EXPECT_TRUE(same_bits(a.camera.look_at, b.camera.look_at));
  EXPECT_TRUE(same_bits(a.camera.up, b.camera.up));
  EXPECT_TRUE(same_bits(a.camera.fov_deg, b.camera.fov_deg));
  EXPECT_EQ(a.camera.fov_axis, b.camera.fov_axis);
  EXPECT_TRUE(same_bits(a.camera.aperture_radius, b.camera.aperture_radius));
  EXPECT_TRUE(same_bits(a.camera.focus_distance, b.camera.focus_distance));
  EXPECT_EQ(a.camera.projection, b.camera.projection);
  if (a.camera.projection == Projection::orthographic) {
    EXPECT_TRUE(same_bits(a.camera.view_size.x, b.camera.view_size.x));
    EXPECT_TRUE(same_bits(a.camera.view_size.y, b.camera.view_size.y));
    EXPECT_TRUE(same_bits(a.camera.view_aspect, b.camera.view_aspect));
  }
  EXPECT_EQ(a.film.width, b.film.width);
  EXPECT_EQ(a.film.height, b.film.height);
  EXPECT_EQ(a.render.spp, b.render.spp);
  EXPECT_EQ(a.render.max_depth, b.render.max_depth);
  EXPECT_EQ(a.render.rr_depth, b.render.rr_depth);
  EXPECT_EQ(a.render.seed, b.render.seed);
  EXPECT_EQ(a.film.filter.kind, b.film.filter.kind);
  EXPECT_TRUE(same_bits(a.film.filter.radius, b.film.filter.radius));
  EXPECT_TRUE(same_bits(a.film.filter.stddev, b.film.filter.stddev));
  EXPECT_TRUE(same_bits(a.film.filter.b, b.film.filter.b));
  EXPECT_TRUE(same_bits(a.film.filter.c, b.film.filter.c));
  EXPECT_EQ(a.render.hide_emitters, b.render.hide_emitters);
  ASSERT_EQ(a.textures.size(), b.textures.size());
  for (size_t i = 0; i < a.textures.size(); ++i) {
    const Texture &x = a.textures[i], &y = b.textures[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.file, y.file);
    EXPECT_EQ(x.color_space, y.color_space);
    EXPECT_EQ(x.filter, y.filter);
    EXPECT_EQ(x.wrap, y.wrap);
    EXPECT_TRUE(same_bits(x.color0, y.color0));
    EXPECT_TRUE(same_bits(x.color1, y.color1));
    EXPECT_TRUE(same_bits(x.to_uv, y.to_uv)) << x.name;
    if (x.kind == TextureKind::rawconstant) {
      EXPECT_TRUE(same_bits(x.value, y.value)) << x.name;
      EXPECT_EQ(x.channels, y.channels) << x.name;
    }
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    expect_same_material(a.materials[i], b.materials[i]);
  }
  ASSERT_EQ(a.groups.size(), b.groups.size());
  for (size_t g = 0; g < a.groups.size(); ++g) {
    EXPECT_EQ(a.groups[g].name, b.groups[g].name);
    ASSERT_EQ(a.groups[g].shapes.size(), b.groups[g].shapes.size());
    for (size_t i = 0; i < a.groups[g].shapes.size(); ++i) {
      expect_same_shape(a.groups[g].shapes[i], b.groups[g].shapes[i]);
    }
  }
  ASSERT_EQ(a.shapes.size(), b.shapes.size());
  for (size_t i = 0; i < a.shapes.size(); ++i) expect_same_shape(a.shapes[i], b.shapes[i]);
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    const Light &x = a.lights[i], &y = b.lights[i];
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_TRUE(same_bits(x.to_world, y.to_world)) << i;
    EXPECT_TRUE(same_bits(x.value, y.value));
    EXPECT_TRUE(same_bits(x.cutoff_angle_deg, y.cutoff_angle_deg));
    EXPECT_TRUE(same_bits(x.beam_width_deg, y.beam_width_deg));
    EXPECT_EQ(x.file, y.file);
    EXPECT_EQ(x.texture, y.texture);
    EXPECT_TRUE(same_bits(x.fov_x_deg, y.fov_x_deg));
    EXPECT_TRUE(same_bits(x.aspect, y.aspect));
  }
}

Scene round_trip(const Scene& scene) {
  return parse_scene(write_scene_json(scene), memory_reader({}));
}

TEST(SceneWriter, MitsubaReferenceSceneRoundTripsExactly) {
  Scene s = load_scene_file(kSourceDir + "/tests/data/reference/cbox/mitsuba.xml");
  expect_same_scene(s, round_trip(s));
}

TEST(SceneWriter, MitsubaMeshesWithNormalsRoundTripExactly) {
  // The bunny gets Mitsuba's computed normals, the McGuire spheres the file's: both stored in
  // the form the parser's renormalisation leaves alone.
  FileReader scenes = folder_reader(kSourceDir + "/scenes");
  Scene s = parse_mitsuba_scene(testing::mitsuba_scene(R"(
      <shape type="ply"><string name="filename" value="meshes/bunny_lowres.ply"/>
        <transform name="to_world"><scale value="7"/><rotate y="1" angle="30"/></transform></shape>
      <shape type="obj"><string name="filename" value="mcguire-cornell/CornellBox-Sphere.obj"/>
        <bsdf type="twosided"><bsdf type="diffuse"/></bsdf></shape>)"),
                                "meshes.xml", scenes);
  ASSERT_FALSE(s.shapes.at(0).normals.empty());
  ASSERT_FALSE(s.shapes.at(1).normals.empty());
  expect_same_scene(s, round_trip(s));
}

TEST(SceneWriter, NativeScenesWithoutNormalsRoundTripExactly) {
  for (const char* file : {"cornell.json", "hexroom.json"}) {
    SCOPED_TRACE(file);
    Scene s = load_scene_file(kSourceDir + "/scenes/" + file);
    expect_same_scene(s, round_trip(s));
  }
}

TEST(SceneWriter, NativeScenesWithFileNormalsComeBackWithinAnUlp) {
  // The parser renormalises normals it reads: a normal normalisation moves comes back moved.
  Scene s = load_scene_file(kSourceDir + "/scenes/cornell-sphere.json");
  Scene back = round_trip(s);
  ASSERT_EQ(back.shapes.size(), s.shapes.size());
  for (size_t i = 0; i < s.shapes.size(); ++i) {
    ASSERT_EQ(back.shapes[i].normals.size(), s.shapes[i].normals.size());
    for (size_t k = 0; k < s.shapes[i].normals.size(); ++k) {
      EXPECT_LE(glm::length(back.shapes[i].normals[k] - s.shapes[i].normals[k]), 1e-15);
    }
    EXPECT_EQ(back.shapes[i].positions, s.shapes[i].positions);
  }
}

/// A scene with the awkward numbers and every kind of field.
Scene awkward_scene() {
  Scene s;
  s.camera.position = {-0.0, 1e-300, 5e-324};
  s.camera.look_at = {0.1, 1e150, -2.5};
  s.camera.up = {0.30000000000000004, 1, 0};
  s.camera.fov_deg = 179.99999999999997;
  s.camera.fov_axis = FovAxis::larger;
  s.camera.aperture_radius = 0.05;
  s.camera.focus_distance = 123456789012345678.0;
  s.film.width = 3;
  s.film.height = 32768;
  s.render = {1234567, 12, std::numeric_limits<uint64_t>::max()};
  Material d, m, g;
  d.name = "dif \"quoted\" \\ name\x01";
  d.reflectance.value = {0, 1, 0.1};
  d.two_sided = true;
  m.name = "mirror";
  m.type = MaterialType::mirror;
  g.name = "glass";
  g.type = MaterialType::glass;
  g.ior = 1.0 / 3.0;
  s.materials = {d, m, g};
  Shape tri;
  tri.positions = {{0, 0, 0}, {1e-7, 0, 0}, {0, 123456.789, 0}, {-1, -1, -1}};
  tri.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  tri.indices = {{0, 1, 2}};
  tri.material = 0;
  tri.emission = {1e30, 0, 2.5};
  tri.two_sided_emission = true;
  Shape sphere;
  sphere.kind = Shape::Kind::sphere;
  sphere.center = {1.1, -2.2, 3.3};
  sphere.radius = 0.1;
  sphere.flip_normals = true;
  sphere.material = 2;
  Shape plain;
  plain.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  plain.indices = {{0, 1, 2}};
  plain.material = 1;
  s.shapes = {tri, sphere, plain};
  return s;
}

TEST(SceneWriter, AwkwardNumbersRoundTripExactly) {
  Scene s = awkward_scene();
  Scene back = round_trip(s);
  expect_same_scene(s, back);
  EXPECT_TRUE(std::signbit(back.camera.position.x));  // -0 stays -0
}

TEST(SceneWriter, WritingIsAFixedPoint) {
  Scene s = awkward_scene();
  std::string once = write_scene_json(s);
  EXPECT_EQ(write_scene_json(round_trip(s)), once);
}

TEST(SceneWriter, CommentAndLayout) {
  std::string json = write_scene_json(awkward_scene(), "from a.xml\nsecond line");
  EXPECT_EQ(json.substr(0, json.find('\n')), "// from a.xml\\x0asecond line");
  EXPECT_NE(json.find("\"fov_axis\": \"larger\""), std::string::npos);
  EXPECT_NE(json.find("\"seed\": 18446744073709551615"), std::string::npos);
  EXPECT_NE(json.find("\"position\": [-0.0, 1e-300, 5e-324]"), std::string::npos);
  EXPECT_NE(json.find("\"dif \\\"quoted\\\" \\\\ name\\u0001\""), std::string::npos);
}

TEST(SceneWriter, NamesAreMadeValidAndUnique) {
  Scene s = awkward_scene();
  s.materials[1].name = s.materials[0].name;
  s.materials[2].name = "";
  Scene back = round_trip(s);
  EXPECT_EQ(back.materials[1].name, s.materials[0].name + " #2");
  EXPECT_EQ(back.materials[2].name, "material");
  s.materials[2].name = "bad \xff byte";
  EXPECT_EQ(round_trip(s).materials[2].name, "bad ? byte");
}

TEST(SceneWriter, RefusesWhatJsonCannotSay) {
  Scene s = awkward_scene();
  s.materials[0].two_sided = false;  // shape 0 emits from both sides
  EXPECT_THROW(write_scene_json(s), SceneError);
  s = awkward_scene();
  s.shapes[1].radius = std::numeric_limits<double>::quiet_NaN();
  try {
    write_scene_json(s);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("shapes[1] (): nan cannot be written in JSON"),
              std::string::npos);
  }
  s = awkward_scene();
  s.shapes[2].material = 7;
  EXPECT_THROW(write_scene_json(s), SceneError);
}

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
