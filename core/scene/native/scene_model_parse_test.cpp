// The native format's textures, material kinds, lights, filters, groups and instances: what
// they read into, and how bad values are refused.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

using testing::error_of;
using testing::parse;
using testing::scene_with_shapes;

std::string with(const std::string& sections) { return R"({"tessera": 1, )" + sections + "}"; }

TEST(SceneModelParse, OrthographicCamera) {
  Scene s = parse(with(R"("camera": {"type": "orthographic", "position": [1, 2, 3],
      "look_at": [1, 2, 0], "view_size": [4, 0.5]})"));
  EXPECT_EQ(s.camera.projection, Projection::orthographic);
  EXPECT_EQ(s.camera.view_size, glm::dvec2(4, 0.5));
  EXPECT_EQ(s.camera.view_aspect, 0);  // a fixed view unless given
  EXPECT_EQ(parse(with(R"("camera": {"type": "orthographic", "view_size": [4, 0.5], "view_aspect": 8})"))
                .camera.view_aspect,
            8);
  EXPECT_EQ(error_of(with(R"("camera": {"type": "orthographic", "view_size": [1, 1], "view_aspect": 0})")),
            "camera.view_aspect: must be > 0 (got 0)");
  EXPECT_EQ(error_of(with(R"("camera": {"view_aspect": 1.5})")),
            "camera.view_aspect: only an orthographic camera has a view_aspect (set \"type\": "
            "\"orthographic\")");
  EXPECT_EQ(parse(with(R"("camera": {"type": "perspective"})")).camera.projection,
            Projection::perspective);
  EXPECT_EQ(error_of(with(R"("camera": {"type": "orthographic"})")),
            "camera.view_size: required");
  EXPECT_EQ(error_of(with(R"("camera": {"type": "orthographic", "view_size": [1, 0]})")),
            "camera.view_size[1]: must be > 0 (got 0)");
  EXPECT_EQ(error_of(with(R"("camera": {"type": "orthographic", "view_size": [1, 1],
      "fov": 30})")),
            "camera.fov: an orthographic camera has no lens (its image covers view_size)");
  EXPECT_EQ(error_of(with(R"("camera": {"view_size": [1, 1]})")),
            "camera.view_size: only an orthographic camera has a view_size (set \"type\": "
            "\"orthographic\")");
  EXPECT_EQ(error_of(with(R"("camera": {"type": "fisheye"})")),
            "camera.type: must be \"perspective\" or \"orthographic\" (got \"fisheye\")");
}

TEST(SceneModelParse, RawConstantTextures) {
  Scene s = parse(with(R"(
    "textures": {"one": {"type": "rawconstant", "value": -2.5},
                 "three": {"type": "rawconstant", "value": [0.5, 0.5, 1]}},
    "materials": {"a": {"reflectance": {"texture": "one"}}})"));
  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(s.textures[0].kind, TextureKind::rawconstant);
  EXPECT_EQ(s.textures[0].value, glm::dvec3(-2.5));
  EXPECT_EQ(s.textures[0].channels, 1);
  EXPECT_EQ(s.textures[1].value, glm::dvec3(0.5, 0.5, 1));
  EXPECT_EQ(s.textures[1].channels, 3);
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "rawconstant"}})")),
            "textures.t.value: required");
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "rawconstant", "value": [1, 2]}})")),
            "textures.t.value: must have 3 elements (got 2)");
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "rawconstant", "value": 1,
      "to_uv": [[1, 0, 0], [0, 1, 0]]}})")),
            "textures.t.to_uv: unknown key (a rawconstant has: type, value)");
}

