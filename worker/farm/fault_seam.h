// A test seam, off unless asked for: a worker started with TESSERA_FAULT_FLIP_BIT=1 flips one bit
// of one sum of every result it renders before encoding it, so its uploads are well formed and
// only their content is wrong: the faulty worker that spot checks must catch
// (docs/reliability.md, "Spot checks").
#pragma once

#include "accum/accumulation.h"

namespace tessera::farm {

/// Whether the environment asks for the seam (TESSERA_FAULT_FLIP_BIT=1), read once per process.
bool fault_flip_bit_requested();

/// `result` with the lowest mantissa bit of its first red sum flipped.
Accumulation with_one_bit_flipped(Accumulation result);

}  // namespace tessera::farm
