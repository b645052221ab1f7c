// Choosing the wavefront loop's build: names, the CPU check, TESSERA_KERNEL_ISA, errors.
#include "render/wavefront/kernel_isa.h"

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace tessera
