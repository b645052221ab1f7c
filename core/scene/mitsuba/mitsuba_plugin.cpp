#include "scene/mitsuba/mitsuba_plugin.h"

#include <algorithm>
#include <array>
#include <cctype>

#include "scene/message_text.h"
#include "scene/mitsuba/mitsuba_transform.h"
#include "scene/mitsuba/mitsuba_values.h"

namespace tessera {
namespace {

constexpr std::array<std::string_view, 9> kPropertyTags = {
    "float", "integer", "boolean", "string", "rgb", "point", "vector", "spectrum", "transform"};

bool is_property_tag(const MitsubaElement& element) {
  // <spectrum type="..."> is a plugin (a texture); <spectrum name=... value=...> a property.
  if (element.tag == "spectrum") return element.attribute("type") == nullptr;
  return std::find(kPropertyTags.begin(), kPropertyTags.end(), element.tag) != kPropertyTags.end();
}

bool is_object(const MitsubaElement& element) {
  return is_mitsuba_object_tag(element.tag) || element.tag == "spectrum";
}

void expect_attributes(const MitsubaElement& element,
                       std::initializer_list<std::string_view> allowed,
                       std::initializer_list<std::string_view> required) {
  for (const auto& [name, value] : element.attributes) {
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      fail_at(element, "unexpected attribute \"" + printable(name) + "\"");
    }
  }
  for (std::string_view name : required) {
    if (!element.attribute(name)) {
      fail_at(element, "missing attribute \"" + std::string(name) + "\"");
    }
  }
}

/// The attribute rules of Mitsuba's parser for each kind of property.
void check_property(const MitsubaElement& p) {
  if (p.tag == "transform") {
    expect_attributes(p, {"name"}, {"name"});
    return;
  }
  if (p.tag == "point" || p.tag == "vector") {
    expect_attributes(p, {"name", "value", "x", "y", "z"}, {"name"});
  } else if (p.tag == "spectrum") {
    expect_attributes(p, {"name", "value", "filename"}, {"name"});
  } else {
    expect_attributes(p, {"name", "value"}, {"name", "value"});
  }
  if (!p.children.empty()) fail_at(p.children.front(), "unexpected inside " + p.label());
}

[[noreturn]] void fail_unknown_element(const MitsubaElement& e) {
  static constexpr std::array<std::string_view, 5> kOperations = {"translate", "rotate", "scale",
                                                                  "matrix", "lookat"};
  if (std::find(kOperations.begin(), kOperations.end(), e.tag) != kOperations.end()) {
    fail_at(e, "a transform operation must be inside <transform name=\"to_world\">");
  }
  if (e.tag == "alias") {
    fail_at(e, "not supported by Tessera's importer (write the scene without it)");
  }
  fail_at(e, "unknown element (Mitsuba 3 has no <" + printable(e.tag) + ">)");
}

}  // namespace

MitsubaPlugin::MitsubaPlugin(const MitsubaElement& element, const MitsubaIds& ids)
    : element_(element) {
  if (element.tag == "scene") {
    expect_attributes(element, {"version"}, {});
  } else {
    expect_attributes(element, {"type", "id", "name"}, {"type"});
    type_ = *element.attribute("type");
  }
  for (const MitsubaElement& child : element.children) {
    if (is_property_tag(child)) {
      check_property(child);
      const std::string& name = *child.attribute("name");
      for (const Child& other : children_) {
        if (other.is_property && *other.element->attribute("name") == name) {
          fail_at(child, "\"" + printable(name) + "\" is given twice (first at line " +
                             std::to_string(other.element->line) + ")");
        }
      }
      children_.push_back(Child{&child, &child, true});
    } else if (child.tag == "ref") {
      expect_attributes(child, {"id", "name"}, {"id"});
      if (!child.children.empty()) fail_at(child.children.front(), "unexpected inside <ref>");
      children_.push_back(Child{&child, &ids.resolve(child), false});
    } else if (is_object(child)) {
      children_.push_back(Child{&child, &child, false});
    } else {
      fail_unknown_element(child);
    }
  }
}

