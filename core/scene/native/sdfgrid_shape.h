// An "sdfgrid" shape of a scene file (docs/scenes.md, "`sdfgrid`"): the zero set of a
// trilinearly interpolated grid of signed distances, as Mitsuba's sdfgrid shape defines it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/volume_grid_file.h"
#include "scene/native/json_value.h"
#include "scene/native/shape_parser.h"
#include "scene/scene.h"

namespace tessera {

/// The voxels (cells of 2 x 2 x 2 neighbouring samples) that can hold the surface: those with
/// a corner value >= 0 and a corner value <= 0 (Mitsuba's non-empty voxels; each is one
/// primitive of the renderer, as a triangle is). `values` has resolution.x * y * z entries.
uint64_t sdf_surface_voxel_count(glm::u32vec3 resolution, const std::vector<float>& values);

/// Makes `shape` an SDF grid of `grid`'s values (Shape::Kind::sdfgrid; sdf_file = `path`).
/// Throws SceneError "<path>: ..." when the grid has more than one channel (Mitsuba refuses
/// it too), fewer than 2 samples along an axis (Mitsuba would divide by zero: its voxel size
/// is 1 / (n - 1)), or no voxel that can hold the surface (Mitsuba: "SDFGrid should at least
/// have one non-empty voxel!").
void set_sdf_grid(Shape& shape, VolumeGridFile grid, const std::string& path);

/// Parses {"type": "sdfgrid", "file": "x.vol"} or {"type": "sdfgrid", "resolution": [nx, ny,
/// nz], "values": [...]} (x fastest), with "normals" ("smooth", the default, or "analytic"),
/// "transform" (maps [0, 1]^3 to the world; affine, invertible), "material" (required) and
/// "two_sided". SDF grids cannot emit light or flip their normals (as in Mitsuba). Throws
/// SceneError naming the JSON path (and the file).
Shape parse_sdfgrid_shape(const JsonValue& value, ShapeContext& context);

}  // namespace tessera
