#include "render/scene/packet_tracer.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "render/scene/embree_packet.h"

namespace tessera {
namespace {

/// Lane `lane` of packet ray `r` (RTCRay, RTCRayK) from ray i of the batch; tnear 0 as for
/// TraceableScene's single rays.
template <typename R>
void load_lane(R& r, int lane, const RayBatch& rays, size_t i) {
  r.org_x[lane] = rays.ox[i];
  r.org_y[lane] = rays.oy[i];
  r.org_z[lane] = rays.oz[i];
  r.dir_x[lane] = rays.dx[i];
  r.dir_y[lane] = rays.dy[i];
  r.dir_z[lane] = rays.dz[i];
  r.tnear[lane] = 0.0f;
  r.tfar[lane] = rays.t_max[i];
  r.time[lane] = 0.0f;
  r.mask[lane] = 0xffffffffu;
  r.id[lane] = 0;
  r.flags[lane] = 0;
}

template <int K>
void intersect_packets(RTCScene scene, const RayBatch& rays, size_t begin, size_t end, HitBatch* hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t first = begin; first < end; first += K) {
    const size_t n = std::min(end - first, size_t(K));
    alignas(64) int valid[K];
    alignas(64) typename EmbreePacket<K>::RayHit rh;
    for (int lane = 0; lane < K; ++lane) {
      const size_t i = first + size_t(lane);
      const bool on = size_t(lane) < n && rays.active[i];
      valid[lane] = on ? -1 : 0;
      if (on) {
        load_lane(rh.ray, lane, rays, i);
      } else {
        // Switched-off lanes still hold finite data: Embree may read them before masking.
        load_lane(rh.ray, lane, rays, first);
        rh.ray.tfar[lane] = -1.0f;
      }
      rh.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.primID[lane] = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
    }
    EmbreePacket<K>::intersect(valid, scene, &context, &rh);
    for (size_t lane = 0; lane < n; ++lane) {
      const size_t i = first + lane;
      hits->geometry[i] = valid[lane] ? rh.hit.geomID[lane] : RTC_INVALID_GEOMETRY_ID;
      hits->instance[i] = rh.hit.instID[0][lane];
      hits->primitive[i] = rh.hit.primID[lane];
      hits->t[i] = rh.ray.tfar[lane];
      hits->u[i] = rh.hit.u[lane];
      hits->v[i] = rh.hit.v[lane];
      hits->ng_x[i] = rh.hit.Ng_x[lane];
      hits->ng_y[i] = rh.hit.Ng_y[lane];
      hits->ng_z[i] = rh.hit.Ng_z[lane];
    }
  }
}

void intersect_single(RTCScene scene, const RayBatch& rays, size_t begin, size_t end, HitBatch* hits) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = begin; i < end; ++i) {
    hits->geometry[i] = RTC_INVALID_GEOMETRY_ID;
    if (!rays.active[i]) continue;
    RTCRayHit rh;
    rh.ray.org_x = rays.ox[i];
    rh.ray.org_y = rays.oy[i];
    rh.ray.org_z = rays.oz[i];
    rh.ray.dir_x = rays.dx[i];
    rh.ray.dir_y = rays.dy[i];
    rh.ray.dir_z = rays.dz[i];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = rays.t_max[i];
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &context, &rh);
    hits->geometry[i] = rh.hit.geomID;
    hits->instance[i] = rh.hit.instID[0];
    hits->primitive[i] = rh.hit.primID;
    hits->t[i] = rh.ray.tfar;
    hits->u[i] = rh.hit.u;
    hits->v[i] = rh.hit.v;
    hits->ng_x[i] = rh.hit.Ng_x;
    hits->ng_y[i] = rh.hit.Ng_y;
    hits->ng_z[i] = rh.hit.Ng_z;
  }
}

