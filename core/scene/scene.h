// The editable scene description: what a scene file says, resolved to world space.
//
// This is the description, not the render-ready scene (STYLE.md habit 8): the worker turns it
// into an immutable Embree scene (worker/render/traceable_scene.h). Everything here is plain data
// so that the server and the client can parse and validate scenes without linking the renderer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace tessera {

/// Which image axis the camera's field of view spans.
enum class FovAxis { x, y, smaller, larger };

struct Camera {
  glm::dvec3 position{0, 0, 1};
  glm::dvec3 look_at{0, 0, 0};
  glm::dvec3 up{0, 1, 0};
  double fov_deg = 39.3;        ///< full angle along fov_axis, degrees, in (0, 180)
  FovAxis fov_axis = FovAxis::x;
  double aperture_radius = 0;   ///< thin lens radius in scene units; 0 = pinhole
  double focus_distance = 1;    ///< distance to the plane in focus, scene units, > 0
};

struct Film {
  int width = 256;
  int height = 256;
};

/// Render defaults the scene file carries; a job may override each of them.
struct RenderSettings {
  int64_t spp = 64;      ///< samples per pixel, >= 1
  int max_depth = -1;    ///< Mitsuba convention: path segments incl. the camera ray; -1 = unbounded
  uint64_t seed = 0;
};

enum class MaterialType { diffuse, mirror, glass };

struct Material {
  std::string name;
  MaterialType type = MaterialType::diffuse;
  glm::dvec3 reflectance{0.5, 0.5, 0.5};  ///< diffuse albedo, linear RGB, each in [0, 1]
  double ior = 1.5;                       ///< glass: interior over exterior index, > 0
  bool two_sided = false;                 ///< diffuse/mirror: both sides alike (glass always is)
};

/// One shape of the scene in world space. Quads, boxes, tetrahedra, triangle lists and meshes
/// are all triangle meshes here; spheres stay exact.
struct Shape {
  enum class Kind { triangles, sphere };
  Kind kind = Kind::triangles;

  // Kind::triangles
  std::vector<glm::dvec3> positions;   ///< world space
  std::vector<glm::dvec3> normals;     ///< per-vertex shading normals, empty = use face normals
  std::vector<glm::u32vec3> indices;   ///< counter-clockwise seen from the front

  // Kind::sphere
  glm::dvec3 center{0, 0, 0};
  double radius = 1;  ///< > 0

  /// Turns the front to the other side: spheres face inward, triangles swap their winding
  /// (already applied to `indices` and `normals` for Kind::triangles; kept for messages).
  bool flip_normals = false;

  uint32_t material = 0;             ///< index into Scene::materials
  glm::dvec3 emission{0, 0, 0};      ///< emitted radiance (W/(m^2 sr)), resolved from `power`
  bool two_sided_emission = false;   ///< emits from both sides
  std::string origin;                ///< where it came from, for messages: "shapes[3]"
  /// Mesh files only: degenerate faces (zero area, or fewer than 3 vertices) dropped while
  /// loading; scanned meshes have some. Explicit geometry with one is an error instead.
  uint64_t dropped_triangles = 0;

  bool is_emitter() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

struct Scene {
  Camera camera;
  Film film;
  RenderSettings render;
  std::vector<Material> materials;
  std::vector<Shape> shapes;
  /// Files the scene references, relative to the scene file's folder ('/'-separated, no "..").
  /// Together with the scene file they are the job's bundle.
  std::vector<std::string> referenced_files;
};

}  // namespace tessera
