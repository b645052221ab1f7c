// Points along rays, p = o + t d, for a structure-of-arrays batch, compiled for every x86
// instruction set Google Highway targets (SSE4, AVX2, AVX-512, ...) and dispatched at run time
// to the best one the CPU has: the seam through which the packet integrator's lane-wise kernels
// are built for AVX2 and AVX-512 (issue 13).
//
// Determinism: every target computes each lane as one IEEE multiply and then one IEEE add
// (never a fused multiply-add, which rounds once and would give other bits on targets that
// have it), so the result is bit-identical on every target and equal to the scalar expression
// compiled with -ffp-contract=off.
#pragma once

#include <cstddef>

namespace tessera::simd {

/// p[i] = o[i] + t[i] * d[i] for i in [0, count), per axis: (px, py, pz) from origins (ox, oy,
/// oz), directions (dx, dy, dz) and distances t. Arrays need no alignment; outputs may alias
/// the origins.
void points_along_rays(const float* ox, const float* oy, const float* oz, const float* dx, const float* dy,
                       const float* dz, const float* t, size_t count, float* px, float* py, float* pz);

/// The instruction set points_along_rays dispatches to on this CPU ("AVX3" is AVX-512).
const char* dispatched_target();

}  // namespace tessera::simd
