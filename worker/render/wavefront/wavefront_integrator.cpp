#include "render/wavefront/wavefront_integrator.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "render/embree_packet.h"
#include "render/path_vertex.h"

namespace tessera {
namespace {

/// One bounce's packets of width K, filled straight from the paths and read back by lane: the
/// closest-hit packet, and the shadow packet that the bounce's shadow rays fill in order and
/// that is traced each time it is full (and once more for the rest at the end of the bounce).
/// Which rays share a packet is therefore the same as cutting the bounce's live paths, and
/// its shadow rays, into runs of K in order: a function of the group alone.
template <int K>
struct Packets {
  alignas(64) typename EmbreePacket<K>::RayHit rayhit;
  alignas(64) typename EmbreePacket<K>::Ray shadow;
  alignas(64) int valid[K];
  alignas(64) int shadow_valid[K];
  uint32_t shadow_path[K];
  glm::dvec3 shadow_contribution[K];
  int shadows = 0;

  /// Every lane holds finite data from the start (Embree may read switched-off lanes before
  /// masking them); the fields a query never writes (tnear 0, time, mask, id, flags, as for
  /// TraceableScene's single rays) are set here once.
  Packets() {
    for (int lane = 0; lane < K; ++lane) {
      init_lane(rayhit.ray, lane);
      init_lane(shadow, lane);
      valid[lane] = shadow_valid[lane] = 0;
    }
  }

  template <typename R>
  static void init_lane(R& r, int lane) {
    r.org_x[lane] = r.org_y[lane] = r.org_z[lane] = 0.0f;
    r.dir_x[lane] = r.dir_y[lane] = r.dir_z[lane] = 0.0f;
    r.tnear[lane] = 0.0f;
    r.tfar[lane] = -1.0f;
    r.time[lane] = 0.0f;
    r.mask[lane] = 0xffffffffu;
    r.id[lane] = 0;
    r.flags[lane] = 0;
  }

