#include "scene/mitsuba/mitsuba_sensor.h"

#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>

#include "scene/message_text.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_values.h"

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

/// The film's <rfilter>: box (radius 0.5), tent (radius 1) or gaussian (stddev 0.5, footprint
/// 4 stddev); without one, Mitsuba's default gaussian.
PixelFilter read_rfilter(MitsubaPlugin& film, const MitsubaIds& ids) {
  PixelFilter filter;
  const MitsubaElement* rfilter = single_object(film, "rfilter");
  if (!rfilter) {
    filter.kind = FilterKind::gaussian;
    filter.stddev = 0.5;
    filter.radius = 4 * filter.stddev;
    return filter;
  }
  MitsubaPlugin plugin(*rfilter, ids);
  auto positive = [&](const char* name, double fallback) {
    double value = plugin.take_float(name).value_or(fallback);
    if (!(value > 0)) {
      fail_at(*plugin.property(name), "must be > 0 (got " + format_number(value) + ")");
    }
    return value;
  };
  if (plugin.type() == "box") {
    filter.kind = FilterKind::box;
    filter.radius = positive("radius", 0.5);
  } else if (plugin.type() == "tent") {
    filter.kind = FilterKind::tent;
    filter.radius = positive("radius", 1.0);
  } else if (plugin.type() == "gaussian") {
    filter.kind = FilterKind::gaussian;
    filter.stddev = positive("stddev", 0.5);
    filter.radius = 4 * filter.stddev;
  } else if (plugin.type() == "mitchell" || plugin.type() == "catmullrom") {
    // Mitsuba's catmullrom is the Mitchell-Netravali cubic with B = 0, C = 0.5 (and no
    // parameters); mitchell reads B and C (its docs say A and B; its code reads B and C).
    filter.kind = FilterKind::mitchell;
    filter.radius = 2;
    if (plugin.type() == "catmullrom") {
      filter.b = 0;
      filter.c = 0.5;
    } else {
      for (const char* name : {"B", "C"}) {
        const std::optional<double> v = plugin.take_float(name);
        if (!v) continue;
        if (!std::isfinite(*v)) fail_at(*plugin.property(name), "must be finite (got " + format_number(*v) + ")");
        (name[0] == 'B' ? filter.b : filter.c) = *v;
      }
    }
  } else if (plugin.type() == "lanczos") {
    filter.kind = FilterKind::lanczos;
    const int64_t lobes = plugin.take_integer("lobes").value_or(3);
    if (lobes < 1 || lobes > kMaxLanczosLobes) {
      fail_at(*plugin.property("lobes"), "must be a whole number from 1 to " + std::to_string(kMaxLanczosLobes) +
                                             " (got " + std::to_string(lobes) + ")");
    }
    filter.radius = double(lobes);
  } else {
    fail_at(*rfilter,
            "unsupported reconstruction filter (Tessera has box, tent, gaussian, mitchell, "
            "catmullrom and lanczos)");
  }
  plugin.finish();
  return filter;
}

