#include "render/bsdf/bsdf.h"

#include <algorithm>
#include <cmath>

namespace tessera {
namespace {

using Impl = std::variant<DiffuseBsdf, ConductorBsdf, RoughConductorBsdf, DielectricBsdf,
                          RoughDielectricBsdf, ThinDielectricBsdf, PlasticBsdf, RoughPlasticBsdf,
                          PrincipledBsdf, BlendBsdf, PrincipledThinBsdf, PPlasticBsdf,
                          PolarizerBsdf, HairBsdf>;

Impl make_impl(const BsdfParams& p) {
  switch (p.type) {
    case MaterialType::diffuse: return DiffuseBsdf(p);
    case MaterialType::mirror:
    case MaterialType::conductor: return ConductorBsdf(p);
    case MaterialType::rough_conductor: return RoughConductorBsdf(p);
    case MaterialType::glass: return DielectricBsdf(p);
    case MaterialType::rough_glass: return RoughDielectricBsdf(p);
    case MaterialType::thin_glass: return ThinDielectricBsdf(p);
    case MaterialType::plastic: return PlasticBsdf(p);
    case MaterialType::rough_plastic: return RoughPlasticBsdf(p);
    case MaterialType::principled: return PrincipledBsdf(p);
    case MaterialType::blend: return BlendBsdf(p);
    case MaterialType::principled_thin: return PrincipledThinBsdf(p);
    case MaterialType::pplastic: return PPlasticBsdf(p);
    case MaterialType::polarizer: return PolarizerBsdf(p);
    case MaterialType::hair: return HairBsdf(p);
  }
  return DiffuseBsdf(p);  // unreachable: every MaterialType is handled above
}

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

Bsdf::Bsdf(const BsdfParams& p) : impl_(make_impl(p)) {}

// The guards below make the no-NaN contract hold at the interface even if an extreme input
// slips past a BSDF's own checks; the tests (bsdf_test.cpp) also check the BSDFs directly.
glm::vec3 Bsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  const glm::vec3 f = std::visit([&](const auto& b) { return b.eval(wo, wi); }, impl_);
  return finite(f) ? f : glm::vec3(0.0f);
}

float Bsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  const float p = std::visit([&](const auto& b) { return b.pdf(wo, wi); }, impl_);
  return std::isfinite(p) ? p : 0.0f;
}

std::optional<BsdfSample> Bsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  return checked_sample(std::visit([&](const auto& b) { return b.sample(wo, u_lobe, u); }, impl_));
}

float Bsdf::caustic_guide_share(glm::vec3 wo) const {
  if (std::holds_alternative<DiffuseBsdf>(impl_)) return 1.0f;
  if (const auto* p = std::get_if<PlasticBsdf>(&impl_)) return p->diffuse_probability(wo);
  if (const auto* p = std::get_if<RoughPlasticBsdf>(&impl_)) return p->diffuse_probability(wo);
  if (const auto* p = std::get_if<PrincipledBsdf>(&impl_)) return p->diffuse_probability(wo);
  if (const auto* p = std::get_if<RoughConductorBsdf>(&impl_)) return std::min(1.0f, 2.0f * p->mean_alpha());
  return 0.0f;
}

bool Bsdf::has_smooth_lobe() const {
  return std::visit([](const auto& b) { return b.has_smooth_lobe(); }, impl_);
}

}  // namespace tessera
