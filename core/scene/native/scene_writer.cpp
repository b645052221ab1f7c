#include "scene/native/scene_writer.h"

#include "scene/native/json_value.h"
#include "scene/native/scene_writer_camera.h"
#include "scene/native/scene_writer_lights.h"
#include "scene/native/scene_writer_materials.h"
#include "scene/native/scene_writer_shapes.h"
#include "scene/native/scene_writer_text.h"
#include "scene/scene_error.h"

namespace tessera {

std::string write_scene_json(const Scene& scene, const std::string& comment) {
  using namespace scene_writer;  // this file's parts (scene_writer_*.h)
  std::string out;
  if (!comment.empty()) out += "// " + valid_utf8(printable_whole(comment)) + "\n";
  out += "{\n  \"tessera\": 1,\n";
  Names names{unique_names(scene.textures, "texture"), unique_names(scene.materials, "material"),
              unique_names(scene.groups, "group"), unique_names(scene.media, "medium")};
  std::string camera = camera_json(scene.camera);
  if (scene.camera.medium >= 0) {
    // Before the closing "\n  },\n" of the camera object.
    camera.insert(camera.size() - 6, ", \"medium\": " + medium_name(scene.camera.medium, names, "camera.medium"));
  }
  out += camera;
  out += film_json(scene.film);
  out += "  \"render\": {\"spp\": " + std::to_string(scene.render.spp) +
         ", \"max_depth\": " + std::to_string(scene.render.max_depth) +
         ", \"rr_depth\": " + std::to_string(scene.render.rr_depth) +
         ", \"seed\": " + std::to_string(scene.render.seed) +
         ", \"hide_emitters\": " + bool_text(scene.render.hide_emitters) + "},\n";
  out += "  \"textures\": " + block(scene.textures.size(), '{', '}', [&](size_t i) {
    return texture_json(scene.textures[i], i, names);
  }) + ",\n";
  out += "  \"materials\": " + block(scene.materials.size(), '{', '}', [&](size_t i) {
    return material_json(scene.materials[i], i, names);
  }) + ",\n";
  if (!scene.media.empty()) {  // a scene without media writes as before media existed
    out += "  \"media\": " + block(scene.media.size(), '{', '}', [&](size_t i) {
      return medium_json(scene.media[i], i, names, scene.textures);
    }) + ",\n";
  }
  out += "  \"groups\": " + block(scene.groups.size(), '{', '}', [&](size_t g) {
    const ShapeGroup& group = scene.groups[g];
    std::string body = "    " + json_string(names.groups[g]) + ": {\"shapes\": [";
    for (size_t i = 0; i < group.shapes.size(); ++i) {
      const Shape& shape = group.shapes[i];
      if (shape.kind == Shape::Kind::instance) {
        throw SceneError("groups." + printable(names.groups[g]) + ": groups cannot hold instances");
      }
      body += (i ? ",\n" : "\n") +
              shape_json(shape, "groups." + printable(names.groups[g]) + ".shapes[" +
                                    std::to_string(i) + "] (" + printable(shape.origin) + ")",
                         scene.materials, names);
    }
    return body + "]}";
  }) + ",\n";
  out += "  \"shapes\": " + block(scene.shapes.size(), '[', ']', [&](size_t i) {
    const Shape& shape = scene.shapes[i];
    return shape_json(shape, "shapes[" + std::to_string(i) + "] (" + printable(shape.origin) + ")",
                      scene.materials, names);
  }) + ",\n";
  out += "  \"lights\": " + block(scene.lights.size(), '[', ']', [&](size_t i) {
    return light_json(scene.lights[i], i, names);
  }) + "\n}\n";
  return out;
}

}  // namespace tessera