TEST(SceneModelParse, TexturesAndTexturedParameters) {
  Scene s = parse(with(R"(
    "textures": {
      "albedo": {"type": "bitmap", "file": "tex\\albedo.png"},
      "hdr": {"type": "bitmap", "file": "tex/a.EXR", "filter": "nearest", "wrap": "clamp",
              "to_uv": [[2, 0, 0.5], [0, 3, 0]]},
      "checks": {"type": "checkerboard", "color0": [1, 1, 1]}},
    "materials": {
      "a": {"reflectance": {"texture": "albedo"}},
      "b": {"reflectance": {"texture": "checks", "scale": 0.5}, "opacity": {"texture": "hdr"}},
      "c": {"type": "rough_conductor", "alpha": {"texture": "hdr", "scale": 0.2}}})"));
  ASSERT_EQ(s.textures.size(), 3u);
  EXPECT_EQ(s.textures[0].file, "tex/albedo.png");
  EXPECT_EQ(s.textures[0].color_space, TextureColorSpace::srgb);
  EXPECT_EQ(s.textures[1].color_space, TextureColorSpace::linear);  // float images: linear
  EXPECT_EQ(s.textures[1].filter, TextureFilter::nearest);
  EXPECT_EQ(s.textures[1].wrap, TextureWrap::clamp);
  glm::dvec3 uv = s.textures[1].to_uv * glm::dvec3(1, 1, 1);
  EXPECT_EQ(uv, glm::dvec3(2.5, 3, 1));
  EXPECT_EQ(s.textures[2].kind, TextureKind::checkerboard);
  EXPECT_EQ(s.textures[2].color1, glm::dvec3(0.2));
  EXPECT_EQ(s.referenced_files, (std::vector<std::string>{"tex/albedo.png", "tex/a.EXR"}));
  EXPECT_EQ(s.materials[0].reflectance.texture, 0);
  EXPECT_EQ(s.materials[0].reflectance.value, glm::dvec3(1));
  EXPECT_EQ(s.materials[1].reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(s.materials[1].opacity.texture, 1);
  EXPECT_EQ(s.materials[2].alpha_u.texture, 1);
  EXPECT_EQ(s.materials[2].alpha_v.value, 0.2);

  EXPECT_EQ(error_of(with(R"("materials": {"a": {"reflectance": {"texture": "nope"}}})")),
            "materials.a.reflectance.texture: unknown texture \"nope\"");
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "bitmap", "file": "../t.png"}})"))
                .rfind("textures.t.file: ", 0),
            0u);
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "noise"}})")),
            "textures.t.type: unknown texture type \"noise\" (expected bitmap, checkerboard, "
            "rawconstant, mesh_attribute or volume)");
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "bitmap", "file": "a.png",
                                                 "wrap": "tile"}})")),
            "textures.t.wrap: must be \"repeat\", \"mirror\" or \"clamp\" (got \"tile\")");
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "checkerboard",
                                                 "to_uv": [[0, 0, 1], [0, 0, 1]]}})")),
            "textures.t.to_uv: must be invertible");
  // Checkerboard colours are unbounded above, like a bitmap's texels (an eta, a radiance), but
  // not negative.
  Scene bright = parse(with(R"("textures": {"t": {"type": "checkerboard",
                                                  "color0": [5.8, 1, 0], "color1": [1.5, 1.5, 1.5]}})"));
  EXPECT_EQ(bright.textures.at(0).color0, glm::dvec3(5.8, 1, 0));
  EXPECT_EQ(error_of(with(R"("textures": {"t": {"type": "checkerboard",
                                                 "color1": [0.5, -0.1, 0.5]}})")),
            "textures.t.color1[1]: must be >= 0 (got -0.1)");
}

