#include "scene/transform.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace tessera {

Transform::Transform(const glm::dmat4& matrix)
    : matrix_(matrix), normal_matrix_(glm::transpose(glm::inverse(glm::dmat3(matrix)))) {}

Transform Transform::then(const Transform& next) const { return Transform(next.matrix_ * matrix_); }

glm::dvec3 Transform::point(const glm::dvec3& p) const {
  return glm::dvec3(matrix_ * glm::dvec4(p, 1.0));
}

glm::dvec3 Transform::normal(const glm::dvec3& n) const {
  return glm::normalize(normal_matrix_ * n);
}

double Transform::determinant() const { return glm::determinant(linear()); }

std::optional<double> Transform::similarity_scale() const {
  // L^T L = s^2 I exactly for a similarity.
  glm::dmat3 l = linear();
  glm::dmat3 gram = glm::transpose(l) * l;
  double s2 = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
  if (!(s2 > 0) || !std::isfinite(s2)) return std::nullopt;
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      worst = std::max(worst, std::abs(gram[c][r] - (c == r ? s2 : 0.0)));
    }
  }
  if (worst > 1e-6 * s2) return std::nullopt;
  return std::sqrt(s2);
}

}  // namespace tessera