const MitsubaElement* MitsubaPlugin::property(std::string_view name) const {
  for (const Child& c : children_) {
    if (c.is_property && *c.element->attribute("name") == name) return c.element;
  }
  return nullptr;
}

bool MitsubaPlugin::has(std::string_view name) const {
  for (const Child& c : children_) {
    const std::string* child_name = c.element->attribute("name");
    if (child_name && *child_name == name) return true;
  }
  return false;
}

const MitsubaElement* MitsubaPlugin::take(std::string_view name) {
  if (std::find(reads_.begin(), reads_.end(), name) == reads_.end()) reads_.emplace_back(name);
  for (Child& c : children_) {
    if (c.is_property && !c.taken && *c.element->attribute("name") == name) {
      c.taken = true;
      return c.element;
    }
  }
  return nullptr;
}

void MitsubaPlugin::fail_type(const MitsubaElement& p, std::string_view expected) const {
  std::string name = printable(*p.attribute("name"));
  if (p.tag == "spectrum") {
    fail_at(p, "Tessera renders in RGB and reads no spectra: give " + name + " as " +
                   std::string(expected));
  }
  fail_at(p, name + " must be given as " + std::string(expected) + " in " + element_.label());
}

std::optional<double> MitsubaPlugin::take_float(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "float" && p->tag != "integer") fail_type(*p, "<float>");
  std::optional<double> value = parse_mitsuba_float(*p->attribute("value"));
  if (!value) fail_at(*p, "\"" + printable(*p->attribute("value")) + "\" is not a finite number");
  return value;
}

std::optional<int64_t> MitsubaPlugin::take_integer(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "integer") fail_type(*p, "<integer>");
  std::optional<int64_t> value = parse_mitsuba_integer(*p->attribute("value"));
  if (!value) fail_at(*p, "\"" + printable(*p->attribute("value")) + "\" is not an integer");
  return value;
}

std::optional<bool> MitsubaPlugin::take_boolean(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "boolean") fail_type(*p, "<boolean>");
  std::string text = *p->attribute("value");
  for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (text == "true") return true;
  if (text == "false") return false;
  fail_at(*p, "\"" + printable(*p->attribute("value")) + "\" must be true or false");
}

std::optional<std::string> MitsubaPlugin::take_string(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "string") fail_type(*p, "<string>");
  return *p->attribute("value");
}

std::optional<glm::dvec3> MitsubaPlugin::take_color(std::string_view name, MitsubaColorRole role) {
  const MitsubaElement* p = take(name);
  if (!p) {
    // A texture given as a nested plugin, <texture name="reflectance" ...> or a <ref>.
    for (const Child& c : children_) {
      const std::string* child_name = c.element->attribute("name");
      if (!c.is_property && child_name && *child_name == name) {
        fail_at(*c.element, std::string(name) + " takes no texture in " + element_.label() +
                                " (give it as <rgb>, <float> or <spectrum>)");
      }
    }
    return std::nullopt;
  }
  if (p->tag == "float" || p->tag == "integer") {
    std::optional<double> grey = parse_mitsuba_float(*p->attribute("value"));
    if (!grey) fail_at(*p, "\"" + printable(*p->attribute("value")) + "\" is not a finite number");
    return glm::dvec3(*grey);
  }
  if (p->tag == "spectrum") {
    const std::string* value = p->attribute("value");
    if (!value) {
      fail_at(*p, "spectra from files are not supported: give the wavelength:value pairs in "
                  "value=\"...\" or an <rgb>");
    }
    std::string error;
    std::optional<glm::dvec3> rgb = mitsuba_spectrum_to_rgb(*value, role, error);
    if (!rgb) fail_at(*p, error);
    return rgb;
  }
  if (p->tag != "rgb") fail_type(*p, "<rgb>, <float> or <spectrum>");
  const std::string& text = *p->attribute("value");
  if (std::optional<std::vector<double>> one = parse_mitsuba_floats(text, 1)) {
    return glm::dvec3((*one)[0]);
  }
  std::optional<std::vector<double>> rgb = parse_mitsuba_floats(text, 3);
  if (!rgb) fail_at(*p, "value must be one number or three (got \"" + printable(text) + "\")");
  return glm::dvec3((*rgb)[0], (*rgb)[1], (*rgb)[2]);
}

