// The optics helpers moved to bsdf/fresnel.h with the BSDFs; this header keeps old includes
// working.
#pragma once

#include "render/bsdf/fresnel.h"
