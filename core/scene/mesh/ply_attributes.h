// Mitsuba's mesh attributes in PLY files: which properties of an element form which attribute
// (docs/scenes.md, "Mesh attributes").
#pragma once

#include <string_view>
#include <vector>

#include "scene/mesh_attribute.h"
#include "scene/mesh/ply_header.h"

namespace tessera {

/// The attributes of one PLY element and where each of its properties goes.
struct PlyAttributeLayout {
  /// Names and channel counts, in the order Mitsuba finds them; `values` empty.
  std::vector<MeshAttribute> attributes;
  /// Per property of the element: the attribute it belongs to (index into `attributes`) and its
  /// channel, or {-1, -1}.
  struct Slot {
    int attribute = -1;
    int channel = -1;
  };
  std::vector<Slot> slots;
};

/// Groups the scalar properties of `element` into attributes as Mitsuba 3's PLY reader does
/// (src/shapes/ply.h, find_other_fields), prefixing names with `kind` ("vertex_" or "face_"):
/// - r, g, b (or red, green, blue) form "<kind>color" (3 channels; with alpha, 4 channels,
///   which Mitsuba's textures read as 0: Tessera then leaves the attribute out);
/// - consecutive properties <prefix>_<c> whose postfixes c run through one of x y z w,
///   r g b a, 0 1 2 3 or 1 2 3 4 from its start form "<kind><prefix>" ("<kind><prefix>_color"
///   for r g b) when there are 1 or 3 of them; others (2 or 4 fields, names without a
///   one-letter postfix, a broken sequence, a prefix seen before) are left out, as Mitsuba
///   leaves them out with a warning.
/// `reserved[i]` marks properties that are geometry (positions, normals, uvs, indices) and lists.
PlyAttributeLayout ply_attribute_layout(const PlyElement& element, std::string_view kind,
                                        const std::vector<bool>& reserved);

/// A PLY value as Mitsuba stores it in an attribute: floats as they are (in single precision);
/// integers normalised to [0, 1] by their type's maximum and sRGB-decoded (Mitsuba's struct
/// converter with its Normalized and Gamma flags).
float ply_attribute_value(double value, PlyType type);

}  // namespace tessera
