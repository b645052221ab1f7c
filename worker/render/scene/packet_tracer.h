// Closest-hit and occlusion queries for many rays at once, through Embree's ray packets
// (rtcIntersect4/8/16, rtcOccluded4/8/16): the geometry half of a wavefront or packet
// integrator. It only reads an Embree scene built elsewhere (TraceableScene's).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <embree3/rtcore.h>

#include "render/math/ray.h"

namespace tessera {

/// Rays in structure-of-arrays form: ray i is o + t d for t in [0, t_max[i]], traced only when
/// active[i] != 0. Directions need not be unit length.
struct RayBatch {
  std::vector<float> ox, oy, oz;
  std::vector<float> dx, dy, dz;
  std::vector<float> t_max;
  std::vector<uint8_t> active;

  size_t size() const { return ox.size(); }
  /// Sets the size; rays added by growing are inactive (all fields zero).
  void resize(size_t n);
  /// Stores `ray` at index i (< size()), active.
  void set(size_t i, const Ray& ray);
  Ray get(size_t i) const { return {{ox[i], oy[i], oz[i]}, {dx[i], dy[i], dz[i]}, t_max[i]}; }
};

/// Closest hits in structure-of-arrays form, one entry per ray of the batch traced.
/// geometry[i] == RTC_INVALID_GEOMETRY_ID when ray i escaped or was inactive; its other fields
/// are then unspecified. Otherwise the fields are Embree's: t along the ray's own (unnormalised)
/// direction, the hit's barycentric u and v (0 for spheres), and the geometric normal ng, not
/// normalised: Embree's cross product of the edges for triangles, the hit point less the centre
/// for spheres (sphere_intersector.cpp; the renderer recomputes a unit normal from the point).
struct HitBatch {
  /// Embree geometry id: an index into the geometry table; for a shape reached through an
  /// instance, the shape's id inside the instanced scene (then `instance` is the instance's id).
  std::vector<uint32_t> geometry;
  std::vector<uint32_t> instance;   ///< Embree's instID[0]; RTC_INVALID_GEOMETRY_ID if not instanced
  std::vector<uint32_t> primitive;  ///< triangle index within the geometry; 0 for spheres
  std::vector<float> t, u, v;
  std::vector<float> ng_x, ng_y, ng_z;

  size_t size() const { return geometry.size(); }
  void resize(size_t n);
};

/// Traces RayBatches through one committed Embree scene, `width` rays per query.
///
/// Which rays share a packet depends only on their indices: the rays of [begin, end) are cut
/// into packets [begin, begin + width), [begin + width, begin + 2 width), ... with inactive
/// rays and the short tail as switched-off lanes, never compacted. The results are the same
/// bits for every width (packet_tracer_test.cpp checks widths 1, 4, 8 and 16 against each other
/// on triangle meshes and the double-precision spheres): width is a speed choice only. Across
/// Embree instruction sets they are not: rtcIntersect1 on the same 20,000 random rays of the
/// repository's scenes gave other t or u bits for 13-17 % of them with isa=avx2 and 44-57 %
/// with isa=sse4.2 than with avx512, and up to 276 other primitives, so a farm's determinism
/// still rests on pinning Embree's ISA (--isa). One exception to width-independence, seen with
/// Embree 3.13.5: a ray starting exactly on a surface reached through an Embree instance can be
/// reported occluded by rtcOccluded4/8/16 (a self-hit at t = 0) and not by rtcOccluded1; rays
/// spawned through offset_ray_origin (ray_offset.h) never start on their surface.
/// Thread-safe: const queries on a read-only scene; each call is sequential, callers
/// parallelise over disjoint index ranges.
class PacketTracer {
 public:
  /// `scene` must be committed and outlive the tracer. `width` is 1 (rtcIntersect1 per ray),
  /// 4, 8 or 16; throws std::invalid_argument otherwise.
  PacketTracer(RTCScene scene, int width);

  /// The widest packet Embree's `device` runs natively: 16 (AVX-512), 8 (AVX, AVX2), else 4.
  static int native_width(RTCDevice device);

  int width() const { return width_; }

  /// Closest hits of rays [begin, end) of `rays` into the same indices of `hits`, which must
  /// have at least `end` entries.
  void intersect(const RayBatch& rays, size_t begin, size_t end, HitBatch* hits) const;
  /// occluded[i] = 1 when something blocks active ray i for t in [0, t_max[i]], else 0 (also
  /// for inactive rays), for i in [begin, end); `occluded` must have at least `end` entries.
  void occluded(const RayBatch& rays, size_t begin, size_t end, std::vector<uint8_t>* occluded) const;

 private:
  RTCScene scene_;
  int width_;
};

}  // namespace tessera
