// The p-value of a chi-square statistic, for the statistical tests of samplers and of the
// directions BSDFs, lights and warps draw.
#pragma once

#include <cmath>

namespace tessera::test {

/// Upper tail probability of the chi-square distribution (Wilson-Hilferty approximation).
inline double chi_square_p_value(double chi2, int dof) {
  const double k = dof;
  const double z = (std::cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / std::sqrt(2.0 / (9.0 * k));
  return 0.5 * std::erfc(z / std::sqrt(2.0));
}

}  // namespace tessera::test
