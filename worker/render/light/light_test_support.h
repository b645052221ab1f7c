// Test support for the light tests: a seeded uniform generator and a chi-square test of
// sampled directions against a density (Mitsuba's ChiSquareTest, simplified: fixed bins whose
// expected counts come from integrating the density on a fine grid inside each bin).
#pragma once

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/sampling/chi_square_p_value.h"
#include "scene/scene_error.h"
#include "scene/loader/scene_loader.h"

namespace tessera::test {

/// Uniform floats in [0, 1) from a fixed seed, the same on every platform (mt19937_64 is fully
/// specified; the standard distributions are not, so they are avoided).
class UniformFloats {
 public:
  explicit UniformFloats(uint64_t seed) : engine_(seed) {}
  float next() { return float(engine_() >> 40) * 0x1p-24f; }
  glm::vec2 next2() {
    const float a = next();
    return {a, next()};
  }

 private:
  std::mt19937_64 engine_;
};

/// Bins over the sphere in a frame: cos(theta) = dot(d, frame[2]),
/// phi = atan2(dot(d, frame[1]), dot(d, frame[0])), both cut at the given ascending edges
/// (cos edges within [-1, 1]; phi edges spanning one turn: last = first + 2 pi).
/// A density constant inside each bin is integrated exactly; a smooth one to about
/// 1 / kSub^2 relative.
struct DirectionBins {
  glm::mat3 frame{1.0f};
  std::vector<double> cos_edges;
  std::vector<double> phi_edges;

  /// n equal steps of cos(theta) over [-1, 1] and of phi over [0, 2 pi).
  static DirectionBins uniform(int n_cos, int n_phi, glm::mat3 frame = glm::mat3(1.0f)) {
    DirectionBins b;
    b.frame = frame;
    for (int i = 0; i <= n_cos; ++i) b.cos_edges.push_back(-1.0 + 2.0 * i / n_cos);
    for (int i = 0; i <= n_phi; ++i) b.phi_edges.push_back(2.0 * M_PI * i / n_phi);
    return b;
  }
};

struct DirectionChiSquareResult {
  double chi2 = 0;
  int dof = 0;
  double p_value = 0;
  std::string detail;  ///< the worst bins, for the failure message
};

/// Draws n directions with `sample` (nullopt = a sample that produced nothing) and compares
/// the counts per bin with n * the integral of `pdf` over the bin. Directions outside the cos
/// range and samples that produced nothing fall in an extra bin whose expected count is
/// n * (1 - integral over all bins).
/// Bins expecting fewer than 5 are pooled (among them the bins that the integration grid
/// sees as empty though a silhouette crosses them).
inline DirectionChiSquareResult chi_square_directions(
    const DirectionBins& bins, int n, const std::function<std::optional<glm::vec3>()>& sample,
    const std::function<double(glm::vec3)>& pdf) {
  constexpr int kSub = 32;
  const size_t nc = bins.cos_edges.size() - 1, np = bins.phi_edges.size() - 1;
  auto direction = [&](double cos_theta, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
    return glm::normalize(bins.frame * glm::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)),
                                                 float(cos_theta)));
  };
  std::vector<double> expected(nc * np + 1, 0.0), observed(nc * np + 1, 0.0);
  double inside = 0;
  for (size_t i = 0; i < nc; ++i) {
    for (size_t j = 0; j < np; ++j) {
      const double dc = (bins.cos_edges[i + 1] - bins.cos_edges[i]) / kSub;
      const double dp = (bins.phi_edges[j + 1] - bins.phi_edges[j]) / kSub;
      double mass = 0;
      for (int a = 0; a < kSub; ++a) {
        for (int b = 0; b < kSub; ++b) {
          mass += pdf(
              direction(bins.cos_edges[i] + (a + 0.5) * dc, bins.phi_edges[j] + (b + 0.5) * dp));
        }
      }
      mass *= dc * dp;
      expected[i * np + j] = mass * n;
      inside += mass;
    }
  }
  expected.back() = std::max(0.0, 1.0 - inside) * n;
  for (int k = 0; k < n; ++k) {
    const std::optional<glm::vec3> d = sample();
    if (!d) {
      observed.back() += 1;
      continue;
    }
    const glm::vec3 local = glm::transpose(bins.frame) * *d;
    const double c = local.z;
    double phi = std::atan2(double(local.y), double(local.x));
    while (phi < bins.phi_edges.front()) phi += 2 * M_PI;
    while (phi >= bins.phi_edges.back()) phi -= 2 * M_PI;
    size_t bin = nc * np;
    if (c >= bins.cos_edges.front() && c <= bins.cos_edges.back()) {
      size_t i = 0, j = 0;
      while (i + 1 < nc && c >= bins.cos_edges[i + 1]) ++i;
      while (j + 1 < np && phi >= bins.phi_edges[j + 1]) ++j;
      bin = i * np + j;
    }
    observed[bin] += 1;
  }
  DirectionChiSquareResult r;
  double pooled_expected = 0, pooled_observed = 0;
  std::ostringstream worst;
  int reported = 0;  // the first few bins off by more than 4 sigma
  for (size_t k = 0; k < expected.size(); ++k) {
    if (expected[k] < 5) {
      pooled_expected += expected[k];
      pooled_observed += observed[k];
      continue;
    }
    const double d = observed[k] - expected[k];
    r.chi2 += d * d / expected[k];
    ++r.dof;
    if (std::abs(d) > 4 * std::sqrt(expected[k]) && ++reported <= 8) {
      worst << "bin " << k << " observed " << observed[k] << " expected " << expected[k] << "; ";
    }
  }
  if (pooled_expected > 0) {
    const double d = pooled_observed - pooled_expected;
    r.chi2 += d * d / pooled_expected;
    ++r.dof;
  }
  r.dof -= 1;
  r.p_value = r.dof > 0 ? chi_square_p_value(r.chi2, r.dof) : 1.0;
  r.detail =
      "chi2 " + std::to_string(r.chi2) + " dof " + std::to_string(r.dof) + "; " + worst.str();
  return r;
}

