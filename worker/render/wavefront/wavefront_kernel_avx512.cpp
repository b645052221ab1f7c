// The wavefront kernel for AVX-512 (F, VL, BW, DQ, CD): wavefront_kernels.h. AVX-512F brings
// its own FMA instructions; -ffp-contract=off (worker/CMakeLists.txt) keeps GCC from using them.
#include "render/wavefront/wavefront_kernel_includes.h"

#if TESSERA_WAVEFRONT_X86_KERNELS
#pragma GCC push_options
#pragma GCC target("avx2,bmi,bmi2,lzcnt,popcnt,avx512f,avx512vl,avx512bw,avx512dq,avx512cd")
#define TESSERA_WAVEFRONT_NS wavefront_avx512
#define TESSERA_WAVEFRONT_PREDRAW 1
#include "render/wavefront/wavefront_kernel.inc"
#pragma GCC pop_options
#endif