TEST(SceneModelParse, MaterialKindsTakeMitsubasParameters) {
  Scene s = parse(with(R"("materials": {
      "gold": {"type": "conductor", "eta": [0.2, 0.4, 1.4], "k": [4, 2.4, 1.6]},
      "brushed": {"type": "rough_conductor", "distribution": "ggx", "alpha_u": 0.05,
                  "alpha_v": 0.3, "sample_visible": false, "perfect": true},
      "frosted": {"type": "rough_glass", "ior": 1.33, "alpha": 0.2},
      "window": {"type": "thin_glass", "specular_transmittance": [0.9, 0.9, 0.9]},
      "red": {"type": "plastic", "diffuse_reflectance": [0.5, 0, 0], "nonlinear": true},
      "satin": {"type": "rough_plastic", "alpha": 0.3, "ior": 1.6, "two_sided": true},
      "leaf": {"reflectance": [0, 0.5, 0], "back": "satin", "bump_map": "h", "bump_scale": 2,
               "normal_map": "h"}},
      "textures": {"h": {"type": "bitmap", "file": "h.png"}})"));
  ASSERT_EQ(s.materials.size(), 7u);
  EXPECT_EQ(s.materials[0].type, MaterialType::conductor);
  EXPECT_EQ(s.materials[0].k, glm::dvec3(4, 2.4, 1.6));
  EXPECT_EQ(s.materials[1].distribution, MicrofacetDistribution::ggx);
  EXPECT_EQ(s.materials[1].alpha_v.value, 0.3);
  EXPECT_FALSE(s.materials[1].sample_visible);
  EXPECT_TRUE(s.materials[1].perfect);
  EXPECT_EQ(s.materials[2].alpha_u.value, 0.2);
  EXPECT_EQ(s.materials[2].distribution, MicrofacetDistribution::beckmann);
  EXPECT_EQ(s.materials[3].specular_transmittance.value, glm::dvec3(0.9));
  EXPECT_EQ(s.materials[4].reflectance.value, glm::dvec3(0.5, 0, 0));
  EXPECT_TRUE(s.materials[4].nonlinear);
  EXPECT_EQ(s.materials[6].back, 5);
  EXPECT_EQ(s.materials[6].normal_map, 0);
  EXPECT_EQ(s.materials[6].bump_scale, 2);

  auto material_error = [](const std::string& m) {
    return error_of(with(R"("materials": {"m": )" + m + "}"));
  };
  EXPECT_EQ(material_error(R"({"type": "rough_conductor", "alpha": 0})"),
            "materials.m.alpha: must be > 0 (got 0)");
  EXPECT_EQ(material_error(R"({"type": "rough_glass", "alpha_u": 0.1})"),
            "materials.m: alpha_u and alpha_v go together");
  EXPECT_EQ(material_error(R"({"type": "rough_glass", "alpha": 0.1, "alpha_u": 0.1})"),
            "materials.m.alpha_u: give either alpha or alpha_u and alpha_v, not both");
  EXPECT_EQ(material_error(R"({"type": "rough_plastic", "alpha_u": 0.1})").rfind(
                "materials.m.alpha_u: unknown key", 0),
            0u);
  EXPECT_EQ(material_error(R"({"type": "conductor", "distribution": "ggx"})").rfind(
                "materials.m.distribution: unknown key", 0),
            0u);
  EXPECT_EQ(material_error(R"({"type": "rough_conductor", "distribution": "phong"})"),
            "materials.m.distribution: must be \"beckmann\" or \"ggx\" (got \"phong\")");
  EXPECT_EQ(material_error(R"({"type": "plastic", "reflectance": [1, 1, 1]})"),
            "materials.m.reflectance: plastics call it diffuse_reflectance");
  EXPECT_EQ(material_error(R"({"type": "thin_glass", "two_sided": true})"),
            "materials.m.two_sided: glass is always two-sided (remove this key)");
  EXPECT_EQ(material_error(R"({"opacity": 1.5})"),
            "materials.m.opacity: must be in [0, 1] (got 1.5)");
  EXPECT_EQ(material_error(R"({"type": "conductor", "eta": [1, -1, 1]})"),
            "materials.m.eta[1]: must be >= 0 (got -1)");
  EXPECT_EQ(material_error(R"({"back": "m"})"), "materials.m.back: must name another material");
  EXPECT_EQ(error_of(with(R"("materials": {"m": {"back": "n"}, "n": {}})")),
            "materials.m.back: material \"n\" must be two-sided (it is shaded with its own front)");
}

