#include "render/bsdf/rough_plastic.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "render/bsdf/fresnel.h"
#include "render/bsdf/plastic.h"
#include "render/sampling/warp.h"

namespace tessera {
namespace {

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton's iteration on P_n, in double).
void gauss_legendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
  nodes->resize(n);
  weights->resize(n);
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1;
    for (int iter = 0; iter < 100; ++iter) {
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    (*nodes)[i] = x;
    (*weights)[i] = 2.0 / ((1 - x * x) * dp * dp);
  }
}

/// The Gauss-Legendre rule of n points, worked out once per n (the integrals below ask for the
/// same two rules 128 times per table).
struct GaussLegendre {
  std::vector<double> nodes, weights;
  explicit GaussLegendre(int n) { gauss_legendre(n, &nodes, &weights); }
};
const GaussLegendre& gauss_legendre_rule(int n) {
  static const GaussLegendre rule32(32), rule128(128);
  if (n == 32) return rule32;
  if (n == 128) return rule128;
  throw std::invalid_argument("gauss_legendre_rule: " + std::to_string(n) + " points (32 or 128)");
}

/// Mitsuba's eval_transmittance (transmit = true) and eval_reflectance: the fraction of light
/// arriving along wi that a rough dielectric boundary of relative index eta transmits or
/// reflects, single scattering, with its Gauss-Legendre grid.
float rough_fresnel_integral(const Microfacet& distr, glm::vec3 wi, float eta, bool transmit) {
  const int res = eta > 1.0f ? 32 : 128;
  const GaussLegendre& rule = gauss_legendre_rule(res);
  const std::vector<double>& nodes = rule.nodes;
  const std::vector<double>& weights = rule.weights;
  float result = 0.0f;
  for (int y = 0; y < res; ++y) {
    for (int x = 0; x < res; ++x) {
      const glm::vec2 node(float(nodes[x]) * 0.5f + 0.5f, float(nodes[y]) * 0.5f + 0.5f);
      const float weight = float(weights[x]) * float(weights[y]);
      const glm::vec3 m = distr.sample(wi, node).first;
      const DielectricFresnel f = fresnel_dielectric_signed(glm::dot(wi, m), eta);
      float smith;
      if (transmit) {
        const glm::vec3 wo = refract_m(wi, m, f.cos_theta_t, f.eta_ti);
        smith = wo.z * wi.z >= 0.0f ? 0.0f : distr.smith_g1(wo, m) * (1.0f - f.r);
      } else {
        const glm::vec3 wo = reflect(wi, m);
        smith = wo.z <= 0.0f || wi.z <= 0.0f ? 0.0f : distr.smith_g1(wo, m) * f.r;
      }
      if (std::isfinite(smith)) result += smith * weight * 0.25f;
    }
  }
  return result;
}

}  // namespace

RoughPlasticTable make_rough_plastic_table(MicrofacetDistribution distribution, float alpha,
                                           float eta) {
  RoughPlasticTable t;
  t.distribution = distribution;
  t.alpha = alpha;
  t.eta = eta;
  const Microfacet distr(distribution, alpha, alpha, /*sample_visible=*/true);
  // The angles' integrals on the caller's TBB threads (about 0.3 s of CPU per table, most of a
  // small render's start: each is 32^2 or 128^2 microfacet samples), each into its own entry;
  // the internal reflectance then added up in angle order, so the same bits on any number of
  // threads.
  const auto mu_of = [](int i) {
    return std::max(1e-6f, float(i) / float(RoughPlasticTable::kResolution - 1));
  };
  std::array<float, RoughPlasticTable::kResolution> internal_at{};
  tbb::parallel_for(0, RoughPlasticTable::kResolution, [&](int i) {
    const float mu = mu_of(i);
    const glm::vec3 wi(std::sqrt(1.0f - mu * mu), 0.0f, mu);
    t.external_transmittance[i] = rough_fresnel_integral(distr, wi, eta, /*transmit=*/true);
    internal_at[i] = rough_fresnel_integral(distr, wi, 1.0f / eta, /*transmit=*/false);
  });
  double internal = 0;
  for (int i = 0; i < RoughPlasticTable::kResolution; ++i) internal += internal_at[i] * mu_of(i);
  t.internal_reflectance = float(2.0 * internal / RoughPlasticTable::kResolution);
  return t;
}

