#include "scene/mitsuba/mitsuba_sensor.h"

#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>

#include "scene/native/json_value.h"
#include "scene/mitsuba/mitsuba_plugin.h"

namespace tessera {
namespace {

constexpr int kMaxFilmSize = 32768;

/// The single nested plugin `tag`, or nullptr; refuses a second one.
const MitsubaElement* single_object(MitsubaPlugin& plugin, std::string_view tag) {
  std::vector<MitsubaObject> objects = plugin.take_objects(tag);
  if (objects.size() > 1) {
    fail_at(*objects[1].written, "only one <" + std::string(tag) + "> is allowed here");
  }
  return objects.empty() ? nullptr : objects.front().element;
}

int film_size(MitsubaPlugin& film, const std::string& name, int fallback) {
  std::optional<int64_t> size = film.take_integer(name);
  if (!size) return fallback;
  if (*size < 1 || *size > kMaxFilmSize) {
    fail_at(*film.property(name), "must be in [1, " + std::to_string(kMaxFilmSize) + "] (got " +
                                      std::to_string(*size) + ")");
  }
  return int(*size);
}

/// A crop window is accepted only when it is the whole image: Tessera renders whole images.
void check_crop(MitsubaPlugin& film, const Film& size) {
  const std::array<std::pair<const char*, int64_t>, 4> kFull = {{{"crop_offset_x", 0},
                                                                 {"crop_offset_y", 0},
                                                                 {"crop_width", size.width},
                                                                 {"crop_height", size.height}}};
  for (const auto& [name, full] : kFull) {
    std::optional<int64_t> value = film.take_integer(name);
    if (value && *value != full) {
      fail_at(*film.property(name), "Tessera renders whole images: remove the crop window");
    }
  }
}

void read_rfilter(MitsubaPlugin& film, const MitsubaIds& ids) {
  const MitsubaElement* rfilter = single_object(film, "rfilter");
  if (!rfilter) {
    fail_at(film.element(),
            "no <rfilter>: Mitsuba's default filter is gaussian, which Tessera does not have; "
            "add <rfilter type=\"box\"/> to render with a box filter");
  }
  MitsubaPlugin box(*rfilter, ids);
  if (box.type() != "box") {
    fail_at(*rfilter,
            "Tessera reconstructs with a box filter only (another filter changes the "
            "image): use <rfilter type=\"box\"/>");
  }
  box.finish();
}

Film read_film(MitsubaPlugin& sensor, const MitsubaIds& ids) {
  const MitsubaElement* element = single_object(sensor, "film");
  if (!element) {
    fail_at(sensor.element(),
            "no <film>: add <film type=\"hdrfilm\"> with width, height and "
            "<rfilter type=\"box\"/>");
  }
  MitsubaPlugin film(*element, ids);
  if (film.type() != "hdrfilm") {
    fail_at(*element, "unsupported film (Tessera writes RGB images: use type=\"hdrfilm\")");
  }
  Film size{film_size(film, "width", 768), film_size(film, "height", 576), PixelFilter{}};
  if (std::optional<std::string> format = film.take_string("pixel_format")) {
    if (*format != "rgb" && *format != "rgba") {
      fail_at(*film.property("pixel_format"),
              "\"" + printable(*format) + "\": Tessera renders RGB (use rgb or rgba)");
    }
  }
  // How pixels are stored and in which file format: chosen by `tessera-worker render -o`.
  film.ignore("component_format");
  film.ignore("file_format");
  // Widening the sampled area changes nothing with a box filter of radius 1/2.
  film.ignore("sample_border");
  check_crop(film, size);
  read_rfilter(film, ids);
  film.finish();
  return size;
}

void read_sampler(MitsubaPlugin& sensor, const MitsubaIds& ids, MitsubaSensor& result) {
  const MitsubaElement* element = single_object(sensor, "sampler");
  if (!element) return;
  MitsubaPlugin sampler(*element, ids);
  static constexpr std::array<std::string_view, 5> kSamplers = {
      "independent", "stratified", "multijitter", "orthogonal", "ldsampler"};
  if (std::find(kSamplers.begin(), kSamplers.end(), sampler.type()) == kSamplers.end()) {
    fail_at(*element,
            "unknown sampler (Mitsuba's are independent, stratified, multijitter, "
            "orthogonal and ldsampler; Tessera uses its own sequence for any of them)");
  }
  if (std::optional<int64_t> spp = sampler.take_integer("sample_count")) {
    if (*spp < 1) fail_at(*sampler.property("sample_count"), "must be >= 1");
    result.spp = *spp;
  }
  if (std::optional<int64_t> seed = sampler.take_integer("seed")) {
    if (*seed < 0) fail_at(*sampler.property("seed"), "must be >= 0");
    result.seed = uint64_t(*seed);
  }
  // Stratification details of Mitsuba's own sequences: they change the noise, not the image.
  sampler.ignore("jitter");
  sampler.ignore("strength");
  sampler.finish();
}

FovAxis read_fov_axis(MitsubaPlugin& sensor) {
  std::optional<std::string> axis = sensor.take_string("fov_axis");
  if (!axis || *axis == "x") return FovAxis::x;
  if (*axis == "y") return FovAxis::y;
  if (*axis == "smaller") return FovAxis::smaller;
  if (*axis == "larger") return FovAxis::larger;
  const MitsubaElement& where = *sensor.property("fov_axis");
  if (*axis == "diagonal") {
    fail_at(where,
            "Tessera's fov spans x, y, the smaller or the larger image axis, not the "
            "diagonal; give the horizontal fov 2 atan(tan(fov/2) w / sqrt(w^2 + h^2)) "
            "with fov_axis x");
  }
  fail_at(where, "\"" + printable(*axis) + "\" is no fov axis (x, y, smaller or larger)");
}

void read_fov(MitsubaPlugin& sensor, Camera& camera) {
  if (sensor.property("focal_length")) {
    fail_at(*sensor.property("focal_length"),
            "Tessera takes the field of view as fov (degrees) with fov_axis, not focal_length");
  }
  std::optional<double> fov = sensor.take_float("fov");
  if (!fov) {
    fail_at(sensor.element(),
            "give <float name=\"fov\"> (Mitsuba's default, a 50 mm focal "
            "length along the diagonal, is not supported)");
  }
  if (!(*fov > 0 && *fov < 180)) {
    fail_at(*sensor.property("fov"),
            "must be in (0, 180) degrees (got " + format_number(*fov) + ")");
  }
  camera.fov_deg = *fov;
  camera.fov_axis = read_fov_axis(sensor);
}

/// Position, look_at and up from to_world, which must be rigid and keep orientation.
void read_frame(MitsubaPlugin& sensor, MitsubaSensor& result) {
  std::optional<Transform> to_world = sensor.take_transform("to_world");
  if (!to_world) return;  // camera space = world space: at the origin looking down +z
  std::optional<double> scale = to_world->similarity_scale();
  if (!scale || std::abs(*scale - 1) > 1e-3) {
    fail_at(*sensor.property("to_world"),
            "a camera's to_world must be a rotation and a "
            "translation (no scale or shear)");
  }
  if (to_world->flips_orientation()) {
    fail_at(*sensor.property("to_world"),
            "this to_world mirrors the image (its determinant is negative), which Tessera's "
            "camera cannot do; Mitsuba's lookat gives frames with a positive determinant");
  }
  result.camera_to_world = *to_world;
  const glm::dmat4& m = to_world->matrix();
  result.camera.position = glm::dvec3(m[3]);
  result.camera.look_at = to_world->point(glm::dvec3(0, 0, 1));
  result.camera.up = glm::dvec3(m[1]);
  // What the native format demands of a camera (docs/scenes.md), so that the converted JSON
  // reads back: far from the origin, position + view direction can round to position.
  glm::dvec3 view = result.camera.look_at - result.camera.position;
  double length = glm::length(view);
  double sine = glm::length(glm::cross(view / length, glm::normalize(result.camera.up)));
  if (!(length > 0.5) || !std::isfinite(length) || !(sine > 1e-6) ||
      !std::isfinite(glm::length(result.camera.position))) {
    fail_at(*sensor.property("to_world"), "the camera is too far from the origin to place");
  }
}

double positive(MitsubaPlugin& sensor, const std::string& name, double fallback) {
  std::optional<double> value = sensor.take_float(name);
  if (value && !(*value > 0)) {
    fail_at(*sensor.property(name), "must be > 0 (got " + format_number(*value) + ")");
  }
  return value.value_or(fallback);
}

void read_lens(MitsubaPlugin& sensor, MitsubaSensor& result) {
  result.near_clip = positive(sensor, "near_clip", 1e-2);
  result.far_clip = positive(sensor, "far_clip", 1e4);
  if (!(result.near_clip < result.far_clip)) {
    fail_at(sensor.element(), "near_clip must be smaller than far_clip");
  }
  if (sensor.type() == "perspective") {
    sensor.ignore("focus_distance");  // a pinhole is in focus everywhere
    return;
  }
  std::optional<double> aperture = sensor.take_float("aperture_radius");
  if (!aperture) fail_at(sensor.element(), "a thinlens sensor needs aperture_radius");
  if (!(*aperture >= 0)) {
    fail_at(*sensor.property("aperture_radius"),
            "must be >= 0 (got " + format_number(*aperture) + ")");
  }
  result.camera.aperture_radius = *aperture;
  result.camera.focus_distance = positive(sensor, "focus_distance", result.far_clip);
}

void read_principal_point(MitsubaPlugin& sensor) {
  for (const char* name : {"principal_point_offset_x", "principal_point_offset_y"}) {
    std::optional<double> offset = sensor.take_float(name);
    if (offset && *offset != 0) {
      fail_at(*sensor.property(name), "Tessera's camera is centred: the offset must be 0");
    }
  }
}

}  // namespace

MitsubaSensor read_mitsuba_sensor(const MitsubaElement& element, const MitsubaIds& ids) {
  MitsubaPlugin sensor(element, ids);
  if (sensor.type() != "perspective" && sensor.type() != "thinlens") {
    fail_at(element, "unsupported sensor (Tessera has perspective and thinlens cameras)");
  }
  MitsubaSensor result;
  result.element = &element;
  result.camera.position = glm::dvec3(0);
  result.camera.look_at = glm::dvec3(0, 0, 1);
  result.camera.up = glm::dvec3(0, 1, 0);
  read_frame(sensor, result);
  read_fov(sensor, result.camera);
  read_lens(sensor, result);
  read_principal_point(sensor);
  sensor.ignore("shutter_open");  // motion blur needs moving geometry, which the subset lacks
  sensor.ignore("shutter_close");
  result.film = read_film(sensor, ids);
  read_sampler(sensor, ids, result);
  sensor.finish();
  return result;
}

}  // namespace tessera
