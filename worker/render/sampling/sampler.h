// Random numbers as a pure function of (seed, pixel, sample index, dimension).
//
// The sequence is a shuffled, Owen-scrambled 2D Sobol sequence padded across dimension pairs
// (Burley 2020, "Practical Hash-based Owen Scrambling"; the hash is pbrt-v4's FastOwenScrambler).
// Each pair of dimensions of each pixel gets its own index shuffle and its own scrambles, keyed
// by one hash of (seed, pixel, pair). Shuffling by Owen-scrambling the index maps every aligned
// block of 2^k indices onto an aligned block, so every power-of-two batch of samples [b*B,
// (b+1)*B) is itself a (0,k,2)-net: stratification survives any batch size that is a power of
// two, and nothing depends on tiles, threads or workers (docs/design.md, "The determinism contract").
#pragma once

#include <cstdint>

#include <glm/vec2.hpp>

namespace tessera {

/// Reverses the 32 bits of v: byte swap, then the bits within each byte.
constexpr uint32_t reverse_bits32(uint32_t v) {
  v = __builtin_bswap32(v);
  v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
  return v;
}

/// Reverses the 64 bits of v: for v = hi << 32 | lo, reverse_bits32(lo) << 32 | reverse_bits32(hi),
/// two 32-bit reversals for the price of one.
constexpr uint64_t reverse_bits64(uint64_t v) {
  v = __builtin_bswap64(v);
  v = ((v >> 1) & 0x5555555555555555ull) | ((v & 0x5555555555555555ull) << 1);
  v = ((v >> 2) & 0x3333333333333333ull) | ((v & 0x3333333333333333ull) << 2);
  v = ((v >> 4) & 0x0f0f0f0f0f0f0f0full) | ((v & 0x0f0f0f0f0f0f0f0full) << 4);
  return v;
}

/// 64-bit finaliser of MurmurHash3: a bijective mix with good avalanche.
constexpr uint64_t mix64(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdull;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ull;
  k ^= k >> 33;
  return k;
}

/// SplitMix64's finaliser (Stafford's "Mix13", Steele, Lea and Flood 2014): a bijective mix that
/// turns a Weyl sequence (key + n * odd constant) into a stream that passes BigCrush.
constexpr uint64_t splitmix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

constexpr uint64_t hash_combine(uint64_t seed, uint64_t v) {
  return mix64(seed ^ (v + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2)));
}

/// The hash at the heart of the Owen scramble (pbrt-v4's FastOwenScrambler), applied to the
/// bit-reversed value: a Laine-Karras-style permutation that only lets each bit depend on the
/// bits below it.
constexpr uint32_t laine_karras_hash(uint32_t v, uint32_t seed) {
  v ^= v * 0x3d20adeau;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526c56u;
  v ^= v * 0x53a22864u;
  return v;
}

/// Nested uniform (Owen) scramble of the bits of v, most significant bit first.
constexpr uint32_t owen_scramble(uint32_t v, uint32_t seed) {
  return reverse_bits32(laine_karras_hash(reverse_bits32(v), seed));
}

/// The first two dimensions of the Sobol sequence, as 32-bit fixed-point fractions.
constexpr uint32_t sobol_dim0(uint32_t i) { return reverse_bits32(i); }
namespace detail {

/// The generator matrix of Sobol's second dimension (Pascal's triangle mod 2) applied byte by
/// byte: table[k][b] is the contribution of byte k of the index having value b.
struct Sobol1Table {
  uint32_t table[4][256];
  constexpr Sobol1Table() : table{} {
    uint32_t columns[32] = {};
    uint32_t v = 1u << 31;
    for (int bit = 0; bit < 32; ++bit, v ^= v >> 1) columns[bit] = v;
    for (int k = 0; k < 4; ++k) {
      for (uint32_t b = 0; b < 256; ++b) {
        uint32_t r = 0;
        for (int bit = 0; bit < 8; ++bit) {
          if (b & (1u << bit)) r ^= columns[k * 8 + bit];
        }
        table[k][b] = r;
      }
    }
  }
};

inline constexpr Sobol1Table kSobol1{};

}  // namespace detail

constexpr uint32_t sobol_dim1(uint32_t i) {
  return detail::kSobol1.table[0][i & 0xffu] ^ detail::kSobol1.table[1][(i >> 8) & 0xffu] ^
         detail::kSobol1.table[2][(i >> 16) & 0xffu] ^ detail::kSobol1.table[3][i >> 24];
}

