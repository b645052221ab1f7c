// The caustic guide: where light arrives at diffuse surfaces through glass and mirrors, and from
// which directions, learnt once per scene from photons shot before rendering (docs/renderer.md,
// "Bounces along the caustics"). A diffuse vertex in a cell of the guide sends some of its
// bounces along the directions the cell's photons came from (path_vertex.h), where a cosine
// bounce or a cone toward the whole glass sphere (target_mixture.h) rarely finds the small,
// bright image of a lamp that the glass makes.
//
// Built from the scene alone (integrators/caustic_photons.h), by a deterministic pass: photon i draws its numbers
// from a hash of its index and the photons' weights are summed in index order, so every worker of
// a farm builds the same guide bit for bit (the determinism contract, docs/design.md). The
// guide's weights are estimates; an error in them changes how well it aims, never what a sample
// is expected to give, because the renderer weighs a guided bounce by the guide's own density.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "render/guiding/test_switch.h"
#include "render/sampling/sampler.h"

namespace tessera {

class CausticGuide {
 public:
  /// Bins per side of each of the six faces of the direction cube: a bin spans 7 degrees at a
  /// face's centre, 4 at its corners.
  static constexpr int kFaceBins = 16;
  static constexpr int kBins = 6 * kFaceBins * kFaceBins;
  /// Photons shot toward each specular target (at most SpecularTargets::kMaxTargets of them).
  static constexpr uint32_t kPhotonsPerTarget = uint32_t(1) << 17;
  /// A cell with fewer photons than this is left out (its directions too uncertain to aim by).
  static constexpr uint32_t kMinPhotons = 64;
  /// A cell's side, as a fraction of the targets' mean radius (at least 2 / kGridHalf of the
  /// scene's largest coordinate).
  static constexpr float kCellFraction = 0.125f;
  /// Grid coordinates are clamped to +-kGridHalf (points beyond share the edge cells).
  static constexpr int32_t kGridHalf = 1 << 19;
  /// A cell's probability of a guided bounce (probability()) is its share of the light the
  /// bounce gathers, E_c / (E_c + E_i): E_c the caustic irradiance its photons carry, E_i the
  /// irradiance one diffuse bounce brings there (estimated at build time from kIndirectSamples
  /// cosine directions, each with one light sample where it lands). Optimal for a mixture of a
  /// perfect guide and the cosine (a^2 / p + b^2 / (1 - p) is least at p = a / (a + b)); capped
  /// at kMaxProbability, so a guided vertex's other bounces weigh at most 1 / (1 - cap) times
  /// what they weighed without the guide, and a cell under kMinProbability is left out.
  static constexpr float kMaxProbability = 0.5f;
  static constexpr float kMinProbability = 0.02f;
  static constexpr int kIndirectSamples = 64;
  /// Specular vertices a photon passes at most before it is dropped.
  static constexpr int kMaxSpecularVertices = 8;

  CausticGuide() = default;

  /// One photon's arrival at a diffuse surface after at least one specular vertex.
  struct Deposit {
    uint64_t key;  ///< its cell (cell_key)
    glm::vec3 p;   ///< where it arrived
    glm::vec3 ng;  ///< the surface's normal there, toward where it came from
    uint16_t bin;  ///< the direction toward where it came from
    float weight;  ///< its power (luminance), up to a factor common to all photons
  };
  /// A cell that received at least kMinPhotons deposits: their count, mean position and mean
  /// normal, and their weights summed per direction bin (ascending) and in all.
  struct Candidate {
    uint64_t key = 0;
    uint32_t photons = 0;
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f};
    std::vector<std::pair<uint16_t, float>> bins;
    float total = 0;
  };

  /// A guide is built in three steps (integrators/caustic_photons.cpp traces the photons):
  /// an empty guide on a grid of cells of side `cell_side`, whose cell_key() keys the photons'
  /// deposits; the deposits grouped into candidate cells (group()); the candidates kept whose
  /// share of the light a bounce gathers is large enough (keep()). Grouping sorts stably and
  /// sums in photon order, so the same deposits give the same bits on every machine.
  static CausticGuide on_grid(float cell_side);
  static std::vector<Candidate> group(std::vector<Deposit> deposits);
  /// Keeps candidate c when its probability E_c / (E_c + indirect[c]) is at least
  /// kMinProbability, E_c = its total weight times `power_to_irradiance`. `deposited`: all the
  /// deposits grouped (photons_deposited()).
  void keep(const std::vector<Candidate>& candidates, const std::vector<float>& indirect, float power_to_irradiance,
            uint64_t deposited);

