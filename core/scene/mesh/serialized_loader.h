// Triangle meshes from Mitsuba's ".serialized" files (docs/scenes.md, "Mesh files"). No Debian
// library reads this format; it is small (a header and zlib-compressed arrays), so Tessera reads
// it itself, with zlib for the decompression.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "scene/mesh/triangle_mesh.h"

namespace tessera {

/// The most bytes a shape's arrays may declare per byte of its compressed stream (the bytes from
/// the shape's header to the end of the file). Real meshes inflate 2-3:1; zeros inflate about
/// 1032:1, so a file half a megabyte long could otherwise declare half a gigabyte of arrays.
inline constexpr uint64_t kMaxSerializedInflateRatio = 64;

/// One shape of a serialized file.
struct SerializedMesh {
  std::string shape_name;  ///< the name stored with the shape (version 4); "" for version 3
  TriangleMesh mesh;       ///< object space: positions, normals and uvs as stored
};

/// Reads shape `shape_index` (0 = the first) of the serialized file `bytes`, named `name` in
/// messages. The format, as Mitsuba 3 reads it (src/shapes/serialized.cpp), little-endian:
///   uint16 0x041C, uint16 version (3 or 4), then a zlib stream holding
///   uint32 flags (0x1 normals, 0x2 uvs, 0x8 vertex colours, 0x1000 float, 0x2000 double),
///   a NUL-terminated shape name (version 4 only), uint64 vertex count, uint64 triangle count,
///   positions (3 per vertex), normals, uvs (2 per vertex), colours (3 per vertex; skipped),
///   triangles as 3 uint32 vertex indices each.
/// Shapes are concatenated, each with its own uncompressed 4-byte header; the file ends with the
/// offset of every shape (uint64 for version 4, uint32 for version 3) and a uint32 shape count,
/// which is read only for shape_index > 0 (as Mitsuba does). Flag 0x10 ("face normals") is
/// ignored, as Mitsuba 3 ignores it. Normals are dropped when `read_normals` is false or when one
/// of them is zero or not finite (callers then use face normals or compute their own).
/// 64-bit indices, which the format uses only beyond 2^32 vertices, never occur: more than
/// kMaxMeshElements vertices or triangles are refused before anything is allocated.
/// Throws SceneError("<name>: ...") for a bad magic number or version, a negative or missing
/// shape index, a truncated or corrupt stream, counts beyond the limits or declaring more than
/// kMaxSerializedInflateRatio times the compressed bytes, non-finite positions or uvs, and
/// vertex indices out of range. The arrays are read a chunk at a time: the memory it takes is
/// the mesh's own (serialized_load_bytes).
SerializedMesh load_serialized_mesh(std::string_view bytes, const std::string& name,
                                    int shape_index, bool read_normals);

/// The memory load_serialized_mesh allocates to load every shape of `bytes` once, from the
/// shapes' headers alone (a few bytes of each stream inflated): per shape, 24 bytes a vertex,
/// 24 more with normals, 16 more with uvs, and 12 bytes a triangle. A shape that load would
/// refuse before allocating (bad header, counts over the limits or the inflate ratio) counts
/// 0, and so do the shapes after a bad dictionary entry. Never throws.
uint64_t serialized_load_bytes(std::string_view bytes, const std::string& name);

}  // namespace tessera
