#include "render/geometry/sdf_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "render/math/float_rounding.h"

namespace tessera {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// a (1 - t) + b t: exactly a at t = 0 and b at t = 1, which makes the interpolant on a face
/// the same bits from both voxels that share it.
double lerp(double a, double b, double t) { return a * (1 - t) + b * t; }

/// Corner values indexed x + 2 y + 4 z at local point w.
double trilerp(const double (&f)[8], const glm::dvec3& w) {
  const double y0 = lerp(lerp(f[0], f[1], w.x), lerp(f[2], f[3], w.x), w.y);
  const double y1 = lerp(lerp(f[4], f[5], w.x), lerp(f[6], f[7], w.x), w.y);
  return lerp(y0, y1, w.z);
}

/// Cubic c0 + c1 s + c2 s^2 + c3 s^3.
struct Cubic {
  double c0 = 0, c1 = 0, c2 = 0, c3 = 0;
  double operator()(double s) const { return ((c3 * s + c2) * s + c1) * s + c0; }
  double slope(double s) const { return (3 * c3 * s + 2 * c2) * s + c1; }
};

/// The interpolant along a + s b (local voxel coordinates), with c0 = f_a (the face value).
Cubic along_ray(const double (&f)[8], const glm::dvec3& a, const glm::dvec3& b, double f_a) {
  // f = k0 + k1 x + k2 y + k4 z + k3 xy + k5 xz + k6 yz + k7 xyz
  const double k1 = f[1] - f[0], k2 = f[2] - f[0], k4 = f[4] - f[0];
  const double k3 = f[3] - f[2] - f[1] + f[0];
  const double k5 = f[5] - f[4] - f[1] + f[0];
  const double k6 = f[6] - f[4] - f[2] + f[0];
  const double k7 = f[7] - f[6] - f[5] + f[4] - f[3] + f[2] + f[1] - f[0];
  Cubic c;
  c.c0 = f_a;
  c.c1 = k1 * b.x + k2 * b.y + k4 * b.z + k3 * (a.x * b.y + a.y * b.x) + k5 * (a.x * b.z + a.z * b.x) +
         k6 * (a.y * b.z + a.z * b.y) + k7 * (a.x * a.y * b.z + a.x * b.y * a.z + b.x * a.y * a.z);
  c.c2 = k3 * b.x * b.y + k5 * b.x * b.z + k6 * b.y * b.z +
         k7 * (a.x * b.y * b.z + b.x * a.y * b.z + b.x * b.y * a.z);
  c.c3 = k7 * b.x * b.y * b.z;
  return c;
}

bool same_sign(double a, double b) { return (a > 0 && b > 0) || (a < 0 && b < 0); }

/// A root of `c` in [lo, hi] where f_lo, f_hi (the cubic's values there, or the exact face
/// values at the ends) do not have the same sign: Newton's method, falling back to bisection
/// whenever a step leaves the bracket.
double refine_root(const Cubic& c, double lo, double hi, double f_lo, double f_hi, double scale) {
  if (f_lo == 0) return lo;
  if (f_hi == 0) return hi;
  double s = lo + (hi - lo) * (f_lo / (f_lo - f_hi));
  if (!(s >= lo && s <= hi)) s = 0.5 * (lo + hi);
  const double tolerance = 4 * std::numeric_limits<double>::epsilon() * scale;
  for (int i = 0; i < 100; ++i) {
    const double fs = c(s);
    if (fs == 0) return s;
    if (same_sign(fs, f_lo)) {
      lo = s;
      f_lo = fs;
    } else {
      hi = s;
    }
    double next = s - fs / c.slope(s);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool done = std::abs(next - s) <= tolerance || hi - lo <= tolerance;
    s = next;
    if (done) break;
  }
  return s;
}

/// The box of the surface within a voxel with corner values f, in local [0, 1]^3 coordinates:
/// corners on it and crossings of the edges. Empty (lo > hi) when nothing.
void tight_box(const double (&f)[8], glm::dvec3* lo, glm::dvec3* hi) {
  *lo = glm::dvec3(kInf);
  *hi = glm::dvec3(-kInf);
  auto corner = [](uint32_t i) { return glm::dvec3(i & 1, (i >> 1) & 1, i >> 2); };
  for (uint32_t i = 0; i < 8; ++i) {
    if (f[i] == 0) {
      *lo = glm::min(*lo, corner(i));
      *hi = glm::max(*hi, corner(i));
    }
    for (uint32_t axis = 0; axis < 3; ++axis) {
      if (i & (1u << axis)) continue;
      const uint32_t j = i | (1u << axis);
      if (f[i] == f[j] || same_sign(f[i], f[j])) continue;
      glm::dvec3 p = corner(i);
      p[axis] = std::clamp(f[i] / (f[i] - f[j]), 0.0, 1.0);
      *lo = glm::min(*lo, p);
      *hi = glm::max(*hi, p);
    }
  }
}

}  // namespace