Film read_film(MitsubaPlugin& sensor, const MitsubaIds& ids) {
  const MitsubaElement* element = single_object(sensor, "film");
  if (!element) {  // Mitsuba's default film: hdrfilm 768 x 576 with its gaussian filter
    Film film;
    film.width = 768;
    film.height = 576;
    film.filter.kind = FilterKind::gaussian;
    film.filter.stddev = 0.5;
    film.filter.radius = 2;
    return film;
  }
  MitsubaPlugin film(*element, ids);
  if (film.type() != "hdrfilm") {
    fail_at(*element, "unsupported film (Tessera writes RGB images: use type=\"hdrfilm\")");
  }
  Film size;
  size.width = film_size(film, "width", 768);
  size.height = film_size(film, "height", 576);
  if (std::optional<std::string> format = film.take_string("pixel_format")) {
    if (*format != "rgb" && *format != "rgba") {
      fail_at(*film.property("pixel_format"),
              "\"" + printable(*format) + "\": Tessera renders RGB (use rgb or rgba)");
    }
  }
  // How pixels are stored and in which file format: chosen by `tessera-worker render -o`.
  film.ignore("component_format");
  film.ignore("file_format");
  // Samples outside the image that would splat into border pixels: Tessera's filter importance
  // sampling gives every sample to its own pixel, so there is nothing to widen.
  film.ignore("sample_border");
  // Read and ignored by Mitsuba 3's hdrfilm too: its images carry no banner, and `compensate`
  // (Kahan summation) was removed; Tessera sums in double.
  film.take_boolean("banner");
  film.take_boolean("compensate");
  // Mitsuba 0.6's name for sample_border. It changes border pixels there, and Mitsuba 3 refuses
  // it as an unreferenced property, so a scene that has it was never rendered by Mitsuba 3.
  if (const MitsubaElement* edges = film.property("high_quality_edges")) {
    fail_at(*edges,
            "Mitsuba 0.6's parameter, which Mitsuba 3 refuses too: remove it (Mitsuba 3 names it "
            "sample_border, which Tessera accepts and needs not: every sample counts in its own "
            "pixel)");
  }
  check_crop(film, size);
  size.filter = read_rfilter(film, ids);
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

/// fov with fov_axis, or focal_length (Mitsuba's default "50mm", a 35 mm film's diagonal, kept as
/// a diagonal angle).
void read_fov(MitsubaPlugin& sensor, Camera& camera) {
  if (sensor.property("focal_length") && sensor.property("fov")) {
    fail_at(*sensor.property("focal_length"), "give fov or focal_length, not both");
  }
  std::optional<double> fov = sensor.take_float("fov");
  std::string axis = "x";
  if (fov) {
    if (std::optional<std::string> given = sensor.take_string("fov_axis")) axis = *given;
    for (char& c : axis) c = char(std::tolower(static_cast<unsigned char>(c)));
  } else {
    std::string focal = sensor.take_string("focal_length").value_or("50mm");
    std::string number = focal.ends_with("mm") ? focal.substr(0, focal.size() - 2) : focal;
    std::optional<double> mm = parse_mitsuba_float(number);
    if (!mm || !(*mm > 0)) {
      fail_at(*sensor.property("focal_length"),
              "\"" + printable(focal) + "\" is no focal length (write e.g. \"50mm\")");
    }
    fov = 2 * std::atan(std::sqrt(36.0 * 36 + 24 * 24) / (2 * *mm)) * 180 / std::numbers::pi;
    axis = "diagonal";
  }
  if (axis == "x") {
    camera.fov_axis = FovAxis::x;
  } else if (axis == "y") {
    camera.fov_axis = FovAxis::y;
  } else if (axis == "smaller") {
    camera.fov_axis = FovAxis::smaller;
  } else if (axis == "larger") {
    camera.fov_axis = FovAxis::larger;
  } else if (axis == "diagonal") {
    // Kept as the diagonal, which the camera turns into the horizontal angle for the image's
    // aspect (fov_half_tangents): Mitsuba does so for its film's, also at another size.
    camera.fov_axis = FovAxis::diagonal;
  } else {
    fail_at(*sensor.property("fov_axis"),
            "\"" + printable(axis) + "\" is no fov axis (x, y, smaller, larger or diagonal)");
  }
  if (!(*fov > 0 && *fov < 180)) {
    const MitsubaElement* where = sensor.property("fov");
    fail_at(where ? *where : sensor.element(),
            "the field of view must be in (0, 180) degrees (got " + format_number(*fov) + ")");
  }
  camera.fov_deg = *fov;
}

/// Mitsuba's Transform::has_scale: the rows of the linear part are orthonormal within 1e-3.
bool has_scale(const glm::dmat4& m) {
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      double dot = 0;
      for (int k = 0; k < 3; ++k) dot += m[k][i] * m[k][j];
      if (!(std::abs(dot - (i == j ? 1.0 : 0.0)) <= 1e-3)) return true;
    }
  }
  return false;
}

