#include "render/light/light_set.h"

#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tessera {
namespace {

/// Each light's power (luminance-weighted watts), as the picker weighs it.
template <class Lights>
std::vector<double> powers_of(const Lights& lights, double scene_radius) {
  std::vector<double> powers;
  powers.reserve(lights.size());
  for (const auto& light : lights) {
    powers.push_back(std::visit(
        [&](const auto& l) -> double {
          using T = std::decay_t<decltype(l)>;
          if constexpr (std::is_same_v<T, DirectionalLight> || std::is_same_v<T, ConstantLight> ||
                        std::is_same_v<T, EnvmapLight>) {
            return l.power(scene_radius);
          } else {
            return l.power();
          }
        },
        light));
  }
  return powers;
}

/// Each light's bounds for picking by importance at a point. Lights at infinity weigh their
/// power through the scene's disc divided by r^2 (4 pi^2 L for a constant one: 4 pi times the
/// irradiance bound pi L, as phi / d^2 = 4 pi I / d^2 of a point light is 4 pi times its
/// irradiance); spot lights weigh as the point light of their intensity, within their cone
/// only (SpotLight::bounds): weighed by their power instead, a narrow spot's 2 pi (1 - cos) I
/// made a dim environment outweigh it where it shines. Projector lights likewise, within the
/// cone through their image's corners (ProjectorLight::bounds).
template <class Lights>
std::vector<LightBounds> bounds_of(const Lights& lights, const std::vector<Light>& descriptions,
                                   uint32_t area_count, double scene_radius) {
  std::vector<LightBounds> bounds;
  bounds.reserve(lights.size());
  for (size_t i = 0; i < lights.size(); ++i) {
    bounds.push_back(std::visit(
        [&](const auto& l) -> LightBounds {
          using T = std::decay_t<decltype(l)>;
          LightBounds b;
          if constexpr (std::is_same_v<T, AreaLight> || std::is_same_v<T, SpotLight> ||
                        std::is_same_v<T, ProjectorLight>) {
            b = l.bounds();
          } else if constexpr (std::is_same_v<T, DirectionalLight> ||
                               std::is_same_v<T, ConstantLight> ||
                               std::is_same_v<T, EnvmapLight>) {
            b.infinite = true;
            const double r2 = scene_radius * scene_radius;
            b.phi = r2 > 0 ? l.power(scene_radius) / r2 : l.power(scene_radius);
          } else {
            b.center = glm::vec3(glm::dvec3(descriptions[i - area_count].to_world[3]));
            b.phi = l.power();
          }
          return b;
        },
        lights[i]));
  }
  return bounds;
}

}  // namespace

LightSet::LightSet(const std::vector<const Geometry*>& area_emitters,
                   const std::vector<Light>& lights, const FileReader& reader,
                   const TextureLookup& textures, float scene_radius)
    : picker_({}, std::vector<double>{}) {
  lights_.reserve(area_emitters.size() + lights.size());
  for (const Geometry* g : area_emitters) {
    // emitted() and pdf_area() find a geometry's light by Geometry::emitter.
    if (g->emitter != int32_t(lights_.size())) {
      throw std::invalid_argument("LightSet: area emitter " + std::to_string(lights_.size()) +
                                  " has Geometry::emitter " + std::to_string(g->emitter));
    }
    lights_.emplace_back(AreaLight(*g, textures));
  }
  area_count_ = uint32_t(area_emitters.size());
  for (const Light& light : lights) {
    switch (light.kind) {
      case LightKind::point:
        lights_.emplace_back(PointLight(light));
        break;
      case LightKind::spot:
        lights_.emplace_back(SpotLight(light, textures));
        break;
      case LightKind::directional:
        lights_.emplace_back(DirectionalLight(light));
        break;
      case LightKind::constant:
        environment_.push_back(uint32_t(lights_.size()));
        lights_.emplace_back(ConstantLight(light));
        break;
      case LightKind::envmap:
        environment_.push_back(uint32_t(lights_.size()));
        lights_.emplace_back(EnvmapLight::from_file(light, reader));
        break;
      case LightKind::projector:
        lights_.emplace_back(ProjectorLight(light, textures));
        break;
    }
  }
  picker_ = LightPicker(bounds_of(lights_, lights, area_count_, double(scene_radius)),
                        powers_of(lights_, double(scene_radius)));
}

