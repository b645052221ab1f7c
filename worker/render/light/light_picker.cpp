#include "render/light/light_picker.h"

#include <array>

namespace tessera {
namespace {

std::vector<double> uniform_if_all_zero(std::vector<double> powers) {
  bool any = false;
  for (double p : powers) any = any || p > 0;
  if (!any) powers.assign(powers.size(), 1.0);
  return powers;
}

}  // namespace

LightPicker::LightPicker(std::vector<LightBounds> bounds, const std::vector<double>& powers)
    : distribution_(uniform_if_all_zero(powers)) {
  if (bounds.size() >= 2 && bounds.size() <= kMaxPerPoint) bounds_ = std::move(bounds);
}

double LightPicker::importances(const SurfacePoint& ref, double* importance) const {
  double total = 0;
  for (size_t i = 0; i < bounds_.size(); ++i) {
    importance[i] = bounds_[i].importance(ref.p, ref.ng);
    total += importance[i];
  }
  return total;
}

uint32_t LightPicker::pick_per_point(float u, const SurfacePoint& ref, float* pmf) const {
  std::array<double, kMaxPerPoint> importance;
  const double total = importances(ref, importance.data());
  *pmf = 0;
  if (!(total > 0)) return 0;
  // The first light whose cumulative importance exceeds u * total; lights of importance 0 are
  // never chosen (if rounding carries u * total past the sum, the last light with any).
  const double target = double(u) * total;
  double cumulative = 0;
  uint32_t chosen = 0;
  for (uint32_t i = 0; i < bounds_.size(); ++i) {
    if (!(importance[i] > 0)) continue;
    chosen = i;
    cumulative += importance[i];
    if (target < cumulative) break;
  }
  *pmf = float(importance[chosen] / total);
  return chosen;
}

float LightPicker::pmf_per_point(uint32_t i, const SurfacePoint& ref) const {
  std::array<double, kMaxPerPoint> importance;
  const double total = importances(ref, importance.data());
  if (!(total > 0)) return 0;
  return float(importance[i] / total);
}

}  // namespace tessera
