// Participating media: the phase function's sampling and normalisation, free flights and
// transmittance against closed forms, furnaces and extremes rendered through the volumetric
// path tracer (integrators/volpath.h), and its determinism.
#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "render/bsdf/chi_square.h"
#include "render/media/medium.h"
#include "render/media/phase.h"
#include "render/renderer.h"
#include "render/test_statistics.h"
#include "render/testing/test_scenes.h"
#include "scene/volume_grid_file.h"

namespace tessera {
namespace {

using test::Estimate;

// ------------------------------------------------------------------------- phase functions

/// A phase function seen as a BSDF by the chi-square test: wo is ignored, the path arrives
/// along a fixed direction d.
struct PhaseAsBsdf {
  PhaseFunction phase;
  glm::vec3 d;
  std::optional<BsdfSample> sample(glm::vec3, float, glm::vec2 u) const {
    const PhaseSample s = phase.sample(d, u);
    BsdfSample b;
    b.wi = s.wi;
    b.pdf = s.pdf;
    b.weight = glm::vec3(s.weight);
    return b;
  }
  float pdf(glm::vec3, glm::vec3 wi) const { return phase.eval(d, wi); }
};

TEST(Phase, SamplingMatchesTheDensity) {
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.2f, 0.9f));
  const float gs[] = {0.0f, 0.0005f, 0.3f, -0.6f, 0.9f, -0.99f, 0.99f};
  for (float g : gs) {
    SCOPED_TRACE(g);
    // At |g| = 0.99 the density peaks at 1e4 / sr within a bin or two, where the harness's
    // 16 x 16 midpoint rule per bin is up to 4 % off (chi-square ~60 from integration alone at
    // 200,000 samples, measured against a 64 x 64 rule): fewer samples there keep the test
    // about the sampling.
    const int samples = std::abs(g) > 0.95f ? 20000 : 200000;
    const test::ChiSquareResult r =
        test::chi_square_test(PhaseAsBsdf{PhaseFunction(g), d}, glm::vec3(0, 0, 1), 7, samples, 1e-3 / 7);
    EXPECT_TRUE(r.passed) << r.message;
  }
}

TEST(Phase, DensityIsNormalisedWithMeanCosineG) {
  for (float g : {0.0f, 0.5f, -0.8f, 0.95f, -0.99f}) {
    // Over cos theta in [-1, 1], times 2 pi: fine steps, since g = 0.99 peaks at 1e4 / sr.
    const int n = 2000000;
    double total = 0, mean_cos = 0;
    for (int i = 0; i < n; ++i) {
      const double c = -1 + (i + 0.5) * 2.0 / n;
      const double p = 2 * M_PI * hg_density(float(c), g) * 2.0 / n;
      total += p;
      mean_cos += c * p;
    }
    EXPECT_NEAR(total, 1.0, 2e-3) << g;
    EXPECT_NEAR(mean_cos, g, 2e-3) << g;
  }
  EXPECT_FLOAT_EQ(hg_density(0.3f, 0.0f), float(0.25 / M_PI));
}

// ------------------------------------------------------------------------- free flights

RenderMedium homogeneous_medium(glm::vec3 sigma_t, glm::vec3 albedo) {
  Medium m;
  m.sigma_t.value = glm::dvec3(sigma_t);
  m.albedo.value = glm::dvec3(albedo);
  return make_render_medium(m, {});
}

/// A heterogeneous medium over [0, 1]^3 whose sigma_t grid (2 x 1 x 1 voxels... 1 channel)
/// holds `values` along x, times `scale`.
struct GridMedium {
  std::vector<Texture> textures;
  std::unique_ptr<TextureSet> set;
  RenderMedium medium;
};

GridMedium grid_medium(std::vector<float> values_x, double scale, glm::vec3 albedo) {
  GridMedium g;
  auto grid = std::make_shared<VolumeGridFile>();
  grid->resolution = {uint32_t(values_x.size()), 1, 1};
  grid->channels = 1;
  grid->values = values_x;
  Texture t;
  t.name = "density";
  t.kind = TextureKind::volume;
  t.grid = grid;
  t.file = "density.vol";
  t.filter = TextureFilter::bilinear;
  t.wrap = TextureWrap::clamp;
  g.textures.push_back(t);
  g.set = std::make_unique<TextureSet>(g.textures, FileReader{});
  Medium m;
  m.kind = MediumKind::heterogeneous;
  m.sigma_t = {glm::dvec3(1.0), 0};
  m.albedo.value = glm::dvec3(albedo);
  m.scale = scale;
  g.medium = make_render_medium(m, g.textures);
  return g;
}

