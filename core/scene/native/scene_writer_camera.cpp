#include "scene/native/scene_writer_camera.h"

#include "scene/native/scene_writer_text.h"

namespace tessera::scene_writer {

namespace {

const char* fov_axis_name(FovAxis axis) {
  switch (axis) {
    case FovAxis::x:
      return "x";
    case FovAxis::y:
      return "y";
    case FovAxis::smaller:
      return "smaller";
    case FovAxis::larger:
      return "larger";
    case FovAxis::diagonal:
      return "diagonal";
  }
  return "x";
}

}  // namespace

std::string camera_json(const Camera& c) {
  if (c.projection == Projection::orthographic) {
    return "  \"camera\": {\n    \"type\": \"orthographic\", \"position\": " +
           vec3(c.position, "camera.position") +
           ",\n    \"look_at\": " + vec3(c.look_at, "camera.look_at") +
           ",\n    \"up\": " + vec3(c.up, "camera.up") + ",\n    \"view_size\": [" +
           number(c.view_size.x, "camera.view_size") + ", " +
           number(c.view_size.y, "camera.view_size") + "]" +
           (c.view_aspect > 0 ? ", \"view_aspect\": " + number(c.view_aspect, "camera.view_aspect") : std::string()) +
           "\n  },\n";
  }
  return "  \"camera\": {\n    \"position\": " + vec3(c.position, "camera.position") +
         ",\n    \"look_at\": " + vec3(c.look_at, "camera.look_at") +
         ",\n    \"up\": " + vec3(c.up, "camera.up") +
         ",\n    \"fov\": " + number(c.fov_deg, "camera.fov") + ", \"fov_axis\": \"" +
         fov_axis_name(c.fov_axis) +
         "\",\n    \"aperture_radius\": " + number(c.aperture_radius, "camera.aperture_radius") +
         ", \"focus_distance\": " + number(c.focus_distance, "camera.focus_distance") + "\n  },\n";
}

std::string film_json(const Film& film) {
  std::string filter;
  switch (film.filter.kind) {
    case FilterKind::box:
      filter = "{\"type\": \"box\"}";
      break;
    case FilterKind::tent:
      filter =
          "{\"type\": \"tent\", \"radius\": " + number(film.filter.radius, "film.filter") + "}";
      break;
    case FilterKind::gaussian:
      filter = "{\"type\": \"gaussian\", \"stddev\": " + number(film.filter.stddev, "film.filter") +
               ", \"radius\": " + number(film.filter.radius, "film.filter") + "}";
      break;
    case FilterKind::mitchell:
      filter = "{\"type\": \"mitchell\", \"b\": " + number(film.filter.b, "film.filter") +
               ", \"c\": " + number(film.filter.c, "film.filter") + "}";
      break;
    case FilterKind::lanczos:
      filter = "{\"type\": \"lanczos\", \"lobes\": " + std::to_string(int(film.filter.radius)) + "}";
      break;
  }
  return "  \"film\": {\"width\": " + std::to_string(film.width) +
         ", \"height\": " + std::to_string(film.height) + ", \"filter\": " + filter + "},\n";
}

}  // namespace tessera::scene_writer