RoughPlasticBsdf::RoughPlasticBsdf(const BsdfParams& p)
    : distr_(p.distribution, p.alpha_u, p.alpha_u, p.sample_visible),
      diffuse_reflectance_(p.reflectance),
      specular_reflectance_(p.specular_reflectance),
      eta_(p.eta),
      inv_eta2_(1.0f / (p.eta * p.eta)),
      specular_weight_(plastic_specular_sampling_weight(p.reflectance, p.specular_reflectance)),
      nonlinear_(p.nonlinear),
      table_(p.rough_plastic) {
  if (!table_ || table_->distribution != p.distribution || table_->alpha != p.alpha_u ||
      table_->eta != p.eta) {
    throw std::invalid_argument(
        "rough_plastic BSDF: BsdfParams::rough_plastic must be make_rough_plastic_table(" +
        std::string(p.distribution == MicrofacetDistribution::ggx ? "ggx" : "beckmann") +
        ", alpha " + std::to_string(p.alpha_u) + ", eta " + std::to_string(p.eta) + ")" +
        (table_ ? " (the table given was built for other parameters)" : " (none given)"));
  }
}

float RoughPlasticBsdf::transmittance(float cos_theta) const {
  // Mitsuba's lerp_gather over the table.
  const float x = cos_theta * float(RoughPlasticTable::kResolution - 1);
  const int i = std::clamp(int(x), 0, RoughPlasticTable::kResolution - 2);
  const float w = x - float(i);
  const auto& table = table_->external_transmittance;
  const float t = (1.0f - w) * table[i] + w * table[i + 1];
  return std::clamp(t, 0.0f, 1.0f);  // the quadrature may overshoot 1 slightly when eta ~ 1
}

float RoughPlasticBsdf::specular_probability(float t_o) const {
  const float spec = (1.0f - t_o) * specular_weight_, diff = t_o * (1.0f - specular_weight_);
  return spec + diff > 0.0f ? spec / (spec + diff) : 0.0f;
}

float RoughPlasticBsdf::diffuse_probability(glm::vec3 wo) const {
  if (wo.z <= 0.0f) return 0.0f;
  return 1.0f - specular_probability(transmittance(wo.z));
}

glm::vec3 RoughPlasticBsdf::eval(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
  const glm::vec3 h = glm::normalize(wo + wi);
  const float d = distr_.eval(h);
  const float f = fresnel_dielectric_signed(glm::dot(wo, h), eta_).r;
  const glm::vec3 specular = specular_reflectance_ * (f * d * distr_.G(wo, wi, h) / (4.0f * wo.z));
  glm::vec3 diff = diffuse_reflectance_;
  const float r_int = table_->internal_reflectance;
  diff /= glm::vec3(1.0f) - (nonlinear_ ? diff * r_int : glm::vec3(r_int));
  diff *= kInvPi * inv_eta2_ * wi.z * transmittance(wo.z) * transmittance(wi.z);
  return specular + diff;
}

float RoughPlasticBsdf::pdf(glm::vec3 wo, glm::vec3 wi) const {
  if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
  const float p_spec = specular_probability(transmittance(wo.z));
  const glm::vec3 h = glm::normalize(wo + wi);
  float specular;
  if (distr_.sample_visible()) {
    specular = distr_.eval(h) * distr_.smith_g1(wo, h) / (4.0f * wo.z);
  } else {
    specular = distr_.pdf(wo, h) / (4.0f * glm::dot(wi, h));
  }
  return p_spec * specular + (1.0f - p_spec) * cosine_hemisphere_pdf(wi.z);
}

std::optional<BsdfSample> RoughPlasticBsdf::sample(glm::vec3 wo, float u_lobe, glm::vec2 u) const {
  if (wo.z <= 0.0f) return std::nullopt;
  const float p_spec = specular_probability(transmittance(wo.z));
  BsdfSample s;
  if (u_lobe < p_spec) {
    s.wi = reflect(wo, distr_.sample(wo, u).first);
  } else {
    s.wi = square_to_cosine_hemisphere(u);
  }
  s.pdf = pdf(wo, s.wi);
  if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf)) return std::nullopt;
  s.weight = eval(wo, s.wi) / s.pdf;
  return s;
}

}  // namespace tessera