/// Per channel over n flights of length t_max: the mean weight of those that reached the end
/// (expected: the transmittance) and of those that scattered (expected: albedo (1 - Tr)).
struct FlightMeans {
  glm::dvec3 pass{0.0}, scatter{0.0}, pass_se{0.0}, scatter_se{0.0};
};

FlightMeans flight_means(const RenderMedium& m, const TextureSet& textures, glm::vec3 o, glm::vec3 d,
                         float t_max, int n) {
  std::mt19937_64 rng(5);
  glm::dvec3 s1[2] = {glm::dvec3(0.0), glm::dvec3(0.0)}, s2[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  for (int i = 0; i < n; ++i) {
    TrackingStream stream(rng());
    const FreeFlight f = m.sample_flight(o, d, t_max, test::u01(rng), test::u01(rng), stream, textures);
    EXPECT_TRUE(std::isfinite(f.weight.x + f.weight.y + f.weight.z));
    if (f.scattered) {
      EXPECT_TRUE(f.t >= 0 && f.t < t_max) << f.t;
    }
    const int k = f.scattered ? 1 : 0;
    s1[k] += f.weight;
    s2[k] += f.weight * f.weight;
  }
  FlightMeans r;
  for (int k = 0; k < 2; ++k) {
    const glm::dvec3 mean = s1[k] / double(n);
    const glm::dvec3 se = glm::sqrt(glm::max(s2[k] / double(n) - mean * mean, 0.0) / double(n));
    (k ? r.scatter : r.pass) = mean;
    (k ? r.scatter_se : r.pass_se) = se;
  }
  return r;
}

void expect_flights(const FlightMeans& r, glm::dvec3 tr, glm::dvec3 albedo) {
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(r.pass[c], tr[c], test::kSigmas * r.pass_se[c] + 1e-6) << "channel " << c;
    EXPECT_NEAR(r.scatter[c], albedo[c] * (1 - tr[c]), test::kSigmas * r.scatter_se[c] + 1e-6) << "channel " << c;
  }
}

TEST(FreeFlight, HomogeneousRgbIsUnbiasedPerChannel) {
  const TextureSet none;
  const glm::vec3 sigma(1.0f, 5.0f, 0.2f), albedo(0.9f, 0.5f, 0.7f);
  const RenderMedium m = homogeneous_medium(sigma, albedo);
  for (float t : {0.05f, 0.7f, 3.0f}) {
    SCOPED_TRACE(t);
    const FlightMeans r = flight_means(m, none, glm::vec3(0.0f), glm::vec3(0, 0, 1), t, 400000);
    expect_flights(r, homogeneous_transmittance(sigma, t), glm::dvec3(albedo));
  }
  // A channel of zero extinction passes everything, also to infinity, where the others scatter.
  const RenderMedium clear_red = homogeneous_medium({0, 2, 2}, {1, 1, 1});
  const FlightMeans r = flight_means(clear_red, none, glm::vec3(0.0f), glm::vec3(0, 0, 1),
                                     std::numeric_limits<float>::infinity(), 100000);
  EXPECT_NEAR(r.pass.x, 1.0, 5 * r.pass_se.x + 1e-9);
  EXPECT_EQ(r.pass.y, 0.0);
  EXPECT_NEAR(r.scatter.y, 1.0, 5 * r.scatter_se.y + 1e-9);
}

