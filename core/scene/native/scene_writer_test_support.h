// Helpers shared by the native writer's tests (native/scene_writer*_test.cpp and the round trips
// of whole scene files in loader/scene_files_test.cpp): two scenes compared field by field, bit
// for bit, and a scene written and read back.
#pragma once

#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "scene/native/native_test_support.h"
#include "scene/native/scene_parser.h"
#include "scene/native/scene_writer.h"
#include "scene/scene.h"

namespace tessera::testing {

inline bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

inline ::testing::AssertionResult same_bits(const glm::dvec3& a, const glm::dvec3& b) {
  for (int i = 0; i < 3; ++i) {
    if (!same_bits(a[i], b[i])) {
      return ::testing::AssertionFailure()
             << "component " << i << ": " << format_number(a[i]) << " vs " << format_number(b[i]);
    }
  }
  return ::testing::AssertionSuccess();
}

inline bool same_bits(const glm::dmat3& a, const glm::dmat3& b) {
  for (int c = 0; c < 3; ++c) {
    if (!same_bits(a[c], b[c])) return false;
  }
  return true;
}

inline bool same_bits(const glm::dmat4& a, const glm::dmat4& b) {
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      if (!same_bits(a[c][r], b[c][r])) return false;
    }
  }
  return true;
}

inline void expect_same(const TexturedColor& a, const TexturedColor& b) {
  EXPECT_TRUE(same_bits(a.value, b.value));
  EXPECT_EQ(a.texture, b.texture);
}

inline void expect_same(const TexturedFloat& a, const TexturedFloat& b) {
  EXPECT_TRUE(same_bits(a.value, b.value));
  EXPECT_EQ(a.texture, b.texture);
}

inline void expect_same_material(const Material& x, const Material& y) {
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

inline void expect_same_shape(const Shape& x, const Shape& y) {
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
inline void expect_same_scene(const Scene& a, const Scene& b) {
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

inline Scene round_trip(const Scene& scene) {
  return parse_scene(write_scene_json(scene), memory_reader({}));
}

}  // namespace tessera::testing