LightSample LightSet::sample_other(uint32_t index, float pick_pmf, float pick_sum,
                                   const SurfacePoint& ref, glm::vec2 u) const {
  LightSample s = std::visit(
      [&](const auto& l) -> LightSample {
        using T = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<T, AreaLight>) {
          return l.sample(ref.p, u);  // not reached: sample() handles area lights
        } else if constexpr (std::is_same_v<T, PointLight> || std::is_same_v<T, SpotLight> ||
                             std::is_same_v<T, ProjectorLight>) {
          return l.sample(ref.p);
        } else if constexpr (std::is_same_v<T, DirectionalLight>) {
          return l.sample();
        } else {
          LightSample e;
          float pdf = 0;
          const glm::vec3 wi = l.sample(u, &pdf);
          if (!(pdf > 0)) return e;
          e.wi = wi;
          e.distance = std::numeric_limits<float>::infinity();
          e.radiance = environment(wi);
          e.pdf = pdf_environment(ref, wi, pick_sum);  // combined, pick probabilities included
          return e;
        }
      },
      lights_[index]);
  const bool environment_light = std::holds_alternative<ConstantLight>(lights_[index]) ||
                                 std::holds_alternative<EnvmapLight>(lights_[index]);
  if (!environment_light) s.pdf *= pick_pmf;
  if (!(s.pdf > 0)) return {};
  s.pick_sum = pick_sum;
  return s;
}

glm::vec3 LightSet::emitted(const Geometry& g, uint32_t /*primitive*/, glm::vec2 uv, glm::vec3 ng,
                            glm::vec3 w) const {
  if (g.emitter < 0 || uint32_t(g.emitter) >= area_count_) return glm::vec3(0.0f);
  return std::get<AreaLight>(lights_[size_t(g.emitter)]).emitted(uv, ng, w);
}

float LightSet::pdf_area(const Geometry& g, uint32_t /*primitive*/, const SurfacePoint& ref,
                         glm::vec3 hit_p, glm::vec3 hit_ng, float pick_sum) const {
  // Area, cone and spherical-rectangle sampling: the density does not depend on the primitive
  // (solid-angle sampling of single triangles would need it).
  if (g.emitter < 0 || uint32_t(g.emitter) >= area_count_) return 0.0f;
  const uint32_t i = uint32_t(g.emitter);
  return picker_.pmf(i, ref, pick_sum) * std::get<AreaLight>(lights_[i]).pdf(ref.p, hit_p, hit_ng);
}

glm::vec3 LightSet::environment(glm::vec3 d) const {
  glm::vec3 sum(0.0f);
  for (uint32_t i : environment_) {
    if (const auto* c = std::get_if<ConstantLight>(&lights_[i])) {
      sum += c->radiance();
    } else {
      sum += std::get<EnvmapLight>(lights_[i]).radiance(d);
    }
  }
  return sum;
}

float LightSet::environment_pdf(uint32_t i, glm::vec3 d) const {
  if (const auto* c = std::get_if<ConstantLight>(&lights_[i])) return c->pdf();
  return std::get<EnvmapLight>(lights_[i]).pdf(d);
}

float LightSet::pdf_environment(const SurfacePoint& ref, glm::vec3 d, float pick_sum) const {
  // With several environment lights, the sum once for all of them.
  if (pick_sum < 0 && environment_.size() > 1) pick_sum = picker_.importance_sum(ref);
  float pdf = 0;
  for (uint32_t i : environment_) pdf += picker_.pmf(i, ref, pick_sum) * environment_pdf(i, d);
  return pdf;
}

}  // namespace tessera