/// Position, look_at and up from to_world, which must be rigid and keep orientation.
void read_frame(MitsubaPlugin& sensor, MitsubaSensor& result) {
  std::optional<Transform> to_world = sensor.take_transform("to_world");
  if (!to_world) return;  // camera space = world space: at the origin looking down +z
  if (has_scale(to_world->matrix())) {
    fail_at(*sensor.property("to_world"),
            "a camera's to_world must be a rotation and a translation (no scale or shear; "
            "Mitsuba's tolerance: rows orthonormal within 1e-3)");
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

/// An orthographic sensor's frame and view: to_world = rotation * scale (Mitsuba's lookat after
/// a scale) plus a translation. The image covers local x in [-1, 1] and y in [-1, 1] / aspect
/// and rays start at local z = near_clip (Mitsuba's orthographic_projection), so Tessera's
/// camera sits at the centre of that rectangle and sees nothing behind it, as Mitsuba does.
void read_orthographic_frame(MitsubaPlugin& sensor, MitsubaSensor& result, double aspect) {
  const Transform to_world = sensor.take_transform("to_world").value_or(Transform());
  const glm::dmat4& m = to_world.matrix();
  const glm::dvec3 axes[3] = {glm::dvec3(m[0]), glm::dvec3(m[1]), glm::dvec3(m[2])};
  const double scale[3] = {glm::length(axes[0]), glm::length(axes[1]), glm::length(axes[2])};
  const MitsubaElement& where =
      sensor.property("to_world") ? *sensor.property("to_world") : sensor.element();
  for (int i = 0; i < 3; ++i) {
    if (!(scale[i] > 0) || !std::isfinite(scale[i])) {
      fail_at(where, "an orthographic camera's to_world must keep every axis (it collapses one)");
    }
    for (int j = i + 1; j < 3; ++j) {
      if (!(std::abs(glm::dot(axes[i], axes[j])) <= 1e-3 * scale[i] * scale[j])) {
        fail_at(where,
                "an orthographic camera's to_world must be a rotation of a scale (put <scale> "
                "before <lookat>): this one shears the view");
      }
    }
  }
  if (to_world.flips_orientation()) {
    fail_at(where,
            "this to_world mirrors the image (its determinant is negative), which Tessera's "
            "camera cannot do: give the scale positive factors");
  }
  result.camera_to_world = to_world;
  Camera& camera = result.camera;
  camera.projection = Projection::orthographic;
  camera.position = to_world.point(glm::dvec3(0, 0, result.near_clip));
  camera.look_at = camera.position + axes[2] / scale[2];
  camera.up = axes[1] / scale[1];
  camera.view_size = glm::dvec2(2 * scale[0], 2 * scale[1] / aspect);
  camera.view_aspect = aspect;  // rendered at another size, the height follows (Mitsuba's)
  if (!std::isfinite(glm::length(camera.position)) ||
      !(glm::length(camera.look_at - camera.position) > 0.5)) {
    fail_at(where, "the camera is too far from the origin to place");
  }
}

double positive(MitsubaPlugin& sensor, const std::string& name, double fallback) {
  std::optional<double> value = sensor.take_float(name);
  if (value && !(*value > 0)) {
    fail_at(*sensor.property(name), "must be > 0 (got " + format_number(*value) + ")");
  }
  return value.value_or(fallback);
}

void read_clip(MitsubaPlugin& sensor, MitsubaSensor& result) {
  result.near_clip = positive(sensor, "near_clip", 1e-2);
  result.far_clip = positive(sensor, "far_clip", 1e4);
  if (!(result.near_clip < result.far_clip)) {
    fail_at(sensor.element(), "near_clip must be smaller than far_clip");
  }
}

void read_lens(MitsubaPlugin& sensor, MitsubaSensor& result) {
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
  if (sensor.type() != "perspective" && sensor.type() != "thinlens" &&
      sensor.type() != "orthographic") {
    fail_at(element,
            "unsupported sensor (Tessera has perspective, thinlens and orthographic cameras)");
  }
  MitsubaSensor result;
  result.element = &element;
  result.camera.position = glm::dvec3(0);
  result.camera.look_at = glm::dvec3(0, 0, 1);
  result.camera.up = glm::dvec3(0, 1, 0);
  read_clip(sensor, result);
  result.film = read_film(sensor, ids);
  const double aspect = double(result.film.width) / result.film.height;
  if (sensor.type() == "orthographic") {
    read_orthographic_frame(sensor, result, aspect);
  } else {
    read_frame(sensor, result);
    read_fov(sensor, result.camera);
    read_lens(sensor, result);
    read_principal_point(sensor);
  }
  sensor.ignore("shutter_open");  // motion blur needs moving geometry, which the subset lacks
  sensor.ignore("shutter_close");
  read_sampler(sensor, ids, result);
  std::vector<MitsubaObject> media = sensor.take_objects("medium");
  if (media.size() > 1) fail_at(*media[1].written, "a sensor sits in one medium");
  if (!media.empty()) result.medium = media.front().element;
  sensor.finish();
  return result;
}

double read_mitsuba_fov_x(MitsubaPlugin& plugin, double aspect) {
  Camera camera;
  read_fov(plugin, camera);
  // The horizontal angle of the camera's framing at this aspect (fov_half_tangents, which
  // also turns a diagonal angle as Mitsuba's parse_fov does); an x angle as given.
  if (camera.fov_axis == FovAxis::x) return camera.fov_deg;
  return 2 * std::atan(fov_half_tangents(camera.fov_deg, camera.fov_axis, aspect).x) * 180 / std::numbers::pi;
}

}  // namespace tessera