SdfGrid::SdfGrid(const Shape& shape)
    : n_(shape.sdf_resolution), values_(shape.sdf_values), normals_(shape.sdf_normals) {
  resolution_ = glm::dvec3(n_) - 1.0;
  glm::dmat4 grid_from_object(1.0);
  for (int a = 0; a < 3; ++a) grid_from_object[a][a] = resolution_[a];
  shape_from_grid_ = shape.to_world * glm::inverse(grid_from_object);
  grid_from_shape_ = glm::inverse(shape_from_grid_);
  normal_to_shape_ = glm::transpose(glm::inverse(glm::dmat3(shape.to_world)));

  // Surface voxels, grouped by brick.
  const glm::u32vec3 voxel_count = n_ - 1u;
  const glm::u32vec3 brick_count = (voxel_count + (kBrick - 1)) / kBrick;
  const glm::dmat3 linear(shape_from_grid_);
  // One voxel's extent in the shape's space along each axis.
  const glm::dvec3 voxel_extent = glm::abs(linear[0]) + glm::abs(linear[1]) + glm::abs(linear[2]);
  for (uint32_t bz = 0; bz < brick_count.z; ++bz) {
    for (uint32_t by = 0; by < brick_count.y; ++by) {
      for (uint32_t bx = 0; bx < brick_count.x; ++bx) {
        Brick brick{uint32_t(voxels_.size()), 0};
        glm::dvec3 lo(kInf), hi(-kInf);
        for (uint32_t z = bz * kBrick; z < std::min((bz + 1) * kBrick, voxel_count.z); ++z) {
          for (uint32_t y = by * kBrick; y < std::min((by + 1) * kBrick, voxel_count.y); ++y) {
            for (uint32_t x = bx * kBrick; x < std::min((bx + 1) * kBrick, voxel_count.x); ++x) {
              double f[8];
              for (uint32_t c = 0; c < 8; ++c) f[c] = value(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
              glm::dvec3 box_lo, box_hi;
              tight_box(f, &box_lo, &box_hi);
              if (!(box_lo.x <= box_hi.x)) continue;  // no corner >= 0 with one <= 0
              voxels_.emplace_back(x, y, z);
              ++brick.count;
              for (uint32_t c = 0; c < 8; ++c) {
                const glm::dvec3 local(c & 1 ? box_hi.x : box_lo.x, c & 2 ? box_hi.y : box_lo.y,
                                       c & 4 ? box_hi.z : box_lo.z);
                const glm::dvec3 p(shape_from_grid_ * glm::dvec4(glm::dvec3(x, y, z) + local, 1.0));
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
              }
            }
          }
        }
        if (brick.count == 0) continue;
        const glm::dvec3 pad =
            1e-3 * voxel_extent + 8.0 * double(std::numeric_limits<float>::epsilon()) * glm::max(glm::abs(lo), glm::abs(hi));
        lo -= pad;
        hi += pad;
        RTCBounds b{};
        b.lower_x = round_down(lo.x);
        b.lower_y = round_down(lo.y);
        b.lower_z = round_down(lo.z);
        b.upper_x = round_up(hi.x);
        b.upper_y = round_up(hi.y);
        b.upper_z = round_up(hi.z);
        bricks_.push_back(brick);
        bounds_.push_back(b);
      }
    }
  }
}

float SdfGrid::value(int64_t x, int64_t y, int64_t z) const {
  x = std::clamp<int64_t>(x, 0, n_.x - 1);
  y = std::clamp<int64_t>(y, 0, n_.y - 1);
  z = std::clamp<int64_t>(z, 0, n_.z - 1);
  return values_[(size_t(z) * n_.y + size_t(y)) * n_.x + size_t(x)];
}

double SdfGrid::eval(const glm::u32vec3& cell, const glm::dvec3& w, glm::dvec3* gradient) const {
  double f[8];
  for (uint32_t c = 0; c < 8; ++c) f[c] = value(cell.x + (c & 1), cell.y + ((c >> 1) & 1), cell.z + (c >> 2));
  if (gradient) {
    // Each partial derivative is the bilinear interpolant of the differences along its axis.
    auto bilerp = [](double a, double b, double c, double d, double u, double v) {
      return lerp(lerp(a, b, u), lerp(c, d, u), v);
    };
    gradient->x = bilerp(f[1] - f[0], f[3] - f[2], f[5] - f[4], f[7] - f[6], w.y, w.z);
    gradient->y = bilerp(f[2] - f[0], f[3] - f[1], f[6] - f[4], f[7] - f[5], w.x, w.z);
    gradient->z = bilerp(f[4] - f[0], f[5] - f[1], f[6] - f[2], f[7] - f[3], w.x, w.y);
  }
  return trilerp(f, w);
}

double SdfGrid::intersect_voxel(const glm::u32vec3& cell, const glm::dvec3& og, const glm::dvec3& dg,
                                double t_near, double t_far) const {
  // Slabs of the voxel, in grid space (its faces are at integer coordinates there).
  double t_in = -kInf, t_out = kInf;
  glm::dvec3 slab_in, slab_out;
  for (int a = 0; a < 3; ++a) {
    const double lo = double(cell[a]), hi = lo + 1;
    if (dg[a] == 0) {
      if (og[a] < lo || og[a] > hi) return -1;
      slab_in[a] = -kInf;
      slab_out[a] = kInf;
    } else {
      const double t0 = (lo - og[a]) / dg[a], t1 = (hi - og[a]) / dg[a];
      slab_in[a] = std::min(t0, t1);
      slab_out[a] = std::max(t0, t1);
    }
    t_in = std::max(t_in, slab_in[a]);
    t_out = std::min(t_out, slab_out[a]);
  }
  if (t_out < t_near || t_in > t_out || t_in > t_far) return -1;
  const bool starts_inside = t_in < t_near;
  if (starts_inside) t_in = t_near;

  // End points in local coordinates, a crossed face's coordinate set to exactly 0 or 1.
  const glm::dvec3 corner(cell);
  glm::dvec3 a_in, a_out;
  for (int k = 0; k < 3; ++k) {
    a_in[k] = std::clamp((og[k] - corner[k]) + t_in * dg[k], 0.0, 1.0);
    a_out[k] = std::clamp((og[k] - corner[k]) + t_out * dg[k], 0.0, 1.0);
    if (!starts_inside && slab_in[k] == t_in) a_in[k] = dg[k] > 0 ? 0.0 : 1.0;
    if (slab_out[k] == t_out) a_out[k] = dg[k] > 0 ? 1.0 : 0.0;
  }
  double f[8];
  for (uint32_t c = 0; c < 8; ++c) f[c] = value(cell.x + (c & 1), cell.y + ((c >> 1) & 1), cell.z + (c >> 2));
  const double f_in = trilerp(f, a_in), f_out = trilerp(f, a_out);
  const double length = t_out - t_in;
  const Cubic cubic = along_ray(f, a_in, dg, f_in);

  // Split [0, length] where the cubic turns, so that each piece is monotonic.
  double splits[4] = {0, length, length, length};
  int count = 1;
  const double qa = 3 * cubic.c3, qb = 2 * cubic.c2, qc = cubic.c1;
  double roots[2];
  int root_count = 0;
  if (qa == 0) {
    if (qb != 0) roots[root_count++] = -qc / qb;
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      roots[root_count++] = q / qa;
      if (q != 0) roots[root_count++] = qc / q;
    }
  }
  if (root_count == 2 && roots[0] > roots[1]) std::swap(roots[0], roots[1]);
  for (int i = 0; i < root_count; ++i) {
    if (roots[i] > 0 && roots[i] < length) splits[count++] = roots[i];
  }
  splits[count] = length;

  const double scale = std::abs(t_in) + std::abs(length);
  double s_lo = 0, f_lo = f_in;
  for (int i = 1; i <= count; ++i) {
    const double s_hi = splits[i];
    const double f_hi = i == count ? f_out : cubic(s_hi);
    if (!same_sign(f_lo, f_hi)) {
      const double t = t_in + refine_root(cubic, s_lo, s_hi, f_lo, f_hi, scale);
      if (t > t_near && t <= t_far) return t;
    }
    s_lo = s_hi;
    f_lo = f_hi;
  }
  return -1;
}