std::optional<glm::dvec3> MitsubaPlugin::take_point(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "point" && p->tag != "vector") fail_type(*p, "<point>");
  if (const std::string* value = p->attribute("value")) {
    if (p->attribute("x") || p->attribute("y") || p->attribute("z")) {
      fail_at(*p, "give either value or x/y/z, not both");
    }
    if (std::optional<std::vector<double>> one = parse_mitsuba_floats(*value, 1)) {
      return glm::dvec3((*one)[0]);
    }
    std::optional<std::vector<double>> v = parse_mitsuba_floats(*value, 3);
    if (!v) fail_at(*p, "value must be three numbers (got \"" + printable(*value) + "\")");
    return glm::dvec3((*v)[0], (*v)[1], (*v)[2]);
  }
  glm::dvec3 point(0);
  for (int axis = 0; axis < 3; ++axis) {
    const char* key = axis == 0 ? "x" : axis == 1 ? "y" : "z";
    if (const std::string* text = p->attribute(key)) {
      std::optional<double> v = parse_mitsuba_float(*text);
      if (!v)
        fail_at(*p, std::string(key) + " must be a number (got \"" + printable(*text) + "\")");
      point[axis] = *v;
    }
  }
  return point;
}

std::optional<Transform> MitsubaPlugin::take_transform(std::string_view name) {
  const MitsubaElement* p = take(name);
  if (!p) return std::nullopt;
  if (p->tag != "transform") fail_type(*p, "<transform>");
  return read_mitsuba_transform(*p);
}

std::optional<double> MitsubaPlugin::take_float_or_name(std::string_view name, std::string& text) {
  const MitsubaElement* p = property(name);
  if (p && p->tag == "string") {
    text = *take_string(name);
    return std::nullopt;
  }
  if (p && p->tag != "float" && p->tag != "integer") {
    take(name);
    fail_type(*p, "<float> or <string>");
  }
  return take_float(name);
}

void MitsubaPlugin::ignore(std::string_view name) { take(name); }

std::vector<MitsubaObject> MitsubaPlugin::take_objects(std::string_view tag) {
  std::string label = "<" + std::string(tag) + ">";
  if (std::find(reads_.begin(), reads_.end(), label) == reads_.end()) reads_.push_back(label);
  std::vector<MitsubaObject> objects;
  for (Child& c : children_) {
    if (!c.is_property && !c.taken && c.target->tag == tag) {
      c.taken = true;
      objects.push_back(MitsubaObject{c.target, c.element});
    }
  }
  return objects;
}

std::optional<MitsubaObject> MitsubaPlugin::take_named_object(std::string_view name) {
  if (std::find(reads_.begin(), reads_.end(), name) == reads_.end()) reads_.emplace_back(name);
  for (Child& c : children_) {
    const std::string* child_name = c.element->attribute("name");
    if (!c.is_property && !c.taken && child_name && *child_name == name) {
      c.taken = true;
      return MitsubaObject{c.target, c.element};
    }
  }
  return std::nullopt;
}

void MitsubaPlugin::finish() const {
  for (const Child& c : children_) {
    if (c.taken) continue;
    std::string reads;
    for (const std::string& r : reads_) reads += (reads.empty() ? "" : ", ") + r;
    std::string what = c.element->tag == "ref" ? "(it names " + c.target->label() + ") " : "";
    fail_at(*c.element, what + "is not supported in " + element_.label() +
                            (reads.empty() ? std::string(" (it takes no parameters)")
                                           : " (Tessera reads: " + reads + ")"));
  }
}

}  // namespace tessera