TEST(SceneModelParse, PrincipledTakesMitsubasParametersAndTextures) {
  Scene s = parse(with(R"("materials": {
      "car paint": {"type": "principled", "base_color": [0.2, 0.8, 0.1], "roughness": 0.15,
                    "anisotropic": {"texture": "h", "scale": 0.5}, "metallic": 0.3,
                    "spec_tint": 0.5, "sheen": 0.6, "sheen_tint": 0.7, "flatness": 0.8,
                    "clearcoat": 0.9, "clearcoat_gloss": 0.25, "ior": 1.33,
                    "main_specular_sampling_rate": 2, "clearcoat_sampling_rate": 0.5,
                    "diffuse_reflectance_sampling_rate": 0, "two_sided": true},
      "default": {"type": "principled"},
      "glassy": {"type": "principled", "spec_trans": 1}},
      "textures": {"h": {"type": "bitmap", "file": "h.png"}})"));
  ASSERT_EQ(s.materials.size(), 3u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::principled);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.2, 0.8, 0.1));
  EXPECT_EQ(m.principled.roughness.value, 0.15);
  EXPECT_EQ(m.principled.anisotropic.texture, 0);
  EXPECT_EQ(m.principled.anisotropic.value, 0.5);
  EXPECT_EQ(m.principled.clearcoat_gloss.value, 0.25);
  EXPECT_EQ(m.principled.diffuse_reflectance_sampling_rate, 0.0);
  EXPECT_EQ(m.ior, 1.33);
  EXPECT_TRUE(m.two_sided);
  EXPECT_FALSE(m.principled.transmits());
  EXPECT_EQ(s.materials[1].principled.roughness.value, 0.5);  // Mitsuba's defaults
  EXPECT_EQ(s.materials[1].reflectance.value, glm::dvec3(0.5));
  EXPECT_EQ(s.materials[1].ior, 1.5);
  EXPECT_TRUE(s.materials[2].principled.transmits());

  auto material_error = [](const std::string& m) {
    return error_of(with(R"("materials": {"m": )" + m + "}"));
  };
  EXPECT_EQ(material_error(R"({"type": "principled", "metallic": 1.5})"),
            "materials.m.metallic: must be in [0, 1] (got 1.5)");
  EXPECT_EQ(material_error(R"({"type": "principled", "reflectance": [1, 1, 1]})"),
            "materials.m.reflectance: principled materials call it base_color");
  EXPECT_EQ(material_error(R"({"base_color": [1, 1, 1]})"),
            "materials.m.base_color: only principled materials have a base_color");
  EXPECT_EQ(material_error(R"({"type": "principled", "clearcoat_sampling_rate": -1})"),
            "materials.m.clearcoat_sampling_rate: must be a finite number >= 0 (got -1)");
  EXPECT_EQ(material_error(R"({"type": "principled", "spec_trans": 0.5, "two_sided": true})"),
            "materials.m.two_sided: a principled material with spec_trans transmits light and is "
            "two-sided by nature (remove this key, or set spec_trans to 0)");
  EXPECT_EQ(material_error(R"({"type": "principled", "specular_reflectance": [1, 1, 1]})").rfind(
                "materials.m.specular_reflectance: unknown key", 0),
            0u);
}