template <int K>
void occluded_packets(RTCScene scene, const RayBatch& rays, size_t begin, size_t end,
                      std::vector<uint8_t>* occluded) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t first = begin; first < end; first += K) {
    const size_t n = std::min(end - first, size_t(K));
    alignas(64) int valid[K];
    alignas(64) typename EmbreePacket<K>::Ray r;
    for (int lane = 0; lane < K; ++lane) {
      const size_t i = first + size_t(lane);
      const bool on = size_t(lane) < n && rays.active[i];
      valid[lane] = on ? -1 : 0;
      load_lane(r, lane, rays, on ? i : first);
      if (!on) r.tfar[lane] = -1.0f;
    }
    EmbreePacket<K>::occluded(valid, scene, &context, &r);
    for (size_t lane = 0; lane < n; ++lane) {
      (*occluded)[first + lane] = valid[lane] && r.tfar[lane] < 0.0f ? 1 : 0;
    }
  }
}

void occluded_single(RTCScene scene, const RayBatch& rays, size_t begin, size_t end,
                     std::vector<uint8_t>* occluded) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = begin; i < end; ++i) {
    (*occluded)[i] = 0;
    if (!rays.active[i]) continue;
    RTCRay r;
    r.org_x = rays.ox[i];
    r.org_y = rays.oy[i];
    r.org_z = rays.oz[i];
    r.dir_x = rays.dx[i];
    r.dir_y = rays.dy[i];
    r.dir_z = rays.dz[i];
    r.tnear = 0.0f;
    r.tfar = rays.t_max[i];
    r.time = 0.0f;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(scene, &context, &r);
    (*occluded)[i] = r.tfar < 0.0f ? 1 : 0;
  }
}

}  // namespace

void RayBatch::resize(size_t n) {
  for (std::vector<float>* v : {&ox, &oy, &oz, &dx, &dy, &dz, &t_max}) v->resize(n, 0.0f);
  active.resize(n, 0);
}

void RayBatch::set(size_t i, const Ray& ray) {
  ox[i] = ray.o.x;
  oy[i] = ray.o.y;
  oz[i] = ray.o.z;
  dx[i] = ray.d.x;
  dy[i] = ray.d.y;
  dz[i] = ray.d.z;
  t_max[i] = ray.t_max;
  active[i] = 1;
}

void HitBatch::resize(size_t n) {
  geometry.resize(n, RTC_INVALID_GEOMETRY_ID);
  instance.resize(n, RTC_INVALID_GEOMETRY_ID);
  primitive.resize(n, RTC_INVALID_GEOMETRY_ID);
  for (std::vector<float>* f : {&t, &u, &v, &ng_x, &ng_y, &ng_z}) f->resize(n, 0.0f);
}

PacketTracer::PacketTracer(RTCScene scene, int width) : scene_(scene), width_(width) {
  if (width != 1 && width != 4 && width != 8 && width != 16) {
    throw std::invalid_argument("packet width " + std::to_string(width) + " is not 1, 4, 8 or 16");
  }
}

int PacketTracer::native_width(RTCDevice device) {
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return 16;
  if (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) return 8;
  return 4;
}

void PacketTracer::intersect(const RayBatch& rays, size_t begin, size_t end, HitBatch* hits) const {
  switch (width_) {
    case 1: intersect_single(scene_, rays, begin, end, hits); break;
    case 4: intersect_packets<4>(scene_, rays, begin, end, hits); break;
    case 8: intersect_packets<8>(scene_, rays, begin, end, hits); break;
    default: intersect_packets<16>(scene_, rays, begin, end, hits); break;
  }
}

void PacketTracer::occluded(const RayBatch& rays, size_t begin, size_t end,
                            std::vector<uint8_t>* occluded) const {
  switch (width_) {
    case 1: occluded_single(scene_, rays, begin, end, occluded); break;
    case 4: occluded_packets<4>(scene_, rays, begin, end, occluded); break;
    case 8: occluded_packets<8>(scene_, rays, begin, end, occluded); break;
    default: occluded_packets<16>(scene_, rays, begin, end, occluded); break;
  }
}

}  // namespace tessera
