#include "scene/native/json_document.h"

#include <set>
#include <vector>

#include "scene/native/json_value.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Where the parser is, to name the JSON path of a duplicate key or of a number too large for
/// a double. The parser's callback tells
/// us about objects, arrays, keys and values in document order; we keep one frame per open
/// container.
class PathTracker {
 public:
  bool on_event(nlohmann::detail::parse_event_t event, const Json& parsed) {
    using Event = nlohmann::detail::parse_event_t;
    switch (event) {
      case Event::object_start:
        frames_.push_back(Frame{true, {}, 0, {}});
        break;
      case Event::array_start:
        frames_.push_back(Frame{false, {}, 0, {}});
        break;
      case Event::key:
        on_key(parsed.get_ref<const std::string&>());
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        on_value_done();
        break;
      case Event::value:
        on_value_done();
        break;
    }
    return true;
  }

  /// The JSON path of the value being parsed, e.g. "shapes[2].radius".
  std::string current_path() const {
    if (frames_.empty()) return "";
    std::string path = path_of_top();
    const Frame& top = frames_.back();
    if (top.is_object) return path.empty() ? printable(top.key) : path + "." + printable(top.key);
    return path + "[" + std::to_string(top.index) + "]";
  }

 private:
  struct Frame {
    bool is_object;
    std::string key;  ///< objects: the key whose value is being parsed
    size_t index;     ///< arrays: the index of the element being parsed
    std::set<std::string> keys;
  };

  void on_key(const std::string& key) {
    Frame& top = frames_.back();
    if (!top.keys.insert(key).second) {
      std::string path = path_of_top();
      throw SceneError((path.empty() ? printable(key) : path + "." + printable(key)) +
                       ": duplicate key");
    }
    top.key = key;
  }

  void on_value_done() {
    if (!frames_.empty() && !frames_.back().is_object) ++frames_.back().index;
  }

  /// The JSON path of the innermost open container, e.g. "shapes[2].transform".
  std::string path_of_top() const {
    std::string path;
    for (size_t i = 0; i + 1 < frames_.size(); ++i) {
      const Frame& parent = frames_[i];
      if (parent.is_object) {
        path += (path.empty() ? "" : ".") + printable(parent.key);
      } else {
        path += "[" + std::to_string(parent.index) + "]";
      }
    }
    return path;
  }

  std::vector<Frame> frames_;
};

/// The literal in nlohmann's "number overflow parsing '1e999'".
std::string quoted_literal(const std::string& what) {
  size_t open = what.find('\'');
  size_t close = what.rfind('\'');
  if (open == std::string::npos || close <= open) return "the value";
  return what.substr(open + 1, close - open - 1);
}

/// nlohmann's message without its "[json.exception...] parse error at line L, column C: "
/// prefix: we compute the position ourselves from the byte offset.
std::string parser_message(const std::string& what) {
  size_t column = what.find("column ");
  size_t colon = what.find(": ", column == std::string::npos ? 0 : column);
  if (colon != std::string::npos) return what.substr(colon + 2);
  size_t bracket = what.find("] ");
  return bracket == std::string::npos ? what : what.substr(bracket + 2);
}

/// 1-based line and column of the byte nlohmann's parse_error::byte points at (the last byte it
/// read, counted from 1).
std::string position_of(std::string_view text, size_t byte) {
  size_t last = byte == 0 ? 0 : std::min(byte - 1, text.size());
  size_t line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < last && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(last - line_start + 1);
}

}  // namespace

Json parse_json_document(std::string_view text, const std::string& source_name) {
  PathTracker tracker;
  auto callback = [&tracker](int, nlohmann::detail::parse_event_t event, Json& parsed) {
    return tracker.on_event(event, parsed);
  };
  try {
    return Json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& e) {
    throw SceneError(source_name + ": " + position_of(text, e.byte) + ": " +
                     printable(parser_message(e.what())));
  } catch (const Json::out_of_range& e) {
    // The only range error of parsing: a number literal beyond double's range, like 1e999.
    std::string path = tracker.current_path();
    throw SceneError((path.empty() ? source_name : path) + ": must be a finite number (" +
                     quoted_literal(e.what()) + " is too large for a double)");
  }
}

}  // namespace tessera