TEST(SceneModelParse, PrincipledThinAndPplasticTakeMitsubasParametersAndTextures) {
  Scene s = parse(with(R"("materials": {
      "leaf": {"type": "principled_thin", "base_color": [0.2, 0.8, 0.1], "roughness": 0.15,
               "anisotropic": 0.3, "spec_trans": {"texture": "h"}, "spec_tint": 0.5,
               "sheen": 0.6, "sheen_tint": 0.7, "flatness": 0.8, "diff_trans": 1.5,
               "ior": {"texture": "h", "scale": 1.4},
               "diffuse_reflectance_sampling_rate": 0.5, "specular_reflectance_sampling_rate": 2,
               "specular_transmittance_sampling_rate": 3, "diffuse_transmittance_sampling_rate": 4},
      "thin default": {"type": "principled_thin"},
      "pp": {"type": "pplastic", "diffuse_reflectance": [0.05, 0.03, 0.1], "ior": 1.33,
             "distribution": "ggx", "alpha_u": 0.06, "alpha_v": {"texture": "h"},
             "two_sided": true}},
      "textures": {"h": {"type": "bitmap", "file": "h.png"}})"));
  ASSERT_EQ(s.materials.size(), 3u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::principled_thin);
  EXPECT_EQ(m.reflectance.value, glm::dvec3(0.2, 0.8, 0.1));
  EXPECT_EQ(m.principled.roughness.value, 0.15);
  EXPECT_EQ(m.principled.spec_trans.texture, 0);
  EXPECT_EQ(m.principled.diff_trans.value, 1.5);
  EXPECT_EQ(m.ior, 1.4);
  EXPECT_EQ(m.ior_texture, 0);
  EXPECT_EQ(m.principled.specular_transmittance_sampling_rate, 3.0);
  EXPECT_EQ(m.principled.diffuse_transmittance_sampling_rate, 4.0);
  EXPECT_TRUE(m.transmits());
  EXPECT_EQ(s.materials[1].principled.roughness.value, 0.5);  // Mitsuba's defaults
  EXPECT_EQ(s.materials[1].ior, 1.5);
  EXPECT_EQ(s.materials[1].ior_texture, -1);
  const Material& pp = s.materials[2];
  EXPECT_EQ(pp.type, MaterialType::pplastic);
  EXPECT_EQ(pp.reflectance.value, glm::dvec3(0.05, 0.03, 0.1));
  EXPECT_EQ(pp.ior, 1.33);
  EXPECT_EQ(pp.distribution, MicrofacetDistribution::ggx);
  EXPECT_EQ(pp.alpha_u.value, 0.06);
  EXPECT_EQ(pp.alpha_v.texture, 0);
  EXPECT_TRUE(pp.two_sided);

  auto material_error = [](const std::string& m) {
    return error_of(with(R"("materials": {"m": )" + m + "}"));
  };
  EXPECT_EQ(material_error(R"({"type": "principled_thin", "diff_trans": 2.5})"),
            "materials.m.diff_trans: must be in [0, 2] (got 2.5)");
  EXPECT_EQ(material_error(R"({"type": "principled_thin", "two_sided": true})"),
            "materials.m.two_sided: a principled_thin material is two-sided by nature (remove "
            "this key)");
  EXPECT_EQ(material_error(R"({"type": "principled", "diff_trans": 1})"),
            "materials.m.diff_trans: only principled_thin materials have a diff_trans");
  EXPECT_EQ(material_error(R"({"type": "principled_thin", "metallic": 1})").rfind(
                "materials.m.metallic: unknown key", 0),
            0u);
  EXPECT_EQ(material_error(R"({"type": "pplastic", "reflectance": [1, 1, 1]})"),
            "materials.m.reflectance: plastics call it diffuse_reflectance");
  EXPECT_EQ(material_error(R"({"type": "pplastic", "ior": 0})"),
            "materials.m.ior: must be > 0 (got 0)");
  EXPECT_EQ(material_error(R"({"type": "pplastic", "nonlinear": true})").rfind(
                "materials.m.nonlinear: unknown key", 0),
            0u);
}

