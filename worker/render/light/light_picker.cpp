#include "render/light/light_picker.h"

namespace tessera {
namespace {

std::vector<double> uniform_if_all_zero(std::vector<double> powers) {
  bool any = false;
  for (double p : powers) any = any || p > 0;
  if (!any) powers.assign(powers.size(), 1.0);
  return powers;
}

}  // namespace

LightPicker::LightPicker(const std::vector<double>& powers)
    : distribution_(uniform_if_all_zero(powers)) {}

uint32_t LightPicker::pick(float u, const SurfacePoint& /*ref*/, float* pmf) const {
  return distribution_.sample_discrete(u, pmf);
}

float LightPicker::pmf(uint32_t i, const SurfacePoint& /*ref*/) const {
  return distribution_.pmf(i);
}

}  // namespace tessera