TEST(FreeFlight, HomogeneousDistancesFollowTheBalancePdf) {
  // The sampled distances' histogram against the mean of the channels' densities.
  const glm::vec3 sigma(0.5f, 2.0f, 8.0f);
  const RenderMedium m = homogeneous_medium(sigma, glm::vec3(1.0f));
  const TextureSet none;
  const int n = 300000, bins = 40;
  const double t_max = 4;
  std::vector<double> observed(bins + 1, 0);
  std::mt19937_64 rng(9);
  for (int i = 0; i < n; ++i) {
    TrackingStream stream(0);
    const FreeFlight f = m.sample_flight(glm::vec3(0.0f), glm::vec3(1, 0, 0), float(t_max), test::u01(rng),
                                         test::u01(rng), stream, none);
    observed[f.scattered ? std::min(bins - 1, int(f.t / t_max * bins)) : bins] += 1;
  }
  double chi2 = 0;
  for (int b = 0; b <= bins; ++b) {
    double expected;
    if (b == bins) {
      const glm::dvec3 tr = homogeneous_transmittance(sigma, t_max);
      expected = n * (tr.x + tr.y + tr.z) / 3;
    } else {
      const double a = t_max * b / bins, z = t_max * (b + 1) / bins;
      const glm::dvec3 ta = homogeneous_transmittance(sigma, a), tz = homogeneous_transmittance(sigma, z);
      expected = n * ((ta.x - tz.x) + (ta.y - tz.y) + (ta.z - tz.z)) / 3;  // integral of the pdf
      // ... which the pdf itself must give too (midpoint, fine steps).
      double integral = 0;
      for (int k = 0; k < 1000; ++k) integral += homogeneous_flight_pdf(sigma, a + (k + 0.5) * (z - a) / 1000) * (z - a) / 1000;
      EXPECT_NEAR(integral * n, expected, 1e-4 * expected + 1e-6);
    }
    chi2 += (observed[b] - expected) * (observed[b] - expected) / expected;
  }
  EXPECT_GT(test::gamma_q(bins / 2.0, chi2 / 2.0), 1e-4) << chi2;
}

TEST(FreeFlight, HeterogeneousDeltaTrackingIsUnbiased) {
  // A ramp along x from 0.5 to 3.5 (times 2): Tr over [0, x] = exp(-2 (0.5 x + 1.5 x^2)),
  // with the grid's trilinear interpolation between its two voxel centres (at 0.25 and 0.75;
  // clamped outside them).
  GridMedium g = grid_medium({0.5f, 3.5f}, 2.0, glm::vec3(0.8f, 0.6f, 0.4f));
  EXPECT_FLOAT_EQ(g.medium.majorant, 7.0f);
  auto sigma_at = [](double x) { return 2 * (x < 0.25 ? 0.5 : x > 0.75 ? 3.5 : 0.5 + 3.0 * (x - 0.25) * 2); };
  for (float t : {0.2f, 0.6f, 1.0f}) {
    SCOPED_TRACE(t);
    double tau = 0;
    for (int k = 0; k < 100000; ++k) tau += sigma_at((k + 0.5) * t / 100000) * t / 100000;
    const FlightMeans r = flight_means(g.medium, *g.set, glm::vec3(0.0f, 0.5f, 0.5f), glm::vec3(1, 0, 0), t, 300000);
    expect_flights(r, glm::dvec3(std::exp(-tau)), glm::dvec3(0.8, 0.6, 0.4));
    // Ratio tracking's mean is the same transmittance.
    glm::dvec3 sum(0.0), sum2(0.0);
    std::mt19937_64 rng(3);
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      TrackingStream stream(rng());
      const glm::dvec3 tr = g.medium.transmittance(glm::vec3(0.0f, 0.5f, 0.5f), glm::vec3(1, 0, 0), t, stream, *g.set);
      sum += tr;
      sum2 += tr * tr;
    }
    const double mean = sum.x / n, se = std::sqrt(std::max(0.0, sum2.x / n - mean * mean) / n);
    EXPECT_NEAR(mean, std::exp(-tau), test::kSigmas * se + 1e-9);
  }
  // Outside the grid's [0, 1]^3 the medium is empty.
  TrackingStream stream(1);
  EXPECT_EQ(g.medium.transmittance(glm::vec3(0.0f, 2.0f, 0.5f), glm::vec3(1, 0, 0), 1.0f, stream, *g.set),
            glm::dvec3(1.0));
}

