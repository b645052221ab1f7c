// Sampling piecewise-constant densities in one and two dimensions by inverting their cumulative
// distributions (pbrt-v4's PiecewiseConstant1D/2D; Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 4th ed., section A.4). Hand-written: Debian has no library for it, and the light
// picker and the environment map need only these few lines.
#pragma once

#include <cstdint>
#include <glm/vec2.hpp>
#include <vector>

namespace tessera {

/// A density on [0, 1) that is constant on each of n equal cells, proportional to the given
/// non-negative weights. When every weight is zero the distribution is empty: sampling it is
/// not allowed (check empty()), and pdf() is 0 everywhere.
class PiecewiseConstant1D {
 public:
  PiecewiseConstant1D() = default;
  /// weights: finite and >= 0 (the caller checks), at least one.
  explicit PiecewiseConstant1D(const std::vector<double>& weights);

  bool empty() const { return !(total_ > 0); }
  size_t size() const { return weight_.size(); }
  /// Sum of the weights.
  double total() const { return total_; }

  /// Picks cell i with probability weight_i / total from u in [0, 1); `pmf` receives that
  /// probability and `remapped` (when not null) u's position inside the cell's interval of the
  /// cumulative distribution, again uniform in [0, 1). Never returns a cell of zero weight.
  uint32_t sample_discrete(float u, float* pmf, float* remapped = nullptr) const;
  /// The probability sample_discrete gives cell i.
  float pmf(uint32_t i) const { return empty() ? 0.0f : float(weight_[i] / total_); }

 private:
  // Stored in float (a 4k environment map has 8M cells), summed in double.
  std::vector<float> weight_;
  std::vector<float> cdf_;  ///< cdf_[i] = normalised sum of weights 0..i; 1 from the last
                            ///< non-zero cell on, so that no u lands on a trailing empty cell
  double total_ = 0;
};

/// A density on [0, 1)^2 constant on each of nx * ny cells, proportional to the weights
/// (row-major, weights[y * nx + x]): a marginal distribution over rows and one conditional
/// distribution per row.
class PiecewiseConstant2D {
 public:
  PiecewiseConstant2D() = default;
  PiecewiseConstant2D(const std::vector<double>& weights, uint32_t nx, uint32_t ny);

  bool empty() const { return marginal_.empty(); }
  double total() const { return marginal_.total(); }

  /// Picks a cell (returned as (x, y)) with probability weight / total, its probability in
  /// `pmf`, and the position of u inside that cell in `inside` (uniform in [0, 1)^2).
  glm::u32vec2 sample(glm::vec2 u, float* pmf, glm::vec2* inside) const;
  /// The probability sample() gives cell (x, y).
  float pmf(uint32_t x, uint32_t y) const;

 private:
  PiecewiseConstant1D marginal_;                  ///< over rows
  std::vector<PiecewiseConstant1D> conditional_;  ///< one per row
};

}  // namespace tessera
