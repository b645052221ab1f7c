#include "scene/mitsuba/mitsuba_xml_loader.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>

#include "scene/mesh/mesh_attribute_use.h"
#include "scene/mitsuba/mitsuba_bsdf.h"
#include "scene/mitsuba/mitsuba_clip_check.h"
#include "scene/mitsuba/mitsuba_emitter.h"
#include "scene/mitsuba/mitsuba_file_resolver.h"
#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_integrator.h"
#include "scene/mitsuba/mitsuba_plugin.h"
#include "scene/mitsuba/mitsuba_sensor.h"
#include "scene/mitsuba/mitsuba_shape.h"
#include "scene/mitsuba/mitsuba_texture.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/volume_texture_check.h"

namespace tessera {
namespace {

/// The top-level elements of a scene that Tessera does not read, with what to do instead.
[[noreturn]] void refuse_top_level(const MitsubaElement& element) {
  const std::string& tag = element.tag;
  if (tag == "phase" || tag == "volume") {
    fail_at(element, "belongs inside a <medium> (or is named there by <ref>)");
  }
  if (tag == "ref") fail_at(element, "a <ref> belongs inside the object that uses it");
  fail_at(element,
          "not supported at the top of a scene (Tessera reads <sensor>, <integrator>, "
          "<emitter>, <bsdf>, <texture>, <shape>, and the <film>, <sampler> and <rfilter> a "
          "<ref> names there)");
}

/// Adds every object some <ref> below `element` names to `targets`.
void collect_references(const MitsubaElement& element, const MitsubaIds& ids,
                        std::set<const MitsubaElement*>& targets) {
  for (const MitsubaElement& child : element.children) {
    if (child.tag == "ref") targets.insert(&ids.resolve(child));
    collect_references(child, ids, targets);
  }
}

class SceneBuilder {
 public:
  SceneBuilder(const MitsubaElement& root, const FileReader& reader, MitsubaDocument& document,
               const std::string& root_name)
      : root_(root),
        ids_(root),
        files_(reader, "", root_name),
        referenced_(std::move(document.files_read)),
        textures_(ids_, files_, referenced_),
        materials_(ids_, textures_),
        media_(ids_, textures_),
        context_{ids_, files_, materials_, textures_, referenced_, groups_, lights_, media_} {
    files_.reset(document.search_folders);
    if (document.confined_to) files_.confine_to(*document.confined_to);
    collect_references(root_, ids_, referenced_objects_);
  }

  Scene build() {
    const MitsubaPlugin checked(root_, ids_);  // every child is a Mitsuba element; refs resolve
    for (const MitsubaElement& child : root_.children) add(child);
    if (!sensor_) {
      fail_at(root_,
              "the scene has no <sensor> (Tessera needs a perspective, thinlens or orthographic "
              "sensor; Mitsuba 3 loads such a scene but cannot render it either: \"No sensor "
              "specified\")");
    }
    check_mitsuba_clip_planes(*sensor_, shapes_);
    refuse_overweighted_delta_lights();
    Scene result;
    result.materials = materials_.take();
    result.camera = sensor_->camera;
    if (sensor_->medium) result.camera.medium = media_.of(*sensor_->medium);
    result.shapes = std::move(shapes_);
    result.media = media_.take();
    if (!integrator_.volumetric) drop_media(result);
    refuse_uncounted_null_interactions(result);
    result.film = sensor_->film;
    result.render.spp = sensor_->spp;
    result.render.seed = sensor_->seed;
    result.render.max_depth = integrator_.max_depth;
    result.render.rr_depth = integrator_.rr_depth;
    result.render.hide_emitters = integrator_.hide_emitters;
    result.textures = textures_.take();
    result.groups = std::move(groups_);
    result.lights = std::move(lights_);
    result.referenced_files = std::move(referenced_);
    check_mesh_attribute_use(result);
    check_volume_texture_use(result);
    if (integrator_.particle_tracer) integrator_.note += "; " + mitsuba_ptracer_note(result);
    if (!integrator_.note.empty()) {
      std::fprintf(stderr, "note: %s: line %d: %s\n", integrator_element_->file.c_str(),
                   integrator_element_->line, integrator_.note.c_str());
    }
    if (other_sensors_ > 0) {
      std::fprintf(stderr,
                   "note: %s: line %d: the scene has %d sensors; Tessera renders this first one, "
                   "as Mitsuba 3 does by default (its --sensor 0)\n",
                   sensor_->element->file.c_str(), sensor_->element->line, other_sensors_ + 1);
    }
    return result;
  }

