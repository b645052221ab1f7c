#include "render/bsdf/diffuse.h"

#include "render/sampling/warp.h"

namespace tessera {

glm::vec3 DiffuseBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  return albedo_ * (kInvPi * wi.z);
}

float DiffuseBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  return cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> DiffuseBsdf::sample(glm::vec3 wo, float, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  BsdfSample s;
  s.wi = square_to_cosine_hemisphere(u);
  s.pdf = cosine_hemisphere_pdf(s.wi.z);
  if (!(s.pdf > 0.0f)) return std::nullopt;
  s.weight = albedo_;  // (albedo / pi) cos / (cos / pi)
  return s;
}

}  // namespace tessera
