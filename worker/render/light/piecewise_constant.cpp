#include "render/light/piecewise_constant.h"

#include <algorithm>

namespace tessera {

PiecewiseConstant1D::PiecewiseConstant1D(const std::vector<double>& weights) {
  weight_.reserve(weights.size());
  cdf_.reserve(weights.size());
  size_t last_nonzero = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    total_ += weights[i];
    weight_.push_back(float(weights[i]));
    if (weights[i] > 0) last_nonzero = i;
  }
  double running = 0;
  for (size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    cdf_.push_back(i >= last_nonzero ? 1.0f : float(running / total_));
  }
}

uint32_t PiecewiseConstant1D::sample_discrete(float u, float* pmf, float* remapped) const {
  // The first cell whose cumulative value exceeds u; a zero-weight cell has the same value as
  // the cell before it, so it is never the first to exceed u.
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const uint32_t i = uint32_t(std::min<size_t>(size_t(it - cdf_.begin()), cdf_.size() - 1));
  *pmf = this->pmf(i);
  if (remapped) {
    const float lo = i == 0 ? 0.0f : cdf_[i - 1];
    const float width = cdf_[i] - lo;
    *remapped = width > 0 ? std::clamp((u - lo) / width, 0.0f, 0x1.fffffep-1f) : 0.0f;
  }
  return i;
}

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<double>& weights, uint32_t nx,
                                         uint32_t ny) {
  std::vector<double> row_totals(ny, 0.0);
  conditional_.reserve(ny);
  for (uint32_t y = 0; y < ny; ++y) {
    const auto begin = weights.begin() + ptrdiff_t(size_t(y) * nx);
    conditional_.emplace_back(std::vector<double>(begin, begin + nx));
    row_totals[y] = conditional_.back().total();
  }
  marginal_ = PiecewiseConstant1D(row_totals);
}

glm::u32vec2 PiecewiseConstant2D::sample(glm::vec2 u, float* pmf, glm::vec2* inside) const {
  float pmf_y = 0, pmf_x = 0;
  const uint32_t y = marginal_.sample_discrete(u.y, &pmf_y, &inside->y);
  const uint32_t x = conditional_[y].sample_discrete(u.x, &pmf_x, &inside->x);
  *pmf = pmf_y * pmf_x;
  return {x, y};
}

float PiecewiseConstant2D::pmf(uint32_t x, uint32_t y) const {
  return marginal_.pmf(y) * conditional_[y].pmf(x);
}

}  // namespace tessera
