#include "farm_limits.h"

#include <algorithm>
#include <cctype>
#include <string>

#include "farm_error.h"
#include "scene/mesh/curve_file.h"
#include "scene/native/sdfgrid_shape.h"
#include "scene/mesh/ply_header.h"
#include "scene/scene_error.h"

namespace tessera::server {
namespace {

[[noreturn]] void over(const std::string& what, uint64_t got, uint64_t limit, const char* flag) {
  throw FarmError(ErrorCode::invalid_argument,
                  what + " " + std::to_string(got) + " is over the farm's limit of " +
                      std::to_string(limit) + " (server flag " + flag + ")");
}

std::string lower_extension(const std::string& path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return {};
  std::string ext = path.substr(dot);
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

/// OBJ face lines ("f ..."), counted without allocating: at least one triangle each.
uint64_t obj_faces(const std::string& bytes) {
  uint64_t faces = 0;
  size_t pos = 0;
  while (pos < bytes.size()) {
    size_t start = bytes.find_first_not_of(" \t", pos);
    if (start != std::string::npos && start + 1 < bytes.size() && bytes[start] == 'f' &&
        (bytes[start + 1] == ' ' || bytes[start + 1] == '\t')) {
      ++faces;
    }
    const size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) break;
    pos = end + 1;
  }
  return faces;
}

}  // namespace

void check_unit_count(const JobOptions& options, const FarmLimits& limits) {
  const JobPlan plan = options.plan();
  const uint64_t tiles = uint64_t((plan.width + plan.tile_size - 1) / plan.tile_size) *
                         uint64_t((plan.height + plan.tile_size - 1) / plan.tile_size);
  const uint64_t units = tiles * plan.batch_count();
  if (units > limits.max_units_per_job) {
    throw FarmError(ErrorCode::invalid_argument,
                    "job has " + std::to_string(units) + " work units (" + std::to_string(tiles) +
                        " tiles x " + std::to_string(plan.batch_count()) +
                        " batches), over the farm's limit of " +
                        std::to_string(limits.max_units_per_job) +
                        " (server flag --max-units): use fewer spp, a larger --tile or --batch");
  }
}

void check_unit_samples(const JobOptions& options, const FarmLimits& limits) {
  const BatchSchedule schedule = options.plan().schedule();
  // The largest batch: a fixed schedule's first, a progressive one's cap or its last blocks.
  // Called after check_unit_count, so the batches are few enough to visit.
  uint64_t batch = 0;
  const uint32_t batches = schedule.count();
  for (uint32_t b = 0; b < batches; ++b) {
    batch = std::max<uint64_t>(batch, schedule.end(b) - schedule.begin(b));
  }
  const uint64_t tile_w = uint64_t(std::min(options.tile_size, options.width));
  const uint64_t tile_h = uint64_t(std::min(options.tile_size, options.height));
  const uint64_t samples = tile_w * tile_h * batch;
  if (samples > limits.max_unit_samples) {
    throw FarmError(ErrorCode::invalid_argument,
                    "a work unit of this job has " + std::to_string(samples) + " samples (" +
                        std::to_string(tile_w) + " x " + std::to_string(tile_h) +
                        " tile pixels x " + std::to_string(batch) +
                        " samples per pixel per batch), over the farm's limit of " +
                        std::to_string(limits.max_unit_samples) +
                        " (server flag --max-unit-samples): use a smaller --batch or --tile");
  }
}

void check_pixel_count(const JobOptions& options, const FarmLimits& limits) {
  const uint64_t pixels = uint64_t(options.width) * uint64_t(options.height);
  if (pixels > limits.max_pixels_per_job) {
    throw FarmError(ErrorCode::invalid_argument,
                    "job has " + std::to_string(pixels) + " pixels (" +
                        std::to_string(options.width) + " x " + std::to_string(options.height) +
                        "), over the farm's limit of " +
                        std::to_string(limits.max_pixels_per_job) +
                        " (server flag --max-pixels): render a smaller image");
  }
}

void check_bundle_limits(const v1::SceneBundle& bundle, const FarmLimits& limits) {
  const uint64_t files = uint64_t(bundle.files_size());
  if (files > limits.max_bundle_files) {
    over("bundle: file count", files, limits.max_bundle_files, "--max-bundle-files");
  }
  uint64_t bytes = 0;
  for (const auto& f : bundle.files()) bytes += f.data().size();
  if (bytes > limits.max_bundle_bytes) {
    over("bundle: size in bytes", bytes, limits.max_bundle_bytes, "--max-bundle-mb");
  }
}

void check_declared_triangles(const wire::BundleContents& bundle, const FarmLimits& limits) {
  uint64_t total = 0;
  for (const auto& [path, bytes] : bundle.files) {
    const std::string ext = lower_extension(path);
    uint64_t declared = 0;
    if (ext == ".ply") {
      try {
        const PlyHeader header = parse_ply_header(bytes, path);
        if (const PlyElement* face = header.find("face")) declared = face->count;
      } catch (const SceneError&) {
        continue;  // not a mesh we would read; the parser reports it if the scene uses it
      }
    } else if (ext == ".obj") {
      declared = obj_faces(bytes);
    }
    if (declared > limits.max_triangles) {
      over(path + ": declared faces", declared, limits.max_triangles, "--max-triangles");
    }
    total += declared;
  }
  if (total > limits.max_triangles) {
    over("bundle: mesh faces declared", total, limits.max_triangles, "--max-triangles");
  }
}

void check_scene_triangles(const Scene& scene, const FarmLimits& limits) {
  uint64_t total = 0;
  uint64_t segments = 0;  // curve segments: Embree primitives as a triangle is one
  for (const Shape& shape : scene.shapes) {
    total += shape.indices.size();
    for (uint32_t points : shape.curve_sizes) segments += curve_segment_count(shape.curve_basis, points);
  }
  // SDF grids: one primitive per voxel that can hold the surface (the renderer's Embree
  // primitives), as a triangle is one; a group's grid is stored once whatever places it.
  uint64_t sdf_voxels = 0;
  auto count_sdf = [&](const Shape& shape) {
    if (shape.kind == Shape::Kind::sdfgrid) {
      sdf_voxels += sdf_surface_voxel_count(shape.sdf_resolution, shape.sdf_values);
    }
  };
  for (const Shape& shape : scene.shapes) count_sdf(shape);
  for (const ShapeGroup& group : scene.groups) {
    for (const Shape& shape : group.shapes) count_sdf(shape);
  }
  if (total + segments + sdf_voxels > limits.max_triangles) {
    const std::string what = std::string("scene: triangle") + (segments ? " and curve segment" : "") +
                             (sdf_voxels ? " and SDF surface voxel" : "") + " count";
    over(what, total + segments + sdf_voxels, limits.max_triangles, "--max-triangles");
  }
}

}  // namespace tessera::server
