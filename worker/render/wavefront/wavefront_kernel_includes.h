// Every header wavefront_kernel.inc uses, included by each kernel's translation unit before its
// `#pragma GCC target` (wavefront_kernels.h says why).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <immintrin.h>

#include "render/integrators/path_vertex.h"
#include "render/scene/embree_packet.h"
#include "render/wavefront/wavefront_kernels.h"