TEST(Transmittance, HomogeneousIsTheClosedForm) {
  const RenderMedium m = homogeneous_medium({0.5f, 2.0f, 0.0f}, glm::vec3(0.5f));
  const TextureSet none;
  TrackingStream stream(0);
  const glm::dvec3 tr = m.transmittance(glm::vec3(0.0f), glm::vec3(0, 1, 0), 1.5f, stream, none);
  EXPECT_DOUBLE_EQ(tr.x, std::exp(-0.75));
  EXPECT_DOUBLE_EQ(tr.y, std::exp(-3.0));
  EXPECT_EQ(tr.z, 1.0);
  const glm::dvec3 far = m.transmittance(glm::vec3(0.0f), glm::vec3(0, 1, 0),
                                         std::numeric_limits<float>::infinity(), stream, none);
  EXPECT_EQ(far, glm::dvec3(0, 0, 1));  // never NaN
}

// ------------------------------------------------------------------------- rendered scenes

/// A sphere of radius 1 at the origin filled with `medium` (its interior), its boundary of
/// `boundary` material, under a constant environment of radiance `le`; the camera at distance
/// `camera_z` looking at the centre (inside the medium when camera_z < 1).
Scene medium_sphere_scene(Medium medium, uint32_t boundary_type, double le, double camera_z) {
  Scene s;
  s.camera.position = {0, 0, camera_z};
  s.camera.look_at = {0, 0, -1};
  s.camera.fov_deg = 30;
  Material b;
  b.name = "boundary";
  if (boundary_type == 0) {  // null: a mask of opacity 0
    b.type = MaterialType::diffuse;
    b.reflectance.value = glm::dvec3(0);
    b.opacity.value = 0;
  } else if (boundary_type == 1) {
    b.type = MaterialType::thin_glass;
  } else {
    b.type = MaterialType::glass;
    b.ior = 1.5;
  }
  s.materials.push_back(b);
  medium.name = "fog";
  s.media.push_back(medium);
  Shape sphere = test::sphere({0, 0, 0}, 1, 0);
  sphere.interior = 0;
  s.shapes.push_back(sphere);
  if (camera_z < 1) s.camera.medium = 0;
  Light env;
  env.kind = LightKind::constant;
  env.value = glm::dvec3(le);
  s.lights.push_back(env);
  return s;
}

Estimate render_medium_mean(const Scene& s, uint32_t spp, int size = 8, int max_depth = -1, Accumulation* out = nullptr) {
  const Renderer renderer(s, test::test_job(size, size, spp, max_depth));
  const Accumulation acc = test::render_batches(renderer, spp, spp);
  EXPECT_TRUE(test::all_finite(acc));
  if (out) *out = acc;
  return test::mean_luminance(acc);
}

Medium fog_medium(glm::dvec3 sigma_t, glm::dvec3 albedo, double g = 0) {
  Medium m;
  m.sigma_t.value = sigma_t;
  m.albedo.value = albedo;
  m.phase = g == 0 ? PhaseKind::isotropic : PhaseKind::hg;
  m.g = g;
  return m;
}

TEST(MediaRender, FurnaceRendersTheEnvironment) {
  // A lossless medium behind a lossless boundary in a uniform environment: every path carries
  // the environment's radiance back, whatever it scatters on.
  struct Case {
    const char* name;
    uint32_t boundary;
    double g;
    double camera_z;
  };
  for (const Case& c : {Case{"null", 0, 0.0, 4.0}, Case{"thin glass", 1, 0.7, 4.0}, Case{"glass", 2, -0.5, 4.0},
                        Case{"null, camera inside", 0, 0.0, 0.3}, Case{"g 0.99", 0, 0.99, 4.0},
                        Case{"g -0.99", 0, -0.99, 4.0}}) {
    SCOPED_TRACE(c.name);
    const Scene s = medium_sphere_scene(fog_medium({2, 0.5, 6}, {1, 1, 1}, c.g), c.boundary, 0.8, c.camera_z);
    const Estimate e = render_medium_mean(s, 1024);
    EXPECT_NEAR(e.mean, 0.8, test::tolerance(e, 0.8));
    // The estimator's own standard error here is 0.003-0.012 (measured; the channels' differing
    // weights and roulette): an error that only adds variance, such as weights that grow
    // without bound, must not pass by widening the tolerance.
    EXPECT_LT(e.se, 0.02) << "standard error " << e.se;
  }
}

