// Which instruction set the wavefront integrator's hot code runs with: the same source compiled
// once per target (wavefront_kernels.h), one picked at run time by the CPU.
#pragma once

#include <string>

namespace tessera {

/// A build of the wavefront kernel (wavefront_kernels.h). Every one gives the same bits
/// (docs/renderer.md, "Kernels per instruction set"); they differ only in speed.
enum class KernelIsa {
  automatic,  ///< TESSERA_KERNEL_ISA when set, else the best this CPU runs (best_kernel_isa)
  baseline,   ///< x86-64 (SSE2), as the rest of the build
  avx2,       ///< AVX2 (and BMI1/2, LZCNT, POPCNT), without FMA
  avx512,     ///< AVX-512 F/VL/BW/DQ/CD (x86-64-v4 less FMA contraction)
};

/// "auto", "baseline", "avx2", "avx512".
const char* kernel_isa_name(KernelIsa isa);
/// The inverse of kernel_isa_name; throws std::invalid_argument naming `name` otherwise.
KernelIsa kernel_isa_from_name(const std::string& name);

/// Whether this build holds `isa`'s kernel and this CPU (and its OS) can run it. `baseline`
/// always; `automatic` is not a kernel (false).
bool kernel_isa_supported(KernelIsa isa);

/// The widest kernel this build holds and this CPU runs.
KernelIsa best_kernel_isa();

/// The kernel to run for `requested`: itself when not `automatic`; else `environment` (the
/// value of TESSERA_KERNEL_ISA, null or empty when unset; "auto" means unset), else
/// best_kernel_isa(). Throws std::invalid_argument naming the kernel (and TESSERA_KERNEL_ISA
/// when it came from there) when the name is unknown or this CPU or build lacks it.
KernelIsa resolve_kernel_isa(KernelIsa requested, const char* environment);

}  // namespace tessera
