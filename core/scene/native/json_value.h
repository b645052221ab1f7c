// Checked access to one value of the scene's JSON tree, which knows its own JSON path so that
// every error names the place that is wrong.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/message_text.h"
#include "scene/native/json_document.h"

namespace tessera {

/// A JSON value and its path ("shapes[3].radius"; "" for the document itself). Holds a pointer
/// into the tree: the tree must outlive it. Every accessor that cannot give what is asked
/// throws SceneError("<path>: <what is wrong>").
class JsonValue {
 public:
  JsonValue(const Json& json, std::string path) : json_(&json), path_(std::move(path)) {}

  const Json& json() const { return *json_; }
  const std::string& path() const { return path_; }

  /// Throws SceneError("<path>: <message>").
  [[noreturn]] void fail(std::string_view message) const;

  // --- objects -------------------------------------------------------------------------------
  /// Checks that this is an object whose keys are all in `allowed`; the error names the first
  /// unknown key's path and lists what `owner` (e.g. "a sphere") accepts.
  void expect_object(const std::vector<std::string_view>& allowed, std::string_view owner) const;
  bool has(std::string_view key) const;
  /// The member `key`, or nullopt when absent. This must be an object.
  std::optional<JsonValue> find(std::string_view key) const;
  /// The member `key`; throws "<path>.<key>: required" when absent.
  JsonValue at(std::string_view key) const;
  /// All members in file order. This must be an object.
  std::vector<std::pair<std::string, JsonValue>> members() const;
  /// The JSON path of member `key` of this object.
  std::string child_path(std::string_view key) const;

  // --- arrays --------------------------------------------------------------------------------
  /// The elements; this must be an array.
  std::vector<JsonValue> elements() const;
  /// The elements; this must be an array of exactly `count` elements.
  std::vector<JsonValue> elements(size_t count) const;

  // --- scalars -------------------------------------------------------------------------------
  /// A finite number (NaN cannot be written in JSON; 1e999 reads as infinity and is refused).
  double number() const;
  /// An integer in [min, max]. Integral floats (64.0, 1e3) are accepted.
  int64_t integer(int64_t min, int64_t max) const;
  /// An integer in [0, 2^64 - 1].
  uint64_t unsigned_integer() const;
  bool boolean() const;
  const std::string& string() const;
  /// An array of three finite numbers.
  glm::dvec3 vec3() const;

  // --- optional members with defaults ----------------------------------------------------------
  double number_or(std::string_view key, double fallback) const;
  bool boolean_or(std::string_view key, bool fallback) const;
  glm::dvec3 vec3_or(std::string_view key, const glm::dvec3& fallback) const;

 private:
  [[noreturn]] void fail_type(std::string_view expected) const;

  const Json* json_;
  std::string path_;
};

}  // namespace tessera
