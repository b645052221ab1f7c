// The wavefront kernel for AVX2 (with BMI1/2, LZCNT, POPCNT: every AVX2 CPU has them), without
// FMA: wavefront_kernels.h.
#include "render/wavefront/wavefront_kernel_includes.h"

#if TESSERA_WAVEFRONT_X86_KERNELS
#pragma GCC push_options
#pragma GCC target("avx2,bmi,bmi2,lzcnt,popcnt")
#define TESSERA_WAVEFRONT_NS wavefront_avx2
#define TESSERA_WAVEFRONT_PREDRAW 1
#include "render/wavefront/wavefront_kernel.inc"
#pragma GCC pop_options
#endif
