#include "scene/native/json_value.h"

#include <charconv>
#include <cmath>
#include <limits>

#include "scene/scene_error.h"

namespace tessera {

void JsonValue::fail(std::string_view message) const {
  throw SceneError((path_.empty() ? std::string("scene") : path_) + ": " + std::string(message));
}

void JsonValue::fail_type(std::string_view expected) const {
  std::string got = std::string("a ") + json_->type_name();  // "a string", "a number", ...
  if (json_->is_array()) got = "an array";
  if (json_->is_object()) got = "an object";
  if (json_->is_null()) got = "null";
  fail("must be " + std::string(expected) + " (got " + got + ")");
}

std::string JsonValue::child_path(std::string_view key) const {
  return path_.empty() ? printable(key) : path_ + "." + printable(key);
}

void JsonValue::expect_object(const std::vector<std::string_view>& allowed,
                              std::string_view owner) const {
  if (!json_->is_object()) fail_type("an object");
  for (const auto& [key, value] : json_->items()) {
    bool known = false;
    for (std::string_view a : allowed) known = known || a == key;
    if (known) continue;
    std::string list;
    for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    throw SceneError(child_path(key) + ": unknown key (" + std::string(owner) + " has: " + list +
                     ")");
  }
}

bool JsonValue::has(std::string_view key) const {
  return json_->is_object() && json_->contains(key);
}

std::optional<JsonValue> JsonValue::find(std::string_view key) const {
  if (!json_->is_object()) fail_type("an object");
  auto it = json_->find(key);
  if (it == json_->end()) return std::nullopt;
  return JsonValue(*it, child_path(key));
}

JsonValue JsonValue::at(std::string_view key) const {
  std::optional<JsonValue> member = find(key);
  if (!member) throw SceneError(child_path(key) + ": required");
  return *member;
}

std::vector<std::pair<std::string, JsonValue>> JsonValue::members() const {
  if (!json_->is_object()) fail_type("an object");
  std::vector<std::pair<std::string, JsonValue>> result;
  for (const auto& [key, value] : json_->items()) {
    result.emplace_back(key, JsonValue(value, child_path(key)));
  }
  return result;
}

std::vector<JsonValue> JsonValue::elements() const {
  if (!json_->is_array()) fail_type("an array");
  std::vector<JsonValue> result;
  result.reserve(json_->size());
  for (size_t i = 0; i < json_->size(); ++i) {
    result.emplace_back((*json_)[i], path_ + "[" + std::to_string(i) + "]");
  }
  return result;
}

std::vector<JsonValue> JsonValue::elements(size_t count) const {
  std::vector<JsonValue> result = elements();
  if (result.size() != count) {
    fail("must have " + std::to_string(count) + " elements (got " + std::to_string(result.size()) +
         ")");
  }
  return result;
}

double JsonValue::number() const {
  if (!json_->is_number()) fail_type("a number");
  double x = json_->get<double>();
  // JSON has no NaN; a non-finite value is a literal too large for a double, like 1e999.
  if (!std::isfinite(x)) fail("must be a finite number (got a value too large for a double)");
  return x;
}

int64_t JsonValue::integer(int64_t min, int64_t max) const {
  std::string range = "in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (max == std::numeric_limits<int64_t>::max()) range = ">= " + std::to_string(min);
  if (min == std::numeric_limits<int64_t>::min()) range = "<= " + std::to_string(max);
  if (!json_->is_number()) fail_type("an integer");
  int64_t i = 0;
  if (json_->is_number_unsigned()) {
    uint64_t u = json_->get<uint64_t>();
    if (u > static_cast<uint64_t>(max)) {
      bool unbounded = max == std::numeric_limits<int64_t>::max();
      fail((unbounded ? std::string("is too large for an integer") : "must be " + range) +
           " (got " + json_->dump() + ")");
    }
    i = static_cast<int64_t>(u);
  } else if (json_->is_number_integer()) {
    i = json_->get<int64_t>();
  } else {
    double x = number();
    // 2^63 is the first double past int64's range.
    if (x != std::floor(x)) fail("must be an integer (got " + format_number(x) + ")");
    if (x < -9.2233720368547758e18 || x >= 9.2233720368547758e18) {
      fail("is too large for an integer (got " + format_number(x) + ")");
    }
    i = static_cast<int64_t>(x);
  }
  if (i < min || i > max) fail("must be " + range + " (got " + std::to_string(i) + ")");
  return i;
}

uint64_t JsonValue::unsigned_integer() const {
  if (!json_->is_number()) fail_type("an integer");
  if (json_->is_number_unsigned()) return json_->get<uint64_t>();
  if (json_->is_number_integer()) {
    fail("must be >= 0 (got " + json_->dump() + ")");
  }
  double x = number();
  if (x != std::floor(x)) fail("must be an integer (got " + format_number(x) + ")");
  if (x < 0) fail("must be >= 0 (got " + format_number(x) + ")");
  if (x >= 1.8446744073709552e19) fail("must be < 2^64 (got " + format_number(x) + ")");
  return static_cast<uint64_t>(x);
}

bool JsonValue::boolean() const {
  if (!json_->is_boolean()) fail_type("true or false");
  return json_->get<bool>();
}

const std::string& JsonValue::string() const {
  if (!json_->is_string()) fail_type("a string");
  return json_->get_ref<const std::string&>();
}

glm::dvec3 JsonValue::vec3() const {
  if (!json_->is_array()) fail_type("an array of 3 numbers");
  std::vector<JsonValue> xyz = elements(3);
  return {xyz[0].number(), xyz[1].number(), xyz[2].number()};
}

double JsonValue::number_or(std::string_view key, double fallback) const {
  std::optional<JsonValue> member = find(key);
  return member ? member->number() : fallback;
}

bool JsonValue::boolean_or(std::string_view key, bool fallback) const {
  std::optional<JsonValue> member = find(key);
  return member ? member->boolean() : fallback;
}

glm::dvec3 JsonValue::vec3_or(std::string_view key, const glm::dvec3& fallback) const {
  std::optional<JsonValue> member = find(key);
  return member ? member->vec3() : fallback;
}

}  // namespace tessera
