#include "render/wavefront/kernel_isa.h"

#include <stdexcept>

#include "render/wavefront/wavefront_kernels.h"

namespace tessera {
namespace {

#if TESSERA_WAVEFRONT_X86_KERNELS
/// What wavefront_kernel_avx2.cpp's target pragma asks for.
bool avx2_and_bit_ops() {
  __builtin_cpu_init();  // a no-op after libgcc's constructor; needed if called before it
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
         __builtin_cpu_supports("lzcnt") && __builtin_cpu_supports("popcnt");
}
#endif

}  // namespace

const char* kernel_isa_name(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::automatic: return "auto";
    case KernelIsa::baseline: return "baseline";
    case KernelIsa::avx2: return "avx2";
    case KernelIsa::avx512: return "avx512";
  }
  return "?";
}

KernelIsa kernel_isa_from_name(const std::string& name) {
  for (const KernelIsa isa : {KernelIsa::automatic, KernelIsa::baseline, KernelIsa::avx2, KernelIsa::avx512}) {
    if (name == kernel_isa_name(isa)) return isa;
  }
  throw std::invalid_argument("unknown kernel instruction set \"" + name +
                              "\" (expected auto, baseline, avx2 or avx512)");
}

bool kernel_isa_supported(KernelIsa isa) {
  switch (isa) {
    case KernelIsa::automatic: return false;
    case KernelIsa::baseline: return true;
#if TESSERA_WAVEFRONT_X86_KERNELS
    // libgcc's cpuid check includes the OS's XSAVE state (AVX and AVX-512 registers enabled).
    case KernelIsa::avx2: return avx2_and_bit_ops();
    case KernelIsa::avx512:
      return avx2_and_bit_ops() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512cd");
#else
    case KernelIsa::avx2:
    case KernelIsa::avx512: return false;
#endif
  }
  return false;
}

KernelIsa best_kernel_isa() {
  if (kernel_isa_supported(KernelIsa::avx512)) return KernelIsa::avx512;
  if (kernel_isa_supported(KernelIsa::avx2)) return KernelIsa::avx2;
  return KernelIsa::baseline;
}

KernelIsa resolve_kernel_isa(KernelIsa requested, const char* environment) {
  std::string from;
  KernelIsa isa = requested;
  if (isa == KernelIsa::automatic && environment != nullptr && *environment != '\0') {
    from = " (from TESSERA_KERNEL_ISA)";
    try {
      isa = kernel_isa_from_name(environment);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("TESSERA_KERNEL_ISA: ") + e.what());
    }
  }
  if (isa == KernelIsa::automatic) return best_kernel_isa();
  if (!kernel_isa_supported(isa)) {
    throw std::invalid_argument(std::string("kernel instruction set ") + kernel_isa_name(isa) + from +
                                " is not supported by this CPU or build (best: " +
                                kernel_isa_name(best_kernel_isa()) + ")");
  }
  return isa;
}

}  // namespace tessera