/// The significance level of every chi-square test here: with fixed seeds a pass is
/// reproducible, and a wrong density (a missing sin(theta), a shifted texel) fails by far.
inline constexpr double kChiSquareLevel = 1e-3;

}  // namespace tessera::test

namespace tessera::test {

/// Bins aligned with an environment map's sampling cells (map frame = world), each cell cut
/// into split x split bins: the envmap density is constant on each bin, so the expected counts
/// are exact. A to_world rotation R of the map is applied as `rotation`.
inline DirectionBins envmap_cell_bins(uint32_t width, uint32_t height, int split,
                                      glm::mat3 rotation = glm::mat3(1.0f)) {
  DirectionBins b;
  // The map's (u, v): v = theta / pi about +y, u = atan2(x, -z) / (2 pi): phi about +y
  // measured from -z towards +x.
  b.frame = rotation * glm::mat3(glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
  const uint32_t rows = height - 1;
  for (int i = int(rows) * split; i >= 0; --i) {
    b.cos_edges.push_back(std::cos(M_PI * double(i) / (double(rows) * split)));
  }
  b.cos_edges.front() = -1.0;
  b.cos_edges.back() = 1.0;
  for (uint32_t i = 0; i <= width * uint32_t(split); ++i) {
    b.phi_edges.push_back(2.0 * M_PI * (0.5 + double(i) / split) / double(width));
  }
  return b;
}

}  // namespace tessera::test

namespace tessera::test {

/// Writes an image of the format `extension` names (".exr", ".png", ...) with OpenImageIO
/// from `pixels` (w * h * channels values of type `type`), through a file named after the
/// process so that parallel test processes do not collide, and returns its bytes.
inline std::string image_bytes(const std::string& extension, int w, int h, int channels,
                               OIIO::TypeDesc type, const void* pixels) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("tessera_envmap_test_" + std::to_string(::getpid()) + extension);
  auto out = OIIO::ImageOutput::create(path.string());
  const OIIO::ImageSpec spec(w, h, channels, type);
  if (!out || !out->open(path.string(), spec) || !out->write_image(type, pixels) || !out->close()) {
    throw std::runtime_error("cannot write " + path.string() + ": " + OIIO::geterror());
  }
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::filesystem::remove(path);
  return bytes.str();
}

/// An RGB float EXR's bytes.
inline std::string exr_bytes(int w, int h, const std::vector<float>& rgb) {
  return image_bytes(".exr", w, h, 3, OIIO::TypeDesc::FLOAT, rgb.data());
}

/// A FileReader holding one file.
inline FileReader reader_of(const std::string& name, const std::string& bytes) {
  return [name, bytes](const std::string& path) {
    if (path != name) throw SceneError(path + ": not in the scene bundle");
    return bytes;
  };
}

}  // namespace tessera::test

namespace tessera::test {

/// Irradiance at p (normal n) from a uniform Lambertian polygon of radiance le (Lambert's
/// formula: le / 2 * sum of edge angles times the cosine of their planes with n). One copy for
/// the light tests (two, in anonymous namespaces, collided in the sanitizer pass's unity build).
inline double polygon_irradiance(const std::vector<glm::vec3>& polygon, glm::dvec3 p, glm::dvec3 n, double le) {
  double sum = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3 a = glm::normalize(glm::dvec3(polygon[i]) - p);
    const glm::dvec3 b = glm::normalize(glm::dvec3(polygon[(i + 1) % polygon.size()]) - p);
    const double angle = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
    sum += angle * glm::dot(n, glm::normalize(glm::cross(a, b)));
  }
  return le / 2 * std::abs(sum);
}

}  // namespace tessera::test
