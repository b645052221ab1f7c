// The "textures" object of a scene file, and parameters that are a constant or a texture
// (docs/scenes.md, "Textures").
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/scene.h"
#include "scene/file_reader.h"

namespace tessera {

/// Texture name -> index into Scene::textures.
using TextureNames = std::map<std::string, int32_t>;

/// Parses "textures": an object from name to texture, appended to `textures` in file order.
/// A texture is {"type": "bitmap", "file", "color_space", "filter", "wrap", "to_uv"} or
/// {"type": "checkerboard", "color0", "color1", "to_uv"}, {"type": "rawconstant", "value"},
/// {"type": "mesh_attribute", "attribute", "scale"}, or {"type": "volume", "file", "transform",
/// "filter" (trilinear, nearest), "wrap" (clamp, repeat, mirror)} or {"type": "volume",
/// "value"}. Bitmap and volume files are checked with check_bundle_path and added to
/// `referenced_files` (once each); a volume's grid is read through `reader` and checked
/// (read_volume_texture_grid). Throws SceneError naming the JSON path of what is wrong.
TextureNames parse_textures(const JsonValue& value, std::vector<Texture>& textures,
                            std::vector<std::string>& referenced_files, const FileReader& reader);

/// Limits a constant colour must respect: [min, max] per channel.
struct ColorRange {
  double min = 0;
  double max = 1e300;
};

/// A colour parameter: [r, g, b] (each channel in `range`), or {"texture": name, "scale": s}
/// with s a number or [r, g, b] (each >= 0, default 1).
TexturedColor parse_textured_color(const JsonValue& value, const TextureNames& textures,
                                   ColorRange range);

/// A scalar parameter: a number in (min, max] (`min_open`) or [min, max], or {"texture": name,
/// "scale": s} with s >= 0 (default 1).
TexturedFloat parse_textured_float(const JsonValue& value, const TextureNames& textures,
                                   double min, double max, bool min_open);

/// The index of texture `value` (a string naming one).
int32_t texture_index(const JsonValue& value, const TextureNames& textures);

}  // namespace tessera