TEST(MediaRender, AbsorbingSphereSeenFromItsCentre) {
  // The camera at the centre of a purely absorbing sphere (albedo 0) of radius 1: every ray
  // leaves with exp(-sigma_t) of the environment, per channel. The sampled channel decides
  // nothing here: the balance weights give each channel its own transmittance exactly.
  const glm::dvec3 sigma(0.3, 1.5, 4.0);
  const Scene s = medium_sphere_scene(fog_medium(sigma, {0, 0, 0}), 0, 1.0, 0.0);
  Accumulation acc(TileRect{0, 0, 1, 1});
  render_medium_mean(s, 4096, 4, -1, &acc);
  double r = 0, g = 0, b = 0, n = 0;
  for (size_t i = 0; i < acc.pixels(); ++i) {
    r += acc.rgb[i * 3];
    g += acc.rgb[i * 3 + 1];
    b += acc.rgb[i * 3 + 2];
    n += acc.count[i];
  }
  // Not exact: a path whose sampled channel's flight ends inside is absorbed (weight 0), so
  // each pixel is a mean with noise; 4096 x 16 samples bound it well within 1 %.
  EXPECT_NEAR(r / n, std::exp(-0.3), 0.01);
  EXPECT_NEAR(g / n, std::exp(-1.5), 0.01);
  EXPECT_NEAR(b / n, std::exp(-4.0), 0.004);
}

TEST(MediaRender, Extremes) {
  // sigma_t 0: the medium is vacuum, the null boundary invisible: exactly the environment.
  {
    const Estimate e = render_medium_mean(medium_sphere_scene(fog_medium({0, 0, 0}, {0.5, 0.5, 0.5}), 0, 0.6, 4.0), 16);
    EXPECT_NEAR(e.mean, 0.6, test::tolerance(e, 0.6));
    EXPECT_LT(e.se, 1e-9);
  }
  // sigma_t 1e6, albedo 1 behind a null boundary: a lossless, practically opaque ball still
  // sends the environment back (every path scatters right at the surface and walks out).
  {
    const Estimate e = render_medium_mean(medium_sphere_scene(fog_medium({1e6, 1e6, 1e6}, {1, 1, 1}), 0, 0.6, 4.0), 16);
    EXPECT_NEAR(e.mean, 0.6, test::tolerance(e, 0.6));
  }
  // sigma_t 1e6, albedo 0.5: dark but finite, no NaN (render_medium_mean checks every sample).
  {
    const Estimate e = render_medium_mean(medium_sphere_scene(fog_medium({1e6, 1, 1e6}, {0.5, 0.5, 0.5}), 0, 1.0, 4.0), 16);
    EXPECT_TRUE(std::isfinite(e.mean));
    EXPECT_LT(e.mean, 1.0);
  }
  // max_depth 1: only what the camera sees directly; through the absorbing-free null boundary
  // the environment attenuated by the ball (nothing scatters into view).
  {
    const Estimate e = render_medium_mean(medium_sphere_scene(fog_medium({0, 0, 0}, {1, 1, 1}), 0, 0.5, 4.0), 8, 8, 1);
    EXPECT_NEAR(e.mean, 0.5, test::tolerance(e, 0.5));
  }
}

/// medium_sphere_scene with a heterogeneous medium: a 2 x 2 x 2 grid of `values` (times
/// `scale`) over the sphere's bounding box [-1, 1]^3.
Scene grid_sphere_scene(std::vector<float> values, double scale, double albedo, double le) {
  Medium m;
  m.kind = MediumKind::heterogeneous;
  m.sigma_t = {glm::dvec3(1.0), 0};
  m.albedo.value = glm::dvec3(albedo);
  m.scale = scale;
  Scene s = medium_sphere_scene(m, 0, le, 4.0);
  auto grid = std::make_shared<VolumeGridFile>();
  grid->resolution = {2, 2, 2};
  grid->channels = 1;
  grid->values = std::move(values);
  Texture t;
  t.name = "density";
  t.kind = TextureKind::volume;
  t.file = "density.vol";
  t.grid = grid;
  t.wrap = TextureWrap::clamp;
  t.volume_to_world = glm::dmat4(2.0);  // [0, 1]^3 -> [-1, 1]^3
  t.volume_to_world[3] = glm::dvec4(-1, -1, -1, 1);
  s.textures.push_back(t);
  return s;
}

