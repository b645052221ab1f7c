#include "scene/native/settings_parser.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>

#include "scene/scene_error.h"

namespace tessera {
namespace {

FovAxis parse_fov_axis(const JsonValue& value) {
  const std::string& axis = value.string();
  if (axis == "x") return FovAxis::x;
  if (axis == "y") return FovAxis::y;
  if (axis == "smaller") return FovAxis::smaller;
  if (axis == "larger") return FovAxis::larger;
  if (axis == "diagonal") return FovAxis::diagonal;
  value.fail("must be \"x\", \"y\", \"smaller\", \"larger\" or \"diagonal\" (got \"" + printable(axis) + "\")");
}

/// The camera's frame must be well defined: a view direction and an up vector not along it.
void check_camera_frame(const JsonValue& value, const Camera& camera) {
  glm::dvec3 view = camera.look_at - camera.position;
  double view_length = glm::length(view);
  if (!(view_length > 0)) {
    throw SceneError(value.child_path("look_at") + ": must differ from camera.position");
  }
  if (!std::isfinite(view_length)) {
    throw SceneError(value.child_path("look_at") + ": too far from camera.position");
  }
  double up_length = glm::length(camera.up);
  if (!(up_length > 0) || !std::isfinite(up_length)) {
    throw SceneError(value.child_path("up") + ": must be a non-zero vector");
  }
  double sine = glm::length(glm::cross(view / view_length, camera.up / up_length));
  if (!(sine > 1e-6)) {
    throw SceneError(value.child_path("up") + ": must not be parallel to the view direction");
  }
}

Projection parse_projection(const JsonValue& value) {
  const std::string& type = value.string();
  if (type == "perspective") return Projection::perspective;
  if (type == "orthographic") return Projection::orthographic;
  value.fail("must be \"perspective\" or \"orthographic\" (got \"" + printable(type) + "\")");
}

/// An orthographic camera's view_size: two numbers, each > 0; the lens keys of a perspective
/// camera are refused by name.
glm::dvec2 parse_view_size(const JsonValue& camera) {
  for (const char* lens : {"fov", "fov_axis", "aperture_radius", "focus_distance"}) {
    if (std::optional<JsonValue> key = camera.find(lens)) {
      key->fail("an orthographic camera has no lens (its image covers view_size)");
    }
  }
  std::vector<JsonValue> size = camera.at("view_size").elements(2);
  glm::dvec2 result(size[0].number(), size[1].number());
  for (int i = 0; i < 2; ++i) {
    if (!(result[i] > 0)) size[i].fail("must be > 0 (got " + format_number(result[i]) + ")");
  }
  return result;
}

}  // namespace

Camera parse_camera(const JsonValue& value) {
  value.expect_object({"type", "position", "look_at", "up", "fov", "fov_axis", "aperture_radius",
                       "focus_distance", "view_size", "view_aspect", "medium"},
                      "the camera");
  Camera camera;
  if (std::optional<JsonValue> type = value.find("type")) {
    camera.projection = parse_projection(*type);
  }
  camera.position = value.vec3_or("position", camera.position);
  camera.look_at = value.vec3_or("look_at", camera.look_at);
  camera.up = value.vec3_or("up", camera.up);
  check_camera_frame(value, camera);
  if (camera.projection == Projection::orthographic) {
    camera.view_size = parse_view_size(value);
    if (std::optional<JsonValue> aspect = value.find("view_aspect")) {
      camera.view_aspect = aspect->number();
      if (!(camera.view_aspect > 0) || !std::isfinite(camera.view_aspect)) {
        aspect->fail("must be > 0 (got " + format_number(camera.view_aspect) + ")");
      }
    }
    return camera;
  }
  for (const char* key : {"view_size", "view_aspect"}) {
    if (std::optional<JsonValue> size = value.find(key)) {
      size->fail(std::string("only an orthographic camera has a ") + key +
                 " (set \"type\": \"orthographic\")");
    }
  }
  if (std::optional<JsonValue> fov = value.find("fov")) {
    camera.fov_deg = fov->number();
    if (!(camera.fov_deg > 0 && camera.fov_deg < 180)) {
      fov->fail("must be in (0, 180) degrees (got " + format_number(camera.fov_deg) + ")");
    }
  }
  if (std::optional<JsonValue> axis = value.find("fov_axis")) {
    camera.fov_axis = parse_fov_axis(*axis);
  }
  if (std::optional<JsonValue> aperture = value.find("aperture_radius")) {
    camera.aperture_radius = aperture->number();
    if (camera.aperture_radius < 0) {
      aperture->fail("must be >= 0 (got " + format_number(camera.aperture_radius) + ")");
    }
  }
  if (std::optional<JsonValue> focus = value.find("focus_distance")) {
    camera.focus_distance = focus->number();
    if (!(camera.focus_distance > 0)) {
      focus->fail("must be > 0 (got " + format_number(camera.focus_distance) + ")");
    }
  }
  return camera;
}

PixelFilter parse_filter(const JsonValue& value) {
  PixelFilter filter;
  JsonValue type = value.at("type");
  const std::string& name = type.string();
  auto positive = [&](const char* key, double fallback) {
    std::optional<JsonValue> v = value.find(key);
    if (!v) return fallback;
    double x = v->number();
    if (!(x > 0)) v->fail("must be > 0 (got " + format_number(x) + ")");
    return x;
  };
  if (name == "box") {
    value.expect_object({"type"}, "a box filter");
  } else if (name == "tent") {
    value.expect_object({"type", "radius"}, "a tent filter");
    filter.kind = FilterKind::tent;
    filter.radius = positive("radius", 1);
  } else if (name == "gaussian") {
    value.expect_object({"type", "stddev", "radius"}, "a gaussian filter");
    filter.kind = FilterKind::gaussian;
    filter.stddev = positive("stddev", 0.5);
    filter.radius = positive("radius", 4 * filter.stddev);
  } else if (name == "mitchell") {
    value.expect_object({"type", "b", "c"}, "a mitchell filter");
    filter.kind = FilterKind::mitchell;
    filter.radius = 2;
    if (std::optional<JsonValue> b = value.find("b")) filter.b = b->number();
    if (std::optional<JsonValue> c = value.find("c")) filter.c = c->number();
  } else if (name == "lanczos") {
    value.expect_object({"type", "lobes"}, "a lanczos filter");
    filter.kind = FilterKind::lanczos;
    filter.radius = 3;
    if (std::optional<JsonValue> lobes = value.find("lobes")) filter.radius = double(lobes->integer(1, kMaxLanczosLobes));
  } else {
    type.fail("unknown filter \"" + printable(name) + "\" (expected box, tent, gaussian, mitchell or lanczos)");
  }
  return filter;
}

Film parse_film(const JsonValue& value) {
  value.expect_object({"width", "height", "filter"}, "the film");
  Film film;
  if (std::optional<JsonValue> w = value.find("width")) film.width = int(w->integer(1, 32768));
  if (std::optional<JsonValue> h = value.find("height")) film.height = int(h->integer(1, 32768));
  if (std::optional<JsonValue> f = value.find("filter")) film.filter = parse_filter(*f);
  return film;
}

RenderSettings parse_render(const JsonValue& value) {
  value.expect_object({"spp", "max_depth", "rr_depth", "seed", "hide_emitters"}, "render");
  RenderSettings render;
  if (std::optional<JsonValue> spp = value.find("spp")) {
    render.spp = spp->integer(1, std::numeric_limits<int64_t>::max());
  }
  if (std::optional<JsonValue> depth = value.find("max_depth")) {
    int64_t d =
        depth->integer(std::numeric_limits<int64_t>::min(), std::numeric_limits<int>::max());
    if (d < 1 && d != -1) {
      depth->fail("must be -1 (unbounded) or >= 1 (got " + std::to_string(d) + ")");
    }
    render.max_depth = int(d);
  }
  if (std::optional<JsonValue> rr = value.find("rr_depth")) {
    render.rr_depth = int(rr->integer(1, std::numeric_limits<int>::max()));
  }
  if (std::optional<JsonValue> seed = value.find("seed")) render.seed = seed->unsigned_integer();
  render.hide_emitters = value.boolean_or("hide_emitters", false);
  return render;
}

}  // namespace tessera
