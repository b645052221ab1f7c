// The parameters of one Mitsuba plugin element, such as <bsdf type="diffuse">: its properties
// (<float name="...">, <rgb>, <transform name="to_world">, ...) and its nested plugins (<bsdf>,
// <emitter>, <film>, or a <ref> to one).
//
// A plugin's reader takes what it understands, each value checked for its type; finish() then
// refuses whatever is left. This is how the importer keeps its promise that nothing written in
// a scene is silently dropped: a parameter is either read, accepted as not changing the image
// (ignore()), or refused with its line.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene/mitsuba/mitsuba_ids.h"
#include "scene/mitsuba/mitsuba_spectrum.h"
#include "scene/mitsuba/mitsuba_xml_document.h"
#include "scene/transform.h"

namespace tessera {

/// A nested plugin, written in place or named through a <ref>.
struct MitsubaObject {
  const MitsubaElement* element = nullptr;  ///< the plugin itself (the <ref>'s target)
  const MitsubaElement* written = nullptr;  ///< where its parent names it: itself or the <ref>
};

class MitsubaPlugin {
 public:
  /// Indexes the children of `element` (an object element, or the <scene>). Throws SceneError at
  /// the first child that is no Mitsuba element, at an attribute that does not belong, at a
  /// property given twice, and at a <ref> to an unknown id. `element` and `ids` must outlive
  /// this.
  MitsubaPlugin(const MitsubaElement& element, const MitsubaIds& ids);

  const MitsubaElement& element() const { return element_; }
  /// The `type` attribute ("" for the <scene>).
  const std::string& type() const { return type_; }

  // Each take_* returns nullopt when the property is absent, and throws SceneError naming the
  // property's element when it has another type or a value that does not parse.

  /// <float> (or <integer>): a finite number.
  std::optional<double> take_float(std::string_view name);
  /// <integer>.
  std::optional<int64_t> take_integer(std::string_view name);
  /// <boolean>: "true" or "false", any case.
  std::optional<bool> take_boolean(std::string_view name);
  /// <string>.
  std::optional<std::string> take_string(std::string_view name);
  /// <rgb> (one or three numbers), <float> (grey) or <spectrum name=... value=...> (as
  /// mitsuba_spectrum_to_rgb for `role`). A texture given for it is refused with a message
  /// saying so (read_textured_color takes textures).
  std::optional<glm::dvec3> take_color(std::string_view name,
                                       MitsubaColorRole role = MitsubaColorRole::reflectance);
  /// <point> or <vector>: value="x, y, z" (or one number for all three), or x/y/z attributes
  /// (missing ones are 0).
  std::optional<glm::dvec3> take_point(std::string_view name);
  /// <transform name="...">, see read_mitsuba_transform.
  std::optional<Transform> take_transform(std::string_view name);
  /// <string> or <float>: either is taken; the string is returned in `text`, the number as is.
  /// For parameters such as int_ior that Mitsuba accepts both ways.
  std::optional<double> take_float_or_name(std::string_view name, std::string& text);

  /// The property element `name`, taken or not, or nullptr: for messages about its value.
  const MitsubaElement* property(std::string_view name) const;
  /// True when `name` is given, as a property or as a named nested plugin (a texture).
  bool has(std::string_view name) const;
  /// Accepts property `name` whatever its value: for parameters that do not change the image.
  void ignore(std::string_view name);

  /// The nested plugins whose tag is `tag` (in place or through <ref>), in file order. They are
  /// taken: their parent accepts them.
  std::vector<MitsubaObject> take_objects(std::string_view tag);
  /// The nested plugin (or <ref>) whose `name` attribute is `name`, such as
  /// <texture type="bitmap" name="reflectance">, taken; nullopt when there is none.
  std::optional<MitsubaObject> take_named_object(std::string_view name);

  /// Throws SceneError at the first child nobody took, naming what this plugin reads instead.
  void finish() const;

 private:
  struct Child {
    const MitsubaElement* element;
    const MitsubaElement* target;  ///< for a <ref>: what it names; else the element itself
    bool is_property;
    bool taken = false;
  };

  /// The untaken property `name`, marked taken, or nullptr; records `name` as read.
  const MitsubaElement* take(std::string_view name);
  [[noreturn]] void fail_type(const MitsubaElement& property, std::string_view expected) const;

  const MitsubaElement& element_;
  std::string type_;
  std::vector<Child> children_;
  std::vector<std::string> reads_;  ///< the parameter and plugin names asked for, for messages
};

}  // namespace tessera
