#include "render/bsdf/conductor.h"

#include "render/bsdf/fresnel.h"

namespace tessera {

ConductorBsdf::ConductorBsdf(const BsdfParams& p)
    : specular_reflectance_(p.specular_reflectance),
      eta_(p.conductor_eta),
      k_(p.conductor_k),
      perfect_(p.perfect || p.type == MaterialType::mirror) {}

std::optional<BsdfSample> ConductorBsdf::sample(glm::vec3 wo, float, glm::vec2) const {
  if (wo.z <= 0.0f) return std::nullopt;
  BsdfSample s;
  s.wi = reflect_z(wo);
  s.pdf = 1.0f;
  s.delta = true;
  s.weight = specular_reflectance_;
  if (!perfect_) s.weight *= fresnel_conductor(wo.z, eta_, k_);
  return s;
}

}  // namespace tessera