TEST(MediaRender, HeterogeneousFurnaceAndAnEmptyGrid) {
  // Delta tracking through the whole integrator: a lossless, varying medium returns the
  // environment.
  {
    const Estimate e = render_medium_mean(grid_sphere_scene({0, 1, 2, 3, 4, 5, 6, 7}, 1.0, 1.0, 0.8), 1024);
    EXPECT_NEAR(e.mean, 0.8, test::tolerance(e, 0.8));
    EXPECT_LT(e.se, 0.02) << "standard error " << e.se;
  }
  // A medium with nothing in it (a grid of zeros, majorant 0): the environment exactly.
  {
    const Estimate e = render_medium_mean(grid_sphere_scene({0, 0, 0, 0, 0, 0, 0, 0}, 5.0, 0.5, 0.7), 16);
    EXPECT_NEAR(e.mean, 0.7, test::tolerance(e, 0.7));
    EXPECT_LT(e.se, 1e-9);
  }
  // An absorbing grid (albedo 0) is darker than the environment, never NaN.
  {
    const Estimate e = render_medium_mean(grid_sphere_scene({1, 2, 3, 4, 5, 6, 7, 8}, 2.0, 0.0, 1.0), 64);
    EXPECT_LT(e.mean, 0.95);
    EXPECT_GT(e.mean, 0.0);
  }
}

TEST(MediaRender, SampleEmittersChangesTheNoiseNotTheImage) {
  // A scattering ball under a small area light, no environment: with next-event estimation at
  // its scattering points (MIS against phase sampling) or without (emitters found by phase
  // sampling count in full, as Mitsuba's sample_emitters false), the same mean.
  Estimate with_nee, without_nee;
  for (bool sample : {true, false}) {
    Medium m = fog_medium({1.5, 2.5, 4}, {0.9, 0.8, 0.95}, 0.3);
    m.sample_emitters = sample;
    Scene s = medium_sphere_scene(m, 0, 0.0, 4.0);
    s.lights.clear();
    Material lamp;
    lamp.name = "lamp";
    lamp.reflectance.value = glm::dvec3(0);
    s.materials.push_back(lamp);
    Shape light = test::quad({-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}, 1);  // facing down
    light.emission = glm::dvec3(20);
    s.shapes.push_back(light);
    (sample ? with_nee : without_nee) = render_medium_mean(s, 512);
  }
  EXPECT_GT(with_nee.mean, 0.01);
  EXPECT_NEAR(with_nee.mean, without_nee.mean, test::tolerance(with_nee, without_nee));
  EXPECT_LT(with_nee.se, without_nee.se);  // the light sample is what it is for
}

TEST(MediaRender, OneOrTwoThreadsAndEitherIntegratorGiveTheSameBits) {
  const Scene s = medium_sphere_scene(fog_medium({2, 0.5, 6}, {0.9, 0.8, 1}, 0.4), 1, 0.8, 4.0);
  const Renderer scalar(s, test::test_job(16, 16, 8), {}, IntegratorKind::scalar);
  const Renderer wavefront(s, test::test_job(16, 16, 8), {}, IntegratorKind::wavefront);
  EXPECT_EQ(wavefront.integrator(), IntegratorKind::scalar);  // media render in the scalar order
  const TileRect tile{0, 0, 16, 16};
  Accumulation one, two, w;
  tbb::task_arena arena1(1), arena2(2);
  arena1.execute([&] { one = scalar.render(tile, 0, 8); });
  arena2.execute([&] { two = scalar.render(tile, 0, 8); });
  w = wavefront.render(tile, 0, 8);
  EXPECT_EQ(std::memcmp(one.rgb.data(), two.rgb.data(), one.rgb.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(one.rgb.data(), w.rgb.data(), one.rgb.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace tessera
