#include "simd/ray_points.h"

// Highway compiles this file once per target (foreach_target.h re-includes it).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd/ray_points.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace tessera::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

/// One axis: p = o + t d, a multiply then an add (hn::MulAdd would be fused on AVX2/AVX-512).
void axis(const float* o, const float* d, const float* t, size_t count, float* p) {
  const hn::ScalableTag<float> tag;
  const size_t lanes = hn::Lanes(tag);
  size_t i = 0;
  for (; i + lanes <= count; i += lanes) {
    const auto td = hn::Mul(hn::LoadU(tag, t + i), hn::LoadU(tag, d + i));
    hn::StoreU(hn::Add(hn::LoadU(tag, o + i), td), tag, p + i);
  }
  for (; i < count; ++i) {
    const float td = t[i] * d[i];  // -ffp-contract=off: not fused, as in the vector loop
    p[i] = o[i] + td;
  }
}

void PointsAlongRays(const float* ox, const float* oy, const float* oz, const float* dx, const float* dy,
                     const float* dz, const float* t, size_t count, float* px, float* py, float* pz) {
  axis(ox, dx, t, count, px);
  axis(oy, dy, t, count, py);
  axis(oz, dz, t, count, pz);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace tessera::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace tessera::simd {

HWY_EXPORT(PointsAlongRays);
HWY_EXPORT(TargetName);

void points_along_rays(const float* ox, const float* oy, const float* oz, const float* dx, const float* dy,
                       const float* dz, const float* t, size_t count, float* px, float* py, float* pz) {
  HWY_DYNAMIC_DISPATCH(PointsAlongRays)(ox, oy, oz, dx, dy, dz, t, count, px, py, pz);
}

const char* dispatched_target() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace tessera::simd
#endif