 private:
  /// With emitter_samples N > 1, Mitsuba 3.9.1's `direct` integrator renders a delta light
  /// (point, spot, directional, projector) N times too bright (measured on mitsuba-data's
  /// scenes/hello.xml, point lights, N = 2, 3, 4; as if each sample had full weight, not 1 / N).
  /// Tessera renders the converged image, which would differ from Mitsuba's: refused.
  void refuse_overweighted_delta_lights() const {
    if (integrator_.emitter_samples <= 1) return;
    for (const Light& light : lights_) {
      if (light.kind == LightKind::point || light.kind == LightKind::spot ||
          light.kind == LightKind::directional || light.kind == LightKind::projector) {
        fail_at(*integrator_element_,
                "the direct integrator with " + std::to_string(integrator_.emitter_samples) +
                    " emitter samples and a point, spot, directional or projector light (" +
                    light.origin + "): Mitsuba 3 renders such a light " +
                    std::to_string(integrator_.emitter_samples) +
                    " times too bright then, which Tessera does not reproduce (write "
                    "emitter_samples 1, or the path integrator with max_depth 2)");
      }
    }
  }

  /// Mitsuba's integrators other than volpath and volpathmis ignore media: rays pass through
  /// them as through vacuum. The scene's media are left out then (a note says so), so that
  /// Tessera renders Mitsuba's image.
  void drop_media(Scene& scene) const {
    bool used = scene.camera.medium >= 0;
    for (Shape& shape : scene.shapes) {
      used = used || shape.bounds_medium();
      shape.interior = shape.exterior = -1;
    }
    scene.camera.medium = -1;
    if (used && integrator_element_) {
      std::fprintf(stderr,
                   "note: %s: line %d: this integrator ignores participating media in Mitsuba "
                   "(only volpath and volpathmis render them): the scene's media are left out\n",
                   integrator_element_->file.c_str(), integrator_element_->line);
    } else if (used) {
      std::fprintf(stderr, "note: the scene has no <integrator>: Mitsuba's default, path, ignores "
                           "participating media, so the scene's media are left out\n");
    }
    scene.media.clear();
  }

  /// Mitsuba's volpath does not count null interactions toward max_depth (volpath.cpp counts
  /// only non-null BSDF samples), where its path integrator and Tessera count every hit: with
  /// a finite max_depth a scene with a mask, a null BSDF or a thindielectric (whose straight
  /// transmission is a null interaction) renders differently. Refused, saying what to write.
  void refuse_uncounted_null_interactions(const Scene& scene) const {
    if (integrator_.counts_null_interactions || integrator_.max_depth < 0) return;
    // With media the volumetric path tracer renders the scene, and counts as volpath does.
    if (scene.camera.medium >= 0 ||
        std::any_of(scene.shapes.begin(), scene.shapes.end(), [](const Shape& s) { return s.bounds_medium(); })) {
      return;
    }
    const std::vector<Material>& materials = scene.materials;
    auto null_scattering = [](const Material& m) {
      return m.type == MaterialType::thin_glass || !m.opacity.is_constant() || m.opacity.value < 1;
    };
    for (const Material& m : materials) {
      bool blended = std::any_of(m.blend.begin(), m.blend.end(), null_scattering);
      if (!null_scattering(m) && !blended) continue;
      fail_at(*integrator_element_,
              "volpath with max_depth " + std::to_string(integrator_.max_depth) +
                  " and material \"" + m.name +
                  "\" (a mask, null BSDF or thindielectric): Mitsuba's volpath does not count "
                  "passages through such surfaces toward max_depth, Tessera's path tracer does "
                  "(as Mitsuba's path integrator); write max_depth -1 or the path integrator");
    }
  }

