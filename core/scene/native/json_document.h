// Turning scene file text into a JSON tree, with messages a person can act on.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace tessera {

/// The scene's JSON tree. Ordered, so that materials keep the order of the file.
using Json = nlohmann::ordered_json;

/// Parses JSON text; `//` and `/* */` comments are allowed.
///
/// Throws SceneError:
/// - "<source_name>: line L, column C: <parser message>" for malformed text (L and C 1-based,
///   C counted in bytes);
/// - "<json path>: duplicate key" when an object repeats a key (JSON allows it, but the second
///   value would silently win).
Json parse_json_document(std::string_view text, const std::string& source_name);

}  // namespace tessera