double SdfGrid::intersect(uint32_t primitive, const glm::dvec3& o, const glm::dvec3& d, double t_near,
                          double t_far, uint32_t* voxel) const {
  const glm::dvec3 og(grid_from_shape_ * glm::dvec4(o, 1.0));
  const glm::dvec3 dg(glm::dmat3(grid_from_shape_) * d);
  const Brick& brick = bricks_[primitive];
  double best = -1;
  for (uint32_t i = 0; i < brick.count; ++i) {
    const double t = intersect_voxel(voxels_[brick.first + i], og, dg, t_near, best >= 0 ? best : t_far);
    if (t >= 0 && (best < 0 || t < best)) {
      best = t;
      *voxel = i;
    }
  }
  return best;
}

glm::dvec3 SdfGrid::smooth_gradient(const glm::dvec3& pg) const {
  // Mitsuba's smooth normal (Hansson-Söderlund, Evans and Akenine-Möller, "Ray Tracing of
  // Signed Distance Function Grids", JCGT 2022): the normalised gradients of the 8 voxels
  // around the grid vertex nearest to pg, blended trilinearly by pg's place between their
  // centres. A voxel's gradient along an axis is the difference of the interpolant on its two
  // sample planes along that axis, at pg's position along the other two.
  const glm::ivec3 n(n_);
  glm::ivec3 v, cell;
  glm::dvec3 uvw, w;
  for (int a = 0; a < 3; ++a) {
    v[a] = int(std::lround(pg[a])) - 1;
    uvw[a] = pg[a] - v[a] - 0.5;
    cell[a] = std::clamp(int(std::floor(pg[a])), 0, n[a] - 2);
    w[a] = pg[a] - cell[a];
  }
  auto plane = [&](int a, int q) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    double f[4];
    for (int i = 0; i < 4; ++i) {
      glm::ivec3 idx;
      idx[a] = q;
      idx[b] = cell[b] + (i & 1);
      idx[c] = cell[c] + (i >> 1);
      f[i] = value(idx.x, idx.y, idx.z);
    }
    return lerp(lerp(f[0], f[1], w[b]), lerp(f[2], f[3], w[b]), w[c]);
  };
  glm::dvec3 d_lower, d_upper;  // gradients of the voxels at v and v + 1 along each axis
  for (int a = 0; a < 3; ++a) {
    // pg lies in the upper of the two voxels along a when its cell is v + 1.
    const bool upper = cell[a] != v[a];
    const double g0 = plane(a, cell[a]), g1 = plane(a, cell[a] + 1);
    const double gq = plane(a, cell[a] + (upper ? -1 : 2));
    const double across = g1 - g0, beside = upper ? g0 - gq : gq - g1;
    d_lower[a] = (upper ? beside : across) * resolution_[a];
    d_upper[a] = (upper ? across : beside) * resolution_[a];
  }
  glm::bvec3 inside;
  for (int a = 0; a < 3; ++a) {
    inside[a] = v[a] >= 0;
    if (!inside[a]) uvw[a] = 1;  // voxels below the grid get weight 0
  }
  auto unit = [](const glm::dvec3& g) {
    const double len = glm::length(g);
    return len > 0 ? g / len : glm::dvec3(0.0);
  };
  glm::dvec3 corner_n[8];
  for (int i = 0; i < 8; ++i) {
    const glm::bvec3 hi((i & 1) != 0, (i & 2) != 0, (i & 4) != 0);
    const bool valid = (hi.x || inside.x) && (hi.y || inside.y) && (hi.z || inside.z);
    const glm::dvec3 g(hi.x ? d_upper.x : d_lower.x, hi.y ? d_upper.y : d_lower.y, hi.z ? d_upper.z : d_lower.z);
    corner_n[i] = valid ? unit(g) : glm::dvec3(0.0);
  }
  auto mix = [](const glm::dvec3& a, const glm::dvec3& b, double t) { return a * (1 - t) + b * t; };
  const glm::dvec3 y0 = mix(mix(corner_n[0], corner_n[1], uvw.x), mix(corner_n[2], corner_n[3], uvw.x), uvw.y);
  const glm::dvec3 y1 = mix(mix(corner_n[4], corner_n[5], uvw.x), mix(corner_n[6], corner_n[7], uvw.x), uvw.y);
  return mix(y0, y1, uvw.z);
}