  void add(const MitsubaElement& element) {
    const std::string& tag = element.tag;
    if (tag == "sensor") {
      // Mitsuba keeps the sensors in document order and renders the first unless told
      // otherwise (mitsuba --sensor I, mi.render(scene, sensor=I)). Every sensor is read, so
      // that an unsupported one is refused as Mitsuba would fail on it; the first is rendered.
      MitsubaSensor sensor = read_mitsuba_sensor(element, ids_);
      if (sensor_) {
        ++other_sensors_;
      } else {
        sensor_ = std::move(sensor);
      }
    } else if (tag == "integrator") {
      if (integrator_element_) {
        fail_at(element, "a second integrator (first at line " +
                             std::to_string(integrator_element_->line) + ")");
      }
      integrator_element_ = &element;
      integrator_ = read_mitsuba_integrator(element, ids_);
    } else if (tag == "shape") {
      const std::string* type = element.attribute("type");
      if (type && *type == "shapegroup") {
        read_mitsuba_shape_group(element, context_);  // placed by instances
      } else {
        Shape shape = read_mitsuba_shape(element, context_);
        if (mitsuba_shape_is_empty(shape)) {
          note_empty_mitsuba_shape(shape);  // nothing to render; nothing dropped silently
        } else {
          shapes_.push_back(std::move(shape));
        }
      }
    } else if (tag == "bsdf") {
      // Declared for <ref>s, and checked even when unused, as Mitsuba instantiates it.
      if (referenced_objects_.count(&element)) {
        materials_.of(element);
      } else {
        check_unused_bsdf(element);
      }
    } else if (tag == "texture") {
      textures_.of(element);
    } else if (tag == "medium") {
      // Declared for <ref>s, and read even when unused, as Mitsuba instantiates it.
      media_.of(element);
    } else if (tag == "emitter") {
      add_emitter(element);
    } else if (tag == "sampler" || tag == "rfilter" || tag == "film") {
      // Top-level objects a sensor or film names with <ref>; read there.
      if (!referenced_objects_.count(&element)) {
        fail_at(element, "belongs inside the <sensor> (or is named there by <ref>)");
      }
    } else {
      refuse_top_level(element);
    }
  }

  void add_emitter(const MitsubaElement& element) {
    const std::string* type = element.attribute("type");
    if (type && *type == "area") {
      // An area emitter declared once and attached to shapes through <ref>.
      if (!referenced_objects_.count(&element)) {
        fail_at(element, "an area emitter belongs inside a <shape> (or is named by one with <ref>)");
      }
      return;
    }
    lights_.push_back(read_mitsuba_light(element, ids_, files_, referenced_, textures_));
  }

  /// Reads an unused BSDF into scratch tables, so that an unsupported one is still refused.
  void check_unused_bsdf(const MitsubaElement& element) {
    std::vector<std::string> scratch_files;
    MitsubaTextures scratch_textures(ids_, files_, scratch_files);
    MitsubaMaterials scratch(ids_, scratch_textures);
    scratch.of(element);
  }

  const MitsubaElement& root_;
  MitsubaIds ids_;
  MitsubaFileResolver files_;
  std::vector<std::string> referenced_;
  MitsubaTextures textures_;
  MitsubaMaterials materials_;
  MitsubaMedia media_;
  std::vector<ShapeGroup> groups_;
  std::vector<Light> lights_;  // before context_, which refers to it
  MitsubaShapeContext context_;
  std::optional<MitsubaSensor> sensor_;
  int other_sensors_ = 0;  ///< sensors after the first: read, not rendered
  const MitsubaElement* integrator_element_ = nullptr;
  MitsubaIntegrator integrator_;  // Mitsuba's default integrator: path, unbounded
  std::vector<Shape> shapes_;
  std::set<const MitsubaElement*> referenced_objects_;
};

}  // namespace

Scene parse_mitsuba_scene(std::string_view xml, const std::string& file_name,
                          const FileReader& reader, const std::string& root_name,
                          MitsubaReach reach) {
  MitsubaDocument document = read_mitsuba_document(xml, file_name, reader, root_name, reach);
  return SceneBuilder(document.scene, reader, document, root_name).build();
}

}  // namespace tessera
