// The wavefront kernel for baseline x86-64 (and any other target): wavefront_kernels.h.
#include "render/wavefront/wavefront_kernel_includes.h"

#define TESSERA_WAVEFRONT_NS wavefront_baseline
#define TESSERA_WAVEFRONT_PREDRAW 0  // lane-wise 64-bit multiplies: slower than scalar code on SSE2
#include "render/wavefront/wavefront_kernel.inc"