  template <typename R>
  static void load(R& r, int lane, glm::vec3 o, glm::vec3 d, float t_max) {
    r.org_x[lane] = o.x;
    r.org_y[lane] = o.y;
    r.org_z[lane] = o.z;
    r.dir_x[lane] = d.x;
    r.dir_y[lane] = d.y;
    r.dir_z[lane] = d.z;
    r.tfar[lane] = t_max;
  }
};

}  // namespace

WavefrontIntegrator::WavefrontIntegrator(const TraceableScene& scene, int max_depth, int packet_width)
    : scene_(scene), max_depth_(max_depth), width_(packet_width) {
  if (width_ != 1 && width_ != 4 && width_ != 8 && width_ != 16) {
    throw std::invalid_argument("packet width " + std::to_string(width_) + " is not 1, 4, 8 or 16");
  }
}

void WavefrontIntegrator::trace(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers,
                                PathCounters& counters, Workspace& workspace) const {
  if (samplers.size() != paths.size()) {
    throw std::invalid_argument("WavefrontIntegrator::trace: " + std::to_string(paths.size()) + " paths but " +
                                std::to_string(samplers.size()) + " samplers");
  }
  switch (width_) {
    case 1: trace_single(paths, samplers, counters, workspace); break;
    case 4: trace_packets<4>(paths, samplers, counters, workspace); break;
    case 8: trace_packets<8>(paths, samplers, counters, workspace); break;
    default: trace_packets<16>(paths, samplers, counters, workspace); break;
  }
}

void WavefrontIntegrator::trace_single(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers,
                                       PathCounters& counters, Workspace& workspace) const {
  std::vector<uint32_t>& live = workspace.live;
  std::vector<uint32_t>& next = workspace.next;
  live.resize(paths.size());
  for (size_t i = 0; i < live.size(); ++i) live[i] = uint32_t(i);
  while (!live.empty()) {
    next.clear();
    counters.rays += live.size();
    for (const uint32_t i : live) {
      PathState& path = paths[i];
      Hit hit;
      const bool found = scene_.intersect(path.ray, &hit);
      ShadowQuery shadow;
      bool has_shadow;
      if (path_vertex(scene_, max_depth_, samplers[i], path, found ? &hit : nullptr, &shadow, &has_shadow)) {
        next.push_back(i);
      }
      if (has_shadow) {
        ++counters.shadow_rays;
        if (!scene_.occluded(shadow.o, shadow.d, shadow.t_max)) path.radiance += shadow.contribution;
      }
    }
    live.swap(next);
  }
}

template <int K>
void WavefrontIntegrator::trace_packets(std::vector<PathState>& paths, std::vector<PixelSampler>& samplers,
                                        PathCounters& counters, Workspace& workspace) const {
  using Packet = EmbreePacket<K>;
  const RTCScene embree = scene_.embree_scene();
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  Packets<K> p;
  // Traces the shadow packet's first p.shadows lanes and adds the unblocked contributions.
  const auto flush_shadows = [&] {
    for (int lane = 0; lane < K; ++lane) {
      p.shadow_valid[lane] = lane < p.shadows ? -1 : 0;
      if (lane >= p.shadows) p.shadow.tfar[lane] = -1.0f;
    }
    Packet::occluded(p.shadow_valid, embree, &context, &p.shadow);
    for (int lane = 0; lane < p.shadows; ++lane) {
      if (!(p.shadow.tfar[lane] < 0.0f)) paths[p.shadow_path[lane]].radiance += p.shadow_contribution[lane];
    }
    counters.shadow_rays += uint64_t(p.shadows);
    p.shadows = 0;
  };

  std::vector<uint32_t>& live = workspace.live;
  std::vector<uint32_t>& next = workspace.next;
  live.resize(paths.size());
  for (size_t i = 0; i < live.size(); ++i) live[i] = uint32_t(i);
  while (!live.empty()) {
    const size_t count = live.size();
    counters.rays += count;
    next.clear();
    for (size_t first = 0; first < count; first += K) {
      const int n = int(std::min(count - first, size_t(K)));
      for (int lane = 0; lane < K; ++lane) {
        if (lane < n) {
          const Ray& ray = paths[live[first + size_t(lane)]].ray;
          Packets<K>::load(p.rayhit.ray, lane, ray.o, ray.d, ray.t_max);
          p.valid[lane] = -1;
        } else {
          p.rayhit.ray.tfar[lane] = -1.0f;
          p.valid[lane] = 0;
        }
        p.rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
        p.rayhit.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
      }
      Packet::intersect(p.valid, embree, &context, &p.rayhit);

      for (int lane = 0; lane < n; ++lane) {
        const uint32_t i = live[first + size_t(lane)];
        PathState& path = paths[i];
        Hit hit;
        const uint32_t geometry = p.rayhit.hit.geomID[lane];
        const bool found = geometry != RTC_INVALID_GEOMETRY_ID;
        if (found) {
          scene_.make_hit(path.ray, geometry, p.rayhit.hit.instID[0][lane], p.rayhit.hit.primID[lane],
                          p.rayhit.ray.tfar[lane], p.rayhit.hit.u[lane], p.rayhit.hit.v[lane], &hit);
        }
        ShadowQuery shadow;
        bool has_shadow;
        if (path_vertex(scene_, max_depth_, samplers[i], path, found ? &hit : nullptr, &shadow, &has_shadow)) {
          next.push_back(i);
        }
        if (has_shadow) {
          Packets<K>::load(p.shadow, p.shadows, shadow.o, shadow.d, shadow.t_max);
          p.shadow_path[p.shadows] = i;
          p.shadow_contribution[p.shadows] = shadow.contribution;
          if (++p.shadows == K) flush_shadows();
        }
      }
    }
    // A path's shadow contribution reaches its radiance before its next vertex is shaded.
    if (p.shadows > 0) flush_shadows();
    live.swap(next);
  }
}

}  // namespace tessera