TEST(SceneModelParse, PolarizerTakesTransmittance) {
  Scene s = parse(with(R"("materials": {
      "p": {"type": "polarizer", "transmittance": {"texture": "h", "scale": [0.8, 0.5, 0.2]}},
      "plain": {"type": "polarizer"}},
      "textures": {"h": {"type": "bitmap", "file": "h.png"}})"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].type, MaterialType::polarizer);
  EXPECT_EQ(s.materials[0].specular_transmittance.texture, 0);
  EXPECT_EQ(s.materials[0].specular_transmittance.value, glm::dvec3(0.8, 0.5, 0.2));
  EXPECT_EQ(s.materials[1].specular_transmittance.value, glm::dvec3(1.0));  // Mitsuba's default
  EXPECT_TRUE(s.materials[1].transmits());

  auto material_error = [](const std::string& m) {
    return error_of(with(R"("materials": {"m": )" + m + "}"));
  };
  EXPECT_EQ(material_error(R"({"type": "polarizer", "two_sided": true})"),
            "materials.m.two_sided: a polarizer is two-sided by nature (remove this key)");
  EXPECT_EQ(material_error(R"({"type": "polarizer", "specular_transmittance": [1, 1, 1]})"),
            "materials.m.specular_transmittance: a polarizer calls it transmittance");
  EXPECT_EQ(material_error(R"({"type": "polarizer", "ior": 1.5})"),
            "materials.m.ior: only glass kinds, plastics, principled materials and hair have an ior");
  EXPECT_EQ(material_error(R"({"type": "polarizer", "transmittance": [1.5, 1, 1]})")
                .rfind("materials.m.transmittance", 0),
            0u);
}

TEST(SceneModelParse, BlendNestsTwoMaterials) {
  Scene s = parse(with(R"("materials": {
      "mix": {"type": "blend", "weight": {"texture": "h"}, "two_sided": true,
              "materials": [{"reflectance": [0.1, 0.2, 0.3]},
                            {"type": "blend", "weight": 0.25,
                             "materials": [{"type": "rough_conductor", "alpha": 0.2},
                                           {"type": "principled", "metallic": 1}]}]},
      "frosted mix": {"type": "blend", "weight": 0.5,
                      "materials": [{"type": "rough_glass"}, {}]}},
      "textures": {"h": {"type": "bitmap", "file": "h.png"}})"));
  ASSERT_EQ(s.materials.size(), 2u);
  const Material& m = s.materials[0];
  EXPECT_EQ(m.type, MaterialType::blend);
  EXPECT_EQ(m.blend_weight.texture, 0);
  ASSERT_EQ(m.blend.size(), 2u);
  EXPECT_EQ(m.blend[0].reflectance.value, glm::dvec3(0.1, 0.2, 0.3));
  ASSERT_EQ(m.blend[1].blend.size(), 2u);
  EXPECT_EQ(m.blend[1].blend_weight.value, 0.25);
  EXPECT_EQ(m.blend[1].blend[1].principled.metallic.value, 1.0);
  EXPECT_FALSE(m.transmits());
  EXPECT_TRUE(s.materials[1].transmits());

  auto material_error = [](const std::string& m) {
    return error_of(with(R"("materials": {"m": )" + m + "}"));
  };
  EXPECT_EQ(material_error(R"({"type": "blend", "materials": [{}, {}]})"),
            "materials.m: a blend needs a \"weight\" (number in [0, 1] or texture)");
  EXPECT_EQ(material_error(R"({"type": "blend", "weight": 2, "materials": [{}, {}]})"),
            "materials.m.weight: must be in [0, 1] (got 2)");
  EXPECT_NE(material_error(R"({"type": "blend", "weight": 0.5, "materials": [{}]})")
                .find("materials.m.materials"),
            std::string::npos);
  EXPECT_EQ(material_error(R"({"type": "blend", "weight": 0.5,
                              "materials": [{"two_sided": true}, {}]})"),
            "materials.m.materials[0].two_sided: a blend's nested material has no two_sided of its "
            "own (give it to the blend)");
  EXPECT_EQ(material_error(R"({"type": "blend", "weight": 0.5, "two_sided": true,
                              "materials": [{"type": "glass"}, {}]})"),
            "materials.m.two_sided: a blend of a material that transmits light is two-sided by "
            "nature (remove this key)");
  EXPECT_EQ(material_error(R"({"type": "blend", "weight": 0.5,
                              "materials": [{"type": "velvet"}, {}]})")
                .rfind("materials.m.materials[0].type: unknown material type", 0),
            0u);
}

