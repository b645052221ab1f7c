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
    : distribution_(uniform_if_all_zero(powers)), single_(powers.size() == 1) {
  if (bounds.size() >= 2 && bounds.size() <= kMaxPerPoint) importance_ = LightImportance(bounds);
}

float LightPicker::importance_sum(const SurfacePoint& ref) const {
  if (!per_point()) return kUnknownSum;
  std::array<float, kMaxPerPoint> importance;
  return importance_.evaluate_all(ref.p, ref.ng, importance.data());
}

float LightPicker::pmf_per_point(uint32_t i, const SurfacePoint& ref, float sum) const {
  if (sum < 0) {
    std::array<float, kMaxPerPoint> importance;
    const float total = importance_.evaluate_all(ref.p, ref.ng, importance.data());
    return total > 0 ? importance[i] / total : 0.0f;
  }
  if (!(sum > 0)) return 0;
  return importance_.evaluate(i, ref.p, ref.ng) / sum;
}

}  // namespace tessera