SdfGridHit SdfGrid::hit(uint32_t primitive, uint32_t voxel, const glm::dvec3& o, const glm::dvec3& d,
                        double t) const {
  const Brick& brick = bricks_[primitive];
  const glm::u32vec3 cell = voxels_[brick.first + std::min(voxel, brick.count - 1)];
  const glm::dvec3 corner(cell);
  const glm::dvec3 pg(grid_from_shape_ * glm::dvec4(o + t * d, 1.0));
  // Project the point onto the surface along the gradient (within the voxel), so that its
  // error no longer grows with the distance the ray travelled.
  glm::dvec3 w = glm::clamp(pg - corner, 0.0, 1.0);
  glm::dvec3 g;
  double f = eval(cell, w, &g);
  for (int i = 0; i < 4 && f != 0; ++i) {
    const double gg = glm::dot(g, g);
    if (!(gg > 0)) break;
    const glm::dvec3 next = glm::clamp(w - (f / gg) * g, 0.0, 1.0);
    glm::dvec3 g_next;
    const double f_next = eval(cell, next, &g_next);
    if (!(std::abs(f_next) < std::abs(f))) break;
    w = next;
    f = f_next;
    g = g_next;
  }
  const double g_len = glm::length(g);
  // Distance left to the surface, in grid units (a voxel when the gradient vanishes).
  const double residual = g_len > 0 ? std::min(std::abs(f) / g_len, 1.0) : (f == 0 ? 0.0 : 1.0);
  const glm::dvec3 p = glm::dvec3(shape_from_grid_ * glm::dvec4(corner + w, 1.0));
  SdfGridHit out;
  out.p = glm::vec3(p);
  const glm::dmat3 linear(shape_from_grid_);
  const glm::dvec3 reach = glm::abs(linear[0]) + glm::abs(linear[1]) + glm::abs(linear[2]);
  // Rounding to float (half an ulp), the double arithmetic before it, and the distance left.
  out.p_error = glm::vec3(2.0 * double(std::numeric_limits<float>::epsilon()) * glm::abs(p) + reach * residual);
  const glm::dvec3 n_geo = normal_to_shape_ * (g * resolution_);
  const double n_len = glm::length(n_geo);
  const glm::dvec3 ng = n_len > 0 && std::isfinite(n_len) ? n_geo / n_len : -glm::normalize(d);
  out.ng = glm::vec3(ng);
  out.ns = out.ng;
  if (normals_ == SdfNormals::smooth) {
    const glm::dvec3 ns = normal_to_shape_ * smooth_gradient(corner + w);
    const double len = glm::length(ns);
    if (len > 0 && std::isfinite(len)) out.ns = glm::vec3(ns / len);
  }
  return out;
}

