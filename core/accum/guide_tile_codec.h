// Lossless wire and storage format of a GuideTile (accum/guide_tile.h): what a worker uploads
// beside a unit's colour when its job asks for denoising, and what the server stores until it
// merges a job's guides.
#pragma once

#include <string>
#include <string_view>

#include "accum/accumulation_codec.h"
#include "accum/guide_tile.h"

namespace tessera {

/// The guide tile as two accumulations (accumulation_codec.h) of its rect: the albedo sums as
/// one's R, G, B and the normal sums as the other's, each with the sample counts, behind a
/// magic and the first one's length. Lossless and deterministic, like encode_accumulation.
std::string encode_guide_tile(const GuideTile& guides,
                              CodecEffort effort = CodecEffort::standard);

/// Decodes what encode_guide_tile wrote. Throws CodecError naming the problem on truncated,
/// corrupt or inconsistent input, or when its rect is not `rect` (the unit's tile: the tile
/// bounds what decoding may allocate).
GuideTile decode_guide_tile(std::string_view bytes, const TileRect& rect);

}  // namespace tessera