  /// The key of the cell holding point p on a surface whose geometric normal, turned toward
  /// the viewer, is ng: the grid cube and the dominant axis and sign of ng.
  [[gnu::always_inline]] uint64_t cell_key(glm::vec3 p, glm::vec3 ng) const {
    const auto coordinate = [this](float v) {
      const float g = std::floor(v * inv_cell_);
      // NaN and anything past the grid go to its edge (the comparisons are false for NaN).
      const float c = g >= -float(kGridHalf) ? (g <= float(kGridHalf - 1) ? g : float(kGridHalf - 1))
                                             : -float(kGridHalf);
      return uint64_t(int64_t(c) + kGridHalf);
    };
    const float ax = std::fabs(ng.x), ay = std::fabs(ng.y), az = std::fabs(ng.z);
    const uint64_t face = ax >= ay && ax >= az ? (ng.x > 0 ? 0 : 1) : ay >= az ? (ng.y > 0 ? 2 : 3) : (ng.z > 0 ? 4 : 5);
    return (coordinate(p.x) << 43) | (coordinate(p.y) << 23) | (coordinate(p.z) << 3) | face;
  }

  /// While a DisabledForTest lives, build_caustic_guide() returns an empty guide (tests comparing the image's
  /// mean with and without it). No flag or environment variable reaches it.
  using DisabledForTest = TestSwitch<CausticGuide>::Off;

  bool empty() const { return cells_.empty(); }
  size_t cell_count() const { return cells_.size(); }
  /// Photons that reached a diffuse surface through a target, in kept cells and in all.
  uint64_t photons_kept() const { return photons_kept_; }
  uint64_t photons_deposited() const { return photons_deposited_; }

  /// The guide at one vertex: its cell (-1: none) and the probability of a guided bounce there
  /// (0 without a cell).
  struct At {
    int cell = -1;
    float probability = 0;
  };
  /// At point p of a surface whose geometric normal, turned toward the viewer, is ng.
  [[gnu::always_inline]] At at(glm::vec3 p, glm::vec3 ng) const {
    At a;
    a.cell = cell(p, ng);
    if (a.cell >= 0) a.probability = cells_[size_t(a.cell)].probability;
    return a;
  }
  /// The one-sample mixture's density toward unit w at a vertex with a cell: (1 - p) times the
  /// other strategies' density `other_pdf`, plus p times the guide's (`sampled_bin` as for
  /// pdf()).
  [[gnu::always_inline]] float mixed_pdf(At a, float other_pdf, glm::vec3 w, int sampled_bin = -1) const {
    return (1.0f - a.probability) * other_pdf + a.probability * pdf(a.cell, w, sampled_bin);
  }
  /// A strategy number u in [p, 1) that chose the other strategies, rescaled to [0, 1) for them.
  [[gnu::always_inline]] static float other_strategy(float u, float p) {
    return std::min((u - p) / (1.0f - p), 0x1.fffffep-1f);
  }

  /// The probability of a guided bounce in cell `cell` (in (0, kMaxProbability]).
  [[gnu::always_inline]] float probability(int cell) const { return cells_[size_t(cell)].probability; }
  /// Cell `cell`'s photons, their mean position and mean normal (tests, diagnostics).
  uint32_t cell_photons(int cell) const { return cells_[size_t(cell)].photons; }
  glm::vec3 cell_position(int cell) const { return cells_[size_t(cell)].position; }
  glm::vec3 cell_normal(int cell) const { return cells_[size_t(cell)].normal; }

  /// The cell holding point p on a surface whose geometric normal, turned toward the viewer,
  /// is ng; -1 when the guide has none there. Cells are cubes of the grid, split by the
  /// dominant axis and sign of ng (a floor and the wall beside it never share one).
  [[gnu::always_inline]] int cell(glm::vec3 p, glm::vec3 ng) const {
    if (cells_.empty()) return -1;
    const uint64_t key = cell_key(p, ng);
    for (uint64_t s = mix64(key) & mask_;; s = (s + 1) & mask_) {
      if (keys_[s] == key) return slot_cell_[s];
      if (keys_[s] == kEmptyKey) return -1;
    }
  }