namespace {

void sdf_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
  *args->bounds_o = grid->bounds(args->primID);
}

// Embree calls these with N = 1 for rtcIntersect1 and 4, 8 or 16 for packets; each lane is
// solved alone with the same double-precision arithmetic whatever N is.
void sdf_intersect(const RTCIntersectFunctionNArguments* args) {
  const auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i]) continue;
    const glm::dvec3 o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
    const glm::dvec3 d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
    float& tfar = RTCRayN_tfar(rays, N, i);
    uint32_t voxel = 0;
    const double t = grid->intersect(args->primID, o, d, RTCRayN_tnear(rays, N, i), tfar, &voxel);
    if (!(t >= 0)) continue;
    const float tf = float(t);
    if (!(tf <= tfar)) continue;
    tfar = tf;
    // Embree's geometric normal is not read (TraceableScene computes the hit's normals).
    RTCHitN_Ng_x(hits, N, i) = -float(d.x);
    RTCHitN_Ng_y(hits, N, i) = -float(d.y);
    RTCHitN_Ng_z(hits, N, i) = -float(d.z);
    RTCHitN_u(hits, N, i) = float(voxel);
    RTCHitN_v(hits, N, i) = 0;
    RTCHitN_primID(hits, N, i) = args->primID;
    RTCHitN_geomID(hits, N, i) = args->geomID;
    RTCHitN_instID(hits, N, i, 0) = args->context->instID[0];
  }
}

void sdf_occluded(const RTCOccludedFunctionNArguments* args) {
  const auto* grid = static_cast<const SdfGrid*>(args->geometryUserPtr);
  const unsigned N = args->N;
  RTCRayN* rays = args->ray;
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i]) continue;
    const glm::dvec3 o(RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i));
    const glm::dvec3 d(RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i));
    float& tfar = RTCRayN_tfar(rays, N, i);
    uint32_t voxel = 0;
    const double t = grid->intersect(args->primID, o, d, RTCRayN_tnear(rays, N, i), tfar, &voxel);
    if (t >= 0 && float(t) <= tfar) tfar = -INFINITY;
  }
}

}  // namespace

void attach_sdf_grid_callbacks(RTCGeometry geometry, const SdfGrid* grid) {
  rtcSetGeometryUserPrimitiveCount(geometry, grid->primitive_count());
  rtcSetGeometryUserData(geometry, const_cast<SdfGrid*>(grid));
  rtcSetGeometryBoundsFunction(geometry, sdf_bounds, nullptr);
  rtcSetGeometryIntersectFunction(geometry, sdf_intersect);
  rtcSetGeometryOccludedFunction(geometry, sdf_occluded);
}

}  // namespace tessera
