// The header of a PLY file (http://paulbourke.net/dataformats/ply/).
//
// Tessera reads PLY itself: Debian 12 packages no small PLY library (no rply, tinyply or
// happly); those that read PLY (assimp, VTK, PCL) are large multi-format or point-cloud
// libraries, and a render farm reading users' files needs bounded allocation and exact errors
// on truncated or hostile files, which is little code to own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tessera {

enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

/// A PLY scalar type: char/int8, uchar/uint8, short/int16, ushort/uint16, int/int32,
/// uint/uint32, float/float32, double/float64.
enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

/// Size in bytes of a binary value of `type`.
size_t ply_type_size(PlyType type);
bool ply_type_is_integer(PlyType type);

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::float32;  ///< the value type; for a list, the type of its items
  bool is_list = false;
  PlyType count_type = PlyType::uint8;  ///< lists only: the type of the item count
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;

  /// The index of property `name`, or -1.
  int find(std::string_view property_name) const;
  /// Smallest size of one row in the file: bytes in binary (lists empty), values in ASCII.
  uint64_t min_row_size(PlyFormat format) const;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::ascii;
  std::vector<PlyElement> elements;
  size_t data_offset = 0;  ///< first byte after "end_header\n"

  /// The element `name`, or nullptr.
  const PlyElement* find(std::string_view element_name) const;
};

/// Parses the header of PLY `bytes`. Checks that every declared element could fit in the rest
/// of the file (so that no count in a hostile header makes us allocate), and that no element
/// repeats. Throws SceneError("<name>: ...") on anything else than a well-formed header.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& name);

}  // namespace tessera