  /// A direction from cell `cell`'s distribution: a bin by u_bin in [0, 1) (its probability its
  /// share of the cell's photon weight), then a point uniform in the bin's square on its cube
  /// face, from u in [0, 1)^2. *bin receives the bin, for pdf().
  [[gnu::always_inline]] glm::vec3 sample(int cell, float u_bin, glm::vec2 u, int* bin) const {
    const Cell& c = cells_[size_t(cell)];
    const float* cdf = cdf_.data() + c.first;
    const uint32_t i = uint32_t(std::upper_bound(cdf, cdf + c.count - 1, u_bin) - cdf);
    const int b = bin_ids_[c.first + i];
    *bin = b;
    const int face = b / (kFaceBins * kFaceBins);
    const int row = (b / kFaceBins) % kFaceBins, col = b % kFaceBins;
    constexpr float kStep = 2.0f / kFaceBins;
    const float s = (float(row) + u.x) * kStep - 1.0f;
    const float t = (float(col) + u.y) * kStep - 1.0f;
    return face_direction(face, s, t) * (1.0f / std::sqrt((1.0f + s * s) + t * t));
  }

  /// The solid-angle density sample() gives unit direction w in cell `cell`: the bin's
  /// probability over its area on the cube face, times the face's Jacobian 1 / |w_major|^3.
  /// `sampled_bin`: the bin w was drawn from (counted as holding w whatever rounding says), or
  /// -1.
  [[gnu::always_inline]] float pdf(int cell, glm::vec3 w, int sampled_bin = -1) const {
    float major = 0;
    const int b = sampled_bin >= 0 ? sampled_bin : direction_bin(w, &major);
    if (sampled_bin >= 0) direction_bin(w, &major);
    const Cell& c = cells_[size_t(cell)];
    const uint16_t* ids = bin_ids_.data() + c.first;
    const uint16_t* it = std::lower_bound(ids, ids + c.count, uint16_t(b));
    if (it == ids + c.count || *it != b) return 0.0f;
    const float inv = 1.0f / major;
    constexpr float kInvBinArea = float(kFaceBins * kFaceBins) / 4.0f;
    return prob_[c.first + uint32_t(it - ids)] * kInvBinArea * ((inv * inv) * inv);
  }

  /// The bin of unit direction w: the face of its largest component (ties to x, then y), and
  /// the square of that face holding (s, t) = the other two components over |major| (no
  /// trigonometry: the same bits on every CPU). *major receives |w_major|.
  [[gnu::always_inline]] static int direction_bin(glm::vec3 w, float* major) {
    const float ax = std::fabs(w.x), ay = std::fabs(w.y), az = std::fabs(w.z);
    int face;
    float m, s, t;
    if (ax >= ay && ax >= az) {
      face = w.x > 0 ? 0 : 1;
      m = ax, s = w.y, t = w.z;
    } else if (ay >= az) {
      face = w.y > 0 ? 2 : 3;
      m = ay, s = w.z, t = w.x;
    } else {
      face = w.z > 0 ? 4 : 5;
      m = az, s = w.x, t = w.y;
    }
    *major = m;
    constexpr float kHalf = kFaceBins * 0.5f;
    const int row = std::clamp(int((s / m + 1.0f) * kHalf), 0, kFaceBins - 1);
    const int col = std::clamp(int((t / m + 1.0f) * kHalf), 0, kFaceBins - 1);
    return (face * kFaceBins + row) * kFaceBins + col;
  }

  /// The unnormalised direction of point (s, t) of cube face `face` (direction_bin's inverse).
  [[gnu::always_inline]] static glm::vec3 face_direction(int face, float s, float t) {
    const float sign = (face & 1) ? -1.0f : 1.0f;
    switch (face >> 1) {
      case 0: return {sign, s, t};
      case 1: return {t, sign, s};
      default: return {s, t, sign};
    }
  }

 private:
  struct Cell {
    uint32_t first = 0;  ///< its bins in bin_ids_, prob_ and cdf_
    uint32_t count = 0;
    uint32_t photons = 0;
    glm::vec3 position{0.0f};  ///< the mean of its photons' positions
    glm::vec3 normal{0.0f};    ///< the mean of their normals (toward the light), unit
    float probability = 0;     ///< of a guided bounce
  };
  static constexpr uint64_t kEmptyKey = ~uint64_t(0);

  float inv_cell_ = 0;
  uint64_t mask_ = 0;
  std::vector<uint64_t> keys_;       ///< open addressing, kEmptyKey where free
  std::vector<int32_t> slot_cell_;   ///< the cell of each slot
  std::vector<Cell> cells_;
  std::vector<uint16_t> bin_ids_;    ///< per cell, ascending
  std::vector<float> prob_;          ///< each bin's share of its cell's weight
  std::vector<float> cdf_;           ///< running sums of prob_ per cell, the last set to 1
  uint64_t photons_kept_ = 0, photons_deposited_ = 0;
};

}  // namespace tessera
