// Floats lane by lane, four (Float4) or any vector width (the templates below), for code that
// must give the same bits as its scalar form: the light picker's importance of four lights at
// once (light/light_importance.h) and the bounce mixture's cones of four or eight targets or
// lamp images at once (target_mixture.h).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

namespace tessera::float4 {

// GCC's vector extensions: +, -, *, / and comparisons lane by lane, IEEE in every lane, on
// whatever vector unit the target has (or none). -ffp-contract=off keeps a * b + c two
// roundings, as in the scalar code (CMakeLists.txt).
using Float4 = float __attribute__((vector_size(16)));
using Mask4 = int32_t __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Float4 load(const float* v) {
  Float4 r;
  std::memcpy(&r, v, sizeof r);
  return r;
}
[[gnu::always_inline]] inline Mask4 load(const int32_t* v) {
  Mask4 r;
  std::memcpy(&r, v, sizeof r);
  return r;
}
[[gnu::always_inline]] inline Float4 splat(float x) { return Float4{x, x, x, x}; }

/// Correctly rounded in every lane (sqrtps, or the scalar sqrt lane by lane): the same bits.
[[gnu::always_inline]] inline Float4 sqrt4(Float4 x) {
#if defined(__SSE__)
  return _mm_sqrt_ps(x);
#else
  return Float4{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
#endif
}
/// |x| lane by lane (the sign bit cleared), for a float vector V of any width and M, its int32
/// mask type (wider vectors pass between inlined functions only: see the templates below).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class V, class M>
[[gnu::always_inline]] inline V abs_lanes(V x) {
  M bits;
  std::memcpy(&bits, &x, sizeof bits);
  bits &= 0x7fffffff;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}
#pragma GCC diagnostic pop
[[gnu::always_inline]] inline Float4 abs4(Float4 x) { return abs_lanes<Float4, Mask4>(x); }

/// Bit l set where lane l of m is set (m's lanes all-ones or zero, as comparisons give).
[[gnu::always_inline]] inline unsigned lane_bits(Mask4 m) {
#if defined(__SSE__)
  __m128 v;
  std::memcpy(&v, &m, sizeof v);
  return unsigned(_mm_movemask_ps(v));
#else
  return (m[0] ? 1u : 0u) | (m[1] ? 2u : 0u) | (m[2] ? 4u : 0u) | (m[3] ? 8u : 0u);
#endif
}

// The same for any width W of GCC vector type (4 in baseline code, 8 in the AVX2 and AVX-512
// wavefront kernels, wavefront/wavefront_kernel.inc), written without intrinsics so that these
// templates, defined before a kernel's `#pragma GCC target`, compile into it for its own
// instruction set once inlined there: GCC turns the square root's lane loop into one sqrtps
// (vsqrtps on ymm registers in the AVX2 kernel), as IEEE as the scalar sqrtss.

// These pass vectors by value between inlined functions only: GCC's note that the ABI of a
// 32-byte vector differs without AVX does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

/// The number of float lanes of vector type V.
template <class V>
inline constexpr int kWidth = int(sizeof(V) / sizeof(float));

/// kWidth<V> floats (or int32 mask lanes) from v.
template <class V, class T>
[[gnu::always_inline]] inline V load_lanes(const T* v) {
  static_assert(sizeof(T) == sizeof(float));
  V r;
  std::memcpy(&r, v, sizeof r);
  return r;
}
template <class V>
[[gnu::always_inline]] inline V splat_lanes(float x) {
  V r;
  for (int l = 0; l < kWidth<V>; ++l) r[l] = x;
  return r;
}
/// max(x, lo) lane by lane; lo where x is NaN.
template <class V>
[[gnu::always_inline]] inline V at_least(V x, V lo) {
  return x > lo ? x : lo;
}
/// min(x, hi) lane by lane; hi where x is NaN.
template <class V>
[[gnu::always_inline]] inline V at_most(V x, V hi) {
  return x < hi ? x : hi;
}
template <class V>
[[gnu::always_inline]] inline V sqrt_lanes(V x) {
  V r;
  for (int l = 0; l < kWidth<V>; ++l) r[l] = __builtin_sqrtf(x[l]);
  return r;
}
/// Bit l set where lane l of m is set (comparisons' all-ones or zero).
template <class M>
[[gnu::always_inline]] inline unsigned bits_of_lanes(M m) {
  if constexpr (sizeof(M) == sizeof(Mask4)) {
    Mask4 m4;
    std::memcpy(&m4, &m, sizeof m4);
    return lane_bits(m4);
  } else {
    unsigned bits = 0;
    for (int l = 0; l < int(sizeof(M) / sizeof(int32_t)); ++l) bits |= (m[l] < 0 ? 1u : 0u) << l;
    return bits;
  }
}

/// For each set of lanes `bits` of a W-lane vector, the lanes' indices in order, then zeros:
/// compress_lanes' permutation.
template <int W>
struct CompressTable {
  int32_t lanes[1 << W][W];
  constexpr CompressTable() : lanes{} {
    for (int bits = 0; bits < (1 << W); ++bits) {
      int k = 0;
      for (int l = 0; l < W; ++l) {
        if (bits & (1 << l)) lanes[bits][k++] = l;
      }
    }
  }
};
template <int W>
inline constexpr CompressTable<W> kCompressTable{};

/// Stores the lanes of v set in `bits` at out[0], out[1], ... (lane 0 first), moved there by one
/// permutation (vpermps where the instruction set has it) and stored as a whole vector: the
/// lanes after the chosen ones are written too, so out needs room for kWidth<V> floats. For
/// code that appends a vector's chosen lanes to an array (which then needs kWidth<V> - 1 slots
/// of room past its last element). The vector is taken by reference and nothing is returned: a
/// wide vector passed or returned by value would change the baseline build's ABI (-Wpsabi, an
/// error under clang even where the call is inlined).
template <class V, class M>
[[gnu::always_inline]] inline void compress_store(float* out, const V& v, unsigned bits) {
#if defined(__clang__)
  // clang has no run-time vector shuffle builtin (and builds no x86 kernel: wavefront_kernels.h).
  float packed[kWidth<V>] = {};
  int k = 0;
  for (int l = 0; l < kWidth<V>; ++l) {
    if (bits & (1u << l)) packed[k++] = v[l];
  }
#else
  const V packed = __builtin_shuffle(v, load_lanes<M>(kCompressTable<kWidth<V>>.lanes[bits]));
#endif
  std::memcpy(out, &packed, sizeof packed);
}

#pragma GCC diagnostic pop

}  // namespace tessera::float4
