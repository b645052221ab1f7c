#include "scene/mitsuba/mitsuba_xml_loader.h"

#include <algorithm>
#include <optional>

#include "scene/mitsuba/mitsuba_bsdf.h"
#include "scene/mitsuba/mitsuba_clip_check.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_integrator.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_sensor.h"
#include "scene/mitsuba/mitsuba_shape.h"
#include "scene/mitsuba/mitsuba_xml_document.h"

namespace tessera {
namespace {

/// The top-level elements of a scene that Tessera does not read, with what to do instead.
[[noreturn]] void refuse_top_level(const MitsubaElement& element) {
  const std::string& tag = element.tag;
  if (tag == "emitter") {
    fail_at(element,
            "Tessera's lights are area emitters on shapes: put <emitter type=\"area\"> "
            "inside a <shape>");
  }
  if (tag == "texture" || tag == "spectrum") {
    fail_at(element, "textures are not supported (give colours as <rgb>)");
  }
  if (tag == "medium" || tag == "phase" || tag == "volume") {
    fail_at(element, "participating media are not supported");
  }
  if (tag == "film" || tag == "sampler" || tag == "rfilter") {
    fail_at(element, "belongs inside the <sensor>");
  }
  if (tag == "ref") fail_at(element, "a <ref> belongs inside the object that uses it");
  fail_at(element,
          "not supported at the top of a scene (Tessera reads <sensor>, <integrator>, "
          "<bsdf> and <shape> there)");
}

class SceneBuilder {
 public:
  SceneBuilder(const MitsubaElement& root, const FileReader& reader,
               std::vector<std::string> included)
      : root_(root),
        ids_(root),
        materials_(ids_),
        reader_(reader),
        files_(std::move(included)),
        context_{ids_, reader_, materials_, files_} {}

  Scene build() {
    const MitsubaPlugin checked(root_, ids_);  // every child is a Mitsuba element; refs resolve
    for (const MitsubaElement& child : root_.children) add(child);
    if (!sensor_) {
      fail_at(root_,
              "the scene has no <sensor> (Tessera needs a perspective or thinlens sensor "
              "with an hdrfilm and a box rfilter)");
    }
    check_mitsuba_clip_planes(*sensor_, shapes_);
    Scene result;
    result.camera = sensor_->camera;
    result.film = sensor_->film;
    result.render.spp = sensor_->spp;
    result.render.seed = sensor_->seed;
    result.render.max_depth = max_depth_;
    result.materials = materials_.take();
    result.shapes = std::move(shapes_);
    result.referenced_files = std::move(files_);
    return result;
  }

 private:
  void add(const MitsubaElement& element) {
    if (element.tag == "sensor") {
      if (sensor_) {
        fail_at(element, "a second sensor (Tessera renders one camera; first at line " +
                             std::to_string(sensor_->element->line) + ")");
      }
      sensor_ = read_mitsuba_sensor(element, ids_);
    } else if (element.tag == "integrator") {
      if (integrator_) {
        fail_at(element,
                "a second integrator (first at line " + std::to_string(integrator_->line) + ")");
      }
      integrator_ = &element;
      max_depth_ = read_mitsuba_integrator(element, ids_);
    } else if (element.tag == "shape") {
      shapes_.push_back(read_mitsuba_shape(element, context_));
    } else if (element.tag == "bsdf") {
      // Declared for <ref>s; read now so that an unsupported one is refused even when unused.
      read_mitsuba_bsdf(element, ids_);
    } else {
      refuse_top_level(element);
    }
  }

  const MitsubaElement& root_;
  MitsubaIds ids_;
  MitsubaMaterials materials_;
  const FileReader& reader_;
  std::vector<std::string> files_;
  MitsubaShapeContext context_;
  std::optional<MitsubaSensor> sensor_;
  const MitsubaElement* integrator_ = nullptr;
  int max_depth_ = -1;  // Mitsuba's default integrator: path, unbounded
  std::vector<Shape> shapes_;
};

}  // namespace

Scene parse_mitsuba_scene(std::string_view xml, const std::string& file_name,
                          const FileReader& reader) {
  MitsubaDocument document = read_mitsuba_document(xml, file_name, reader);
  return SceneBuilder(document.scene, reader, std::move(document.files_read)).build();
}

}  // namespace tessera