TEST(SceneModelParse, LightsFilterAndHideEmitters) {
  Scene s = parse(with(R"(
    "film": {"width": 4, "height": 4, "filter": {"type": "gaussian", "stddev": 0.25}},
    "render": {"hide_emitters": true},
    "lights": [
      {"type": "point", "transform": {"translate": [0, 3, 0]}, "intensity": 5},
      {"type": "spot", "cutoff_angle": 40, "intensity": [1, 2, 3],
       "transform": {"rotate": {"axis": [1, 0, 0], "angle": 90}}},
      {"type": "directional", "irradiance": [2, 2, 2]},
      {"type": "constant", "radiance": 0.5},
      {"type": "envmap", "file": "sky.hdr", "scale": 2}])"));
  EXPECT_EQ(s.film.filter.kind, FilterKind::gaussian);
  EXPECT_EQ(s.film.filter.radius, 1.0);  // 4 standard deviations
  EXPECT_TRUE(s.render.hide_emitters);
  ASSERT_EQ(s.lights.size(), 5u);
  EXPECT_EQ(s.lights[0].to_world[3], glm::dvec4(0, 3, 0, 1));
  EXPECT_EQ(s.lights[0].value, glm::dvec3(5));
  EXPECT_EQ(s.lights[1].beam_width_deg, 30);  // 3/4 of the cutoff, as Mitsuba
  EXPECT_EQ(s.lights[3].value, glm::dvec3(0.5));
  EXPECT_EQ(s.lights[4].file, "sky.hdr");
  EXPECT_EQ(s.referenced_files, std::vector<std::string>{"sky.hdr"});
  EXPECT_EQ(parse(with(R"("film": {"filter": {"type": "tent"}})")).film.filter.radius, 1);
  EXPECT_EQ(parse(R"({"tessera": 1})").film.filter.kind, FilterKind::box);

  const PixelFilter mitchell = parse(with(R"("film": {"filter": {"type": "mitchell", "b": 0, "c": 0.5}})")).film.filter;
  EXPECT_EQ(mitchell.kind, FilterKind::mitchell);
  EXPECT_EQ(mitchell.radius, 2);
  EXPECT_EQ(mitchell.b, 0);
  EXPECT_EQ(mitchell.c, 0.5);
  EXPECT_EQ(parse(with(R"("film": {"filter": {"type": "mitchell"}})")).film.filter.b, 1.0 / 3);
  const PixelFilter lanczos = parse(with(R"("film": {"filter": {"type": "lanczos"}})")).film.filter;
  EXPECT_EQ(lanczos.kind, FilterKind::lanczos);
  EXPECT_EQ(lanczos.radius, 3);  // its lobes
  EXPECT_EQ(parse(with(R"("film": {"filter": {"type": "lanczos", "lobes": 2}})")).film.filter.radius, 2);
  EXPECT_EQ(error_of(with(R"("film": {"filter": {"type": "lanczos", "lobes": 0}})")).rfind("film.filter.lobes:", 0), 0u);
  EXPECT_EQ(error_of(with(R"("film": {"filter": {"type": "lanczos", "lobes": 2.5}})")).rfind("film.filter.lobes:", 0), 0u);
  EXPECT_EQ(error_of(with(R"("film": {"filter": {"type": "mitchell", "radius": 3}})")).rfind("film.filter", 0), 0u);
  EXPECT_EQ(error_of(with(R"("film": {"filter": {"type": "sinc"}})")),
            "film.filter.type: unknown filter \"sinc\" (expected box, tent, gaussian, mitchell or lanczos)");
  EXPECT_EQ(error_of(with(R"("film": {"filter": {"type": "tent", "radius": 0}})")),
            "film.filter.radius: must be > 0 (got 0)");
  EXPECT_EQ(error_of(with(R"("lights": [{"type": "point", "transform": {"scale": 2}}])")),
            "lights[0].transform: a light's transform must be a rotation and a translation (no "
            "scale or mirror)");
  EXPECT_EQ(error_of(with(R"("lights": [{"type": "spot", "cutoff_angle": 10,
                                         "beam_width": 20}])")),
            "lights[0].beam_width: must be in (0, 10] degrees (got 20)");
  EXPECT_EQ(error_of(with(R"("lights": [{"type": "constant", "transform": {}}])")).rfind(
                "lights[0].transform: unknown key", 0),
            0u);
  EXPECT_EQ(error_of(with(R"("lights": [{"type": "envmap", "file": "a.exr",
                                         "scale": [1, 2, 3]}])")),
            "lights[0].scale: must be a number");
  EXPECT_EQ(error_of(with(R"("lights": [{"type": "area"}])")),
            "lights[0].type: unknown light type \"area\" (expected point, spot, directional, "
            "constant, envmap or projector)");
}

