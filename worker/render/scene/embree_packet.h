// Embree's ray-packet types and queries by packet width K (4, 8, 16), for code templated on the
// width: PacketTracer (packet_tracer.h) and the wavefront integrator, which fills the packets
// straight from its paths (wavefront/wavefront_integrator.h).
#pragma once

#include <embree3/rtcore.h>

namespace tessera {

template <int K>
struct EmbreePacket;

template <>
struct EmbreePacket<4> {
  using RayHit = RTCRayHit4;
  using Ray = RTCRay4;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect4(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded4(valid, s, c, r);
  }
};

template <>
struct EmbreePacket<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded8(valid, s, c, r);
  }
};

template <>
struct EmbreePacket<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded16(valid, s, c, r);
  }
};

}  // namespace tessera
