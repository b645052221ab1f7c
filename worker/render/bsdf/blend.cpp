#include "render/bsdf/blend.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/bsdf/bsdf.h"

namespace tessera {

BlendBsdf::BlendBsdf(const BsdfParams& p) : weight_(std::clamp(p.blend_weight, 0.0f, 1.0f)) {
  if (p.blend.size() != 2) {
    throw std::invalid_argument("blend BSDF: BsdfParams::blend must hold two BSDFs");
  }
  if (!(weight_ >= 0.0f)) weight_ = 0.0f;  // NaN from a texture: the first BSDF
  first_ = std::make_unique<Bsdf>(p.blend[0]);
  second_ = std::make_unique<Bsdf>(p.blend[1]);
}

BlendBsdf::~BlendBsdf() = default;
BlendBsdf::BlendBsdf(BlendBsdf&&) noexcept = default;
BlendBsdf& BlendBsdf::operator=(BlendBsdf&&) noexcept = default;

glm::vec3 BlendBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  return first_->eval(wo, wi) * (1.0f - weight_) + second_->eval(wo, wi) * weight_;
}

float BlendBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  return first_->pdf(wo, wi) * (1.0f - weight_) + second_->pdf(wo, wi) * weight_;
}

std::optional<BsdfSample> BlendBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  const bool second = u_lobe <= weight_ && weight_ > 0.0f;
  const Bsdf& chosen = second ? *second_ : *first_;
  const Bsdf& other = second ? *first_ : *second_;
  const float p_chosen = second ? weight_ : 1.0f - weight_;
  // Mitsuba's rescaling of u_lobe for the chosen BSDF, kept in [0, 1).
  const float u_next = second ? u_lobe / weight_ : (u_lobe - weight_) / (1.0f - weight_);
  std::optional<BsdfSample> s =
      chosen.sample(wo, std::clamp(u_next, 0.0f, std::nextafter(1.0f, 0.0f)), u);
  if (!s) return std::nullopt;
  // Mitsuba's weighting, for smooth and perfectly specular samples alike (a delta sample's pdf
  // is the probability of its lobe, which this adds to the other BSDF's density there).
  const glm::vec3 f_chosen = s->weight * s->pdf;
  const float pdf = p_chosen * s->pdf + (1.0f - p_chosen) * other.pdf(wo, s->wi);
  if (!(pdf > 0.0f)) return std::nullopt;
  s->weight = (p_chosen * f_chosen + (1.0f - p_chosen) * other.eval(wo, s->wi)) / pdf;
  s->pdf = pdf;
  return s;
}

bool BlendBsdf::has_smooth_lobe() const {
  return first_->has_smooth_lobe() || second_->has_smooth_lobe();
}

}  // namespace tessera