TEST(SceneModelParse, UvsFramesGroupsInstancesAndTexturedEmission) {
  Scene s = parse(scene_with_shapes(R"(
      {"type": "triangles", "material": "white", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]],
       "indices": [[0, 1, 2]], "uvs": [[0, 0], [1, 0], [0, 1]]},
      {"type": "sphere", "material": "white", "frame": [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
       "transform": {"rotate": {"axis": [0, 0, 1], "angle": 90}, "scale": 2}},
      {"type": "instance", "group": "g", "transform": {"translate": [5, 0, 0]}},
      {"type": "quad", "vertices": [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]],
       "emission": {"texture": "t", "scale": [2, 2, 2]}})",
                                    R"("textures": {"t": {"type": "checkerboard"}},
      "groups": {"g": {"shapes": [{"type": "sphere", "material": "mirror"}]}}, )"));
  ASSERT_EQ(s.shapes.size(), 4u);
  EXPECT_EQ(s.shapes[0].uvs[1], glm::dvec2(1, 0));
  // The frame turned by the transform's rotation: a quarter turn after a quarter turn.
  glm::dvec3 x = s.shapes[1].frame * glm::dvec3(1, 0, 0);
  EXPECT_NEAR(x.x, -1, 1e-15);
  EXPECT_NEAR(x.y, 0, 1e-15);
  EXPECT_EQ(s.shapes[2].kind, Shape::Kind::instance);
  EXPECT_EQ(s.shapes[2].group, 0u);
  EXPECT_EQ(s.shapes[2].to_world[3], glm::dvec4(5, 0, 0, 1));
  ASSERT_EQ(s.groups.size(), 1u);
  EXPECT_EQ(s.groups[0].shapes.at(0).kind, Shape::Kind::sphere);
  EXPECT_EQ(s.shapes[3].emission_texture, 0);
  EXPECT_EQ(s.shapes[3].emission, glm::dvec3(2));

  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "triangles", "material": "white",
      "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "indices": [[0, 1, 2]], "uvs": [[0, 0]]})")),
            "shapes[0].uvs: must have 3 elements (got 1)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "material": "white",
      "frame": [[1, 0, 0], [0, 2, 0], [0, 0, 1]]})")),
            "shapes[0].frame: must be an orthogonal matrix (a rotation, row by row)");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "instance", "group": "h"})")),
            "shapes[0].group: unknown group \"h\"");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "instance", "group": "g", "material": "white"})",
                                       R"("groups": {"g": {"shapes": [{"type": "sphere",
                                           "material": "white"}]}}, )")),
            "shapes[0].material: unknown key (an \"instance\" shape has: type, group, transform)");
  EXPECT_EQ(error_of(scene_with_shapes("", R"("groups": {"g": {"shapes": [
      {"type": "sphere", "emission": [1, 1, 1]}]}}, )")),
            "groups.g.shapes[0]: shapes in a group cannot emit light");
  EXPECT_EQ(error_of(scene_with_shapes("", R"("groups": {"g": {"shapes": [
      {"type": "instance", "group": "g"}]}}, )")),
            "groups.g.shapes[0].type: groups cannot hold instances");
  EXPECT_EQ(error_of(scene_with_shapes(R"({"type": "sphere", "power": 3,
      "emission": {"texture": "t"}})", R"("textures": {"t": {"type": "checkerboard"}}, )")),
            "shapes[0].power: give either emission or power, not both");
}

}  // namespace
}  // namespace tessera