namespace detail {

/// What get2d needs of the shuffled index s, given r = reverse_bits32(s): s itself and
/// reverse_bits32(sobol_dim1(s)). Both are linear over GF(2) in r (a bit permutation, and a
/// permutation then Sobol's matrix then a permutation), so both come from one table looked up
/// byte by byte: table[k][b] holds, for byte k of r having value b, s's contribution in its low
/// half and reverse_bits32(sobol_dim1(s))'s in its high half. Four loads replace a 32-bit
/// reversal and four loads of a Sobol table.
struct ShuffleTable {
  uint64_t table[4][256];
  constexpr ShuffleTable() : table{} {
    for (int k = 0; k < 4; ++k) {
      for (uint32_t b = 0; b < 256; ++b) {
        const uint32_t s = reverse_bits32(b << (8 * k));
        table[k][b] = uint64_t(reverse_bits32(sobol_dim1(s))) << 32 | s;
      }
    }
  }
};

inline constexpr ShuffleTable kShuffle{};

}  // namespace detail

/// For r = reverse_bits32(s): reverse_bits32(sobol_dim1(s)) << 32 | s.
constexpr uint64_t unreverse_with_sobol_dim1(uint32_t r) {
  return detail::kShuffle.table[0][r & 0xffu] ^ detail::kShuffle.table[1][(r >> 8) & 0xffu] ^
         detail::kShuffle.table[2][(r >> 16) & 0xffu] ^ detail::kShuffle.table[3][r >> 24];
}

/// The reference definition of sobol_dim1, bit by bit (for tests).
constexpr uint32_t sobol_dim1_reference(uint32_t i) {
  uint32_t r = 0;
  for (uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1) {
    if (i & 1u) r ^= v;
  }
  return r;
}

/// A 32-bit fixed-point fraction as a float in [0, 1) (24 bits kept, so never 1).
constexpr float to_unit_float(uint32_t x) { return float(x >> 8) * 0x1p-24f; }

/// The sample stream of one (pixel, sample index): each get*() call takes the next dimension.
/// Callers must consume dimensions in the same order for every sample (the integrator lays
/// them out per path vertex) so that a dimension means the same thing across samples.
class PixelSampler {
 public:
  /// The per-pixel key every dimension's hash starts from.
  static constexpr uint64_t pixel_key(uint64_t seed, int x, int y) {
    return hash_combine(hash_combine(mix64(seed), uint64_t(uint32_t(x))), uint64_t(uint32_t(y)));
  }

  PixelSampler(uint64_t seed, int x, int y, uint32_t sample_index)
      : PixelSampler(pixel_key(seed, x, y), sample_index) {}

  PixelSampler(uint64_t pixel_key, uint32_t sample_index)
      : pixel_key_(pixel_key),
        pair_offset_(0x9e3779b97f4a7c15ull + (pixel_key << 6) + (pixel_key >> 2)),
        sample_key_(sample_key(pixel_key, sample_index)),
        index_(sample_index),
        index_reversed_(reverse_bits32(sample_index)) {}

  /// Dimension pairs from this one on are independent hashed uniforms, not Sobol points:
  /// past the first few bounces stratification no longer lowers the error measurably, and a
  /// hash costs a fraction of three Owen scrambles.
  static constexpr uint32_t kSobolPairs = 14;

  /// The key of one (pixel, sample index) that the independent pairs start from: one mix per
  /// sample, so that each independent pair needs only one more.
  static constexpr uint64_t sample_key(uint64_t pixel_key, uint32_t sample_index) {
    return mix64(pixel_key ^ (uint64_t(sample_index) * 0x9e3779b97f4a7c15ull));
  }

  /// The three 32-bit scramble seeds of a pair, from its one 64-bit hash h: the index shuffle
  /// takes the low half, x the high half and y the high half of h times an odd constant (a
  /// multiply instead of a second mix64: every bit of h reaches y's seed through the carries,
  /// and the product's high half is a different function of h than either half).
  static constexpr uint32_t shuffle_seed(uint64_t h) { return uint32_t(h); }
  static constexpr uint32_t x_seed(uint64_t h) { return uint32_t(h >> 32); }
  static constexpr uint32_t y_seed(uint64_t h) { return uint32_t((h * 0xd1342543de82ef95ull) >> 32); }

