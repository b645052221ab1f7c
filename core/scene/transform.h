// An affine transform from object space to world space.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <optional>

namespace tessera {

/// An invertible affine map p -> M p. Points, normals and the orientation of triangles go
/// through it consistently: normals by the inverse transpose, and a map with a negative
/// determinant (a mirror) flips triangle winding so that the front stays the front.
class Transform {
 public:
  /// The identity.
  Transform() = default;
  /// `matrix` must be affine (last row 0 0 0 1) and invertible; callers check (see
  /// parse_transform).
  explicit Transform(const glm::dmat4& matrix);

  const glm::dmat4& matrix() const { return matrix_; }
  /// This transform followed by `next` (next ∘ this).
  Transform then(const Transform& next) const;

  glm::dvec3 point(const glm::dvec3& p) const;
  /// The transformed normal, unit length. `n` must be non-zero.
  glm::dvec3 normal(const glm::dvec3& n) const;
  /// Determinant of the linear part; < 0 for transforms that mirror.
  double determinant() const;
  bool flips_orientation() const { return determinant() < 0; }
  /// The scale factor s > 0 when the linear part is s times an orthogonal matrix (a similarity:
  /// rotation, mirror, uniform scale), within a relative tolerance of 1e-6; nullopt otherwise.
  std::optional<double> similarity_scale() const;

 private:
  glm::dmat3 linear() const { return glm::dmat3(matrix_); }

  glm::dmat4 matrix_{1.0};
  glm::dmat3 normal_matrix_{1.0};  ///< inverse transpose of the linear part
};

}  // namespace tessera
