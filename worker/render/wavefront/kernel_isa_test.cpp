// Choosing the wavefront loop's build: names, the CPU check, TESSERA_KERNEL_ISA, errors.
#include "render/wavefront/kernel_isa.h"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/sampling/sampler.h"
#include "render/sampling/warp.h"
#include "render/wavefront/wavefront_kernels.h"

namespace tessera {
namespace {

std::string message_of(KernelIsa requested, const char* environment) {
  try {
    resolve_kernel_isa(requested, environment);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(KernelIsa, NamesRoundTrip) {
  for (const KernelIsa isa : {KernelIsa::automatic, KernelIsa::baseline, KernelIsa::avx2, KernelIsa::avx512}) {
    EXPECT_EQ(kernel_isa_from_name(kernel_isa_name(isa)), isa) << kernel_isa_name(isa);
  }
  try {
    kernel_isa_from_name("sse4.2");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("\"sse4.2\""), std::string::npos) << e.what();
  }
}

TEST(KernelIsa, BestIsSupportedAndAtLeastBaseline) {
  EXPECT_TRUE(kernel_isa_supported(KernelIsa::baseline));
  EXPECT_FALSE(kernel_isa_supported(KernelIsa::automatic));
  EXPECT_TRUE(kernel_isa_supported(best_kernel_isa()));
  // Each wider kernel's CPU features include the narrower's.
  if (kernel_isa_supported(KernelIsa::avx512)) {
    EXPECT_TRUE(kernel_isa_supported(KernelIsa::avx2));
    EXPECT_EQ(best_kernel_isa(), KernelIsa::avx512);
  }
}

TEST(KernelIsa, AutomaticReadsTheEnvironmentElseTakesTheBest) {
  EXPECT_EQ(resolve_kernel_isa(KernelIsa::automatic, nullptr), best_kernel_isa());
  EXPECT_EQ(resolve_kernel_isa(KernelIsa::automatic, ""), best_kernel_isa());
  EXPECT_EQ(resolve_kernel_isa(KernelIsa::automatic, "auto"), best_kernel_isa());
  EXPECT_EQ(resolve_kernel_isa(KernelIsa::automatic, "baseline"), KernelIsa::baseline);
  // An explicit choice wins over the environment.
  EXPECT_EQ(resolve_kernel_isa(KernelIsa::baseline, "avx512"), KernelIsa::baseline);
  const std::string bad = message_of(KernelIsa::automatic, "avx1024");
  EXPECT_NE(bad.find("TESSERA_KERNEL_ISA"), std::string::npos) << bad;
  EXPECT_NE(bad.find("avx1024"), std::string::npos) << bad;
}

TEST(KernelIsa, RefusesWhatThisCpuLacks) {
  for (const KernelIsa isa : {KernelIsa::avx2, KernelIsa::avx512}) {
    if (kernel_isa_supported(isa)) {
      EXPECT_EQ(resolve_kernel_isa(isa, nullptr), isa);
      EXPECT_EQ(resolve_kernel_isa(KernelIsa::automatic, kernel_isa_name(isa)), isa);
    } else {
      const std::string m = message_of(isa, nullptr);
      EXPECT_NE(m.find(kernel_isa_name(isa)), std::string::npos) << m;
      EXPECT_NE(message_of(KernelIsa::automatic, kernel_isa_name(isa)).find("TESSERA_KERNEL_ISA"),
                std::string::npos);
    }
  }
}

#if TESSERA_WAVEFRONT_X86_KERNELS
/// The AVX2 and AVX-512 kernels' lane-wise Sobol pairs are get2d()'s bits: every Sobol pair of
/// 1,000 (pixel, sample index) streams, in an order that mixes pairs and streams across lanes,
/// with a count that leaves a partial last group of lanes.
TEST(KernelIsa, LaneWiseSobolPairsAreTheSamplersBits) {
  std::vector<PixelSampler> samplers;
  for (uint32_t i = 0; i < 1000; ++i) {
    samplers.emplace_back(uint64_t(i % 7), int(i * 37 % 101), int(i * 11 % 53), i * 2654435761u);
  }
  std::vector<const PixelSampler*> lanes;
  std::vector<uint32_t> pairs;
  std::vector<glm::vec2> expected;
  for (size_t i = 0; i < samplers.size(); ++i) {
    for (uint32_t k = 0; k < PixelSampler::kSobolPairs; ++k) {
      const uint32_t pair = (k * 5 + uint32_t(i)) % PixelSampler::kSobolPairs;
      PixelSampler s = samplers[i];
      s.set_pair(pair);
      expected.push_back(s.get2d());
      lanes.push_back(&samplers[i]);
      pairs.push_back(pair);
    }
  }
  const size_t count = expected.size() - 5;  // not a multiple of 16
  const auto draws = {std::pair{KernelIsa::avx2, &wavefront_avx2::draw_sobol_pairs},
                      std::pair{KernelIsa::avx512, &wavefront_avx512::draw_sobol_pairs}};
  for (const auto& [isa, draw] : draws) {
    if (!kernel_isa_supported(isa)) continue;
    std::vector<glm::vec2> out(expected.size(), glm::vec2(-1.0f));
    draw(lanes.data(), pairs.data(), count, out.data());
    int differences = 0;
    for (size_t i = 0; i < count && differences < 5; ++i) {
      if (std::memcmp(&out[i], &expected[i], sizeof(glm::vec2)) != 0) {
        ++differences;
        ADD_FAILURE() << kernel_isa_name(isa) << ", draw " << i << " (pair " << pairs[i] << "): " << out[i].x << ", "
                      << out[i].y << " against " << expected[i].x << ", " << expected[i].y;
      }
    }
    EXPECT_EQ(out[count].x, -1.0f) << kernel_isa_name(isa) << ": wrote past the count";
  }
}

/// The AVX2 and AVX-512 kernels' lane-wise cosine-weighted directions (cosine_lanes) are
/// square_to_cosine_hemisphere's bits at every width: the disk's centre (u = 0.5, 0.5), its
/// sector edges (|o.x| = |o.y|) and axes, u at 0 and just below 1, then 4,000 random pairs and
/// every 24-bit grid value of one line; a count that leaves a partial last group of lanes.
TEST(KernelIsa, LaneWiseCosineDirectionsAreTheScalarBits) {
  std::vector<glm::vec2> u = {{0.5f, 0.5f}, {0.0f, 0.0f}, {0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f},
                              {0.5f, 0.0f}, {0.0f, 0.5f}, {0.99999994f, 0.5f}, {0.5f, 0.99999994f},
                              {0.99999994f, 0.99999994f}, {0.5f, 0.50000006f}, {0.49999997f, 0.5f}};
  uint32_t state = 12345;
  const auto uniform = [&state] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) * 0x1p-24f;
  };
  for (int i = 0; i < 4000; ++i) u.emplace_back(uniform(), uniform());
  for (uint32_t k = 0; k < (1u << 24); k += 4099) u.emplace_back(float(k) * 0x1p-24f, 0.3f);
  const size_t count = u.size() - 3;  // not a multiple of 16
  std::vector<glm::vec3> expected(count);
  for (size_t i = 0; i < count; ++i) expected[i] = square_to_cosine_hemisphere(u[i]);
  const auto kernels = {std::pair{KernelIsa::avx2, &wavefront_avx2::cosine_directions},
                        std::pair{KernelIsa::avx512, &wavefront_avx512::cosine_directions}};
  for (const auto& [isa, directions] : kernels) {
    if (!kernel_isa_supported(isa)) continue;
    for (const int width : {4, 8, 16}) {
      std::vector<glm::vec3> out(count + 1, glm::vec3(-1.0f));
      directions(u.data(), count, width, out.data());
      int differences = 0;
      for (size_t i = 0; i < count && differences < 5; ++i) {
        if (std::memcmp(&out[i], &expected[i], sizeof(glm::vec3)) != 0) {
          ++differences;
          ADD_FAILURE() << kernel_isa_name(isa) << " width " << width << ", u (" << u[i].x << ", " << u[i].y
                        << "): (" << out[i].x << ", " << out[i].y << ", " << out[i].z << ") against ("
                        << expected[i].x << ", " << expected[i].y << ", " << expected[i].z << ")";
        }
      }
      EXPECT_EQ(out[count].x, -1.0f) << kernel_isa_name(isa) << " width " << width << ": wrote past the count";
    }
  }
}
#endif

}  // namespace
}  // namespace tessera