  /// The next pair of dimensions, each in [0, 1): the shuffled, scrambled Sobol point
  ///   h = hash_combine(pixel key, pair)
  ///   shuffled = owen_scramble(index, shuffle_seed(h))
  ///   x = owen_scramble(sobol_dim0(shuffled), x_seed(h)),  y = owen_scramble(sobol_dim1(shuffled), y_seed(h))
  /// computed with one bit reversal (of both coordinates at once) instead of seven: sobol_dim0
  /// is a reversal, reversals cancel, the index's reversal is computed once per sample, and the
  /// shuffled index comes back from its reversal together with its sobol_dim1 by one table.
  glm::vec2 get2d() {
    if (pair_ >= kSobolPairs) return get2d_independent();
    const uint64_t h = pair_hash(pair_++);
    // x's scramble takes the reversal of sobol_dim0(shuffled), which is shuffled itself; y's the
    // reversal of sobol_dim1(shuffled). The hash gives shuffled's reversal; one table both.
    const uint64_t dim1_shuffled = unreverse_with_sobol_dim1(laine_karras_hash(index_reversed_, shuffle_seed(h)));
    const uint32_t x_reversed = laine_karras_hash(uint32_t(dim1_shuffled), x_seed(h));
    const uint32_t y_reversed = laine_karras_hash(uint32_t(dim1_shuffled >> 32), y_seed(h));
    // Both final reversals in one 64-bit pass: y lands in the high half.
    const uint64_t yx = reverse_bits64(uint64_t(x_reversed) << 32 | y_reversed);
    return {to_unit_float(uint32_t(yx)), to_unit_float(uint32_t(yx >> 32))};
  }

  /// get2d().x alone, with the same bits (and the same step to the next pair): for the
  /// decisions that take one number (a BSDF's lobe, the bounce mixture's strategy;
  /// path_vertex.h), without y's scramble and reversal.
  float get2d_x() {
    if (pair_ >= kSobolPairs) return get2d_independent().x;
    const uint64_t h = pair_hash(pair_++);
    const uint64_t dim1_shuffled = unreverse_with_sobol_dim1(laine_karras_hash(index_reversed_, shuffle_seed(h)));
    return to_unit_float(reverse_bits32(laine_karras_hash(uint32_t(dim1_shuffled), x_seed(h))));
  }

  /// get2d() by its definition, without the algebra (for tests).
  glm::vec2 get2d_reference() {
    const uint64_t h = hash_combine(pixel_key_, pair_++);
    const uint32_t shuffled = owen_scramble(index_, shuffle_seed(h));
    const uint32_t x = owen_scramble(sobol_dim0(shuffled), x_seed(h));
    const uint32_t y = owen_scramble(sobol_dim1(shuffled), y_seed(h));
    return {to_unit_float(x), to_unit_float(y)};
  }

  /// The next pair of dimensions as independent hashed uniforms, for decisions that gain
  /// nothing from stratification (emitter choice, Russian roulette) and for every pair from
  /// kSobolPairs on: splitmix64(sample_key + pair * kIndependentStep), SplitMix64's stream
  /// with the sample's key as its seed, one mix per pair. Still a pure function of (seed,
  /// pixel, sample index, dimension).
  glm::vec2 get2d_independent() {
    const uint64_t r = splitmix64(sample_key_ + uint64_t(pair_++) * kIndependentStep);
    return {to_unit_float(uint32_t(r)), to_unit_float(uint32_t(r >> 32))};
  }

  /// SplitMix64's increment (the golden ratio in 64 bits): get2d_independent's step per pair.
  static constexpr uint64_t kIndependentStep = 0x9e3779b97f4a7c15ull;

  /// Skips to a fixed pair index, so that each path vertex starts at a known dimension.
  void set_pair(uint32_t pair) { pair_ = pair; }

  /// What get2d() computes a Sobol pair from, for code that draws many samplers' pairs at once
  /// (the wavefront kernels): pair p's hash is mix64(pixel_key_value() ^ (p + pair_offset())), and
  /// index_reversed() is reverse_bits32 of the sample index.
  uint64_t pixel_key_value() const { return pixel_key_; }
  uint64_t pair_offset() const { return pair_offset_; }
  uint32_t index_reversed() const { return index_reversed_; }

 private:
  /// hash_combine(pixel_key_, pair), with the part that depends on the pixel alone computed
  /// once per sample (wrapping sums regroup exactly).
  uint64_t pair_hash(uint32_t pair) const { return mix64(pixel_key_ ^ (uint64_t(pair) + pair_offset_)); }

  uint64_t pixel_key_;
  uint64_t pair_offset_;  ///< hash_combine's pixel-dependent addend
  uint64_t sample_key_;   ///< sample_key(pixel_key_, index_)
  uint32_t index_;
  uint32_t index_reversed_;
  uint32_t pair_ = 0;
};

}  // namespace tessera
