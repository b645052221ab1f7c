#include "scene/mitsuba/mitsuba_xml_document.h"

#include <algorithm>
#include <cctype>
#include <pugixml.hpp>

#include "scene/bundle_path.h"
#include "scene/mitsuba/mitsuba_file_resolver.h"
#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// The parameters declared by <default>, longest name first (see read_mitsuba_document).
class Parameters {
 public:
  /// Declares `$name` unless it exists: the first declaration wins.
  void declare(const std::string& name, const std::string& value) {
    std::string key = "$" + name;
    for (const Entry& e : entries_) {
      if (e.key == key) return;
    }
    auto at = std::find_if(entries_.begin(), entries_.end(),
                           [&](const Entry& e) { return key.size() > e.key.size(); });
    entries_.insert(at, Entry{key, value});
  }

  /// `text` with every unescaped `$name` replaced; returns the name of an undeclared parameter
  /// in `undefined` (and the text unchanged) when one is left.
  std::string substitute(std::string text, std::string& undefined) const {
    for (const Entry& e : entries_) {
      size_t pos = 0;
      while ((pos = text.find(e.key, pos)) != std::string::npos) {
        if (pos > 0 && text[pos - 1] == '\\') {
          pos += e.key.size();
        } else {
          text.replace(pos, e.key.size(), e.value);
          pos += e.value.size();
        }
      }
    }
    for (size_t pos = 0; (pos = text.find('$', pos)) != std::string::npos; ++pos) {
      if (pos > 0 && text[pos - 1] == '\\') continue;
      size_t end = pos + 1;
      while (end < text.size() &&
             (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_')) {
        ++end;
      }
      undefined = text.substr(pos + 1, end - pos - 1);
      return text;
    }
    for (size_t pos = 0; (pos = text.find("\\$", pos)) != std::string::npos; ++pos) {
      text.erase(pos, 1);
    }
    return text;
  }

 private:
  struct Entry {
    std::string key;  ///< "$name"
    std::string value;
  };
  std::vector<Entry> entries_;
};

/// One XML file of the scene: its name for messages, its folder for relative paths, and where
/// its lines start.
struct Source {
  std::string name;
  std::string folder;  ///< bundle path of its folder, "" at the root, else ending in '/'
  std::vector<size_t> newlines;

  Source(std::string name_, std::string folder_, std::string_view text)
      : name(std::move(name_)), folder(std::move(folder_)) {
    for (size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '\n') newlines.push_back(i);
    }
  }

  /// The 1-based line holding byte `offset` (0 when pugixml does not know the offset).
  int line_of(ptrdiff_t offset) const {
    if (offset < 0) return 0;
    return int(std::lower_bound(newlines.begin(), newlines.end(), size_t(offset)) -
               newlines.begin()) +
           1;
  }
};

/// "a/b/" for "a/b/c.xml", "" for "c.xml".
std::string folder_of(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

/// True for "3", "3.0", "3.0.0", "2.1.0", ...: a version Mitsuba 3 reads as it is (older files
/// need Mitsuba's upgrade of parameter names first).
bool is_version_3(const std::string& version) {
  if (version.empty() || (version[0] != '3' && version[0] != '2')) return false;
  bool digit_expected = false;
  for (size_t i = 1; i < version.size(); ++i) {
    char c = version[i];
    if (c == '.' && !digit_expected) {
      digit_expected = true;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      digit_expected = false;
    } else {
      return false;
    }
  }
  return !digit_expected;
}

void expect_attributes(const MitsubaElement& element,
                       std::initializer_list<std::string_view> required) {
  for (const auto& [name, value] : element.attributes) {
    if (std::find(required.begin(), required.end(), name) == required.end()) {
      fail_at(element, "unexpected attribute \"" + printable(name) + "\"");
    }
  }
  for (std::string_view name : required) {
    if (!element.attribute(name)) {
      fail_at(element, "missing attribute \"" + std::string(name) + "\"");
    }
  }
}

class DocumentReader {
 public:
  DocumentReader(const FileReader& reader, const std::string& file_name,
                 const std::string& root_name, MitsubaReach reach)
      : resolver_(reader, folder_of(file_name), root_name) {
    if (reach == MitsubaReach::scene_folders) resolver_.confine_to({folder_of(file_name)});
  }

  MitsubaDocument read(std::string_view xml, const std::string& file_name) {
    pugi::xml_document document;
    Source source(file_name, folder_of(file_name), xml);
    pugi::xml_node root = parse(document, xml, source);
    MitsubaDocument result;
    result.scene = element_of(root, source);
    if (result.scene.tag != "scene") {
      fail_at(result.scene, "the root element must be <scene version=\"3.x.y\">");
    }
    check_version(result.scene);
    include_stack_.push_back(file_name);
    read_children(root, source, result.scene, 1, 0);
    result.files_read = std::move(files_read_);
    result.search_folders = resolver_.folders();
    result.confined_to = resolver_.confined_to();
    return result;
  }

 private:
  pugi::xml_node parse(pugi::xml_document& document, std::string_view xml, const Source& source) {
    // UTF-8 as is (no conversion), so that offsets are offsets into `xml`. DOCTYPE sections are
    // skipped, never expanded.
    pugi::xml_parse_result result =
        document.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!result) {
      throw SceneError(printable(source.name) + ": line " +
                       std::to_string(source.line_of(result.offset)) +
                       ": malformed XML: " + result.description());
    }
    pugi::xml_node root = document.document_element();
    if (!root) throw SceneError(printable(source.name) + ": no XML element");
    return root;
  }

  void check_version(const MitsubaElement& root) {
    const std::string* version = root.attribute("version");
    if (!version) fail_at(root, "missing attribute \"version\" (write version=\"3.0.0\")");
    if (!is_version_3(*version)) {
      fail_at(root, "version \"" + printable(*version) +
                        "\": Tessera reads Mitsuba 3 scenes (version=\"3.x.y\" or \"2.x.y\"); "
                        "upgrade older files with Mitsuba 3 first");
    }
  }

  /// The element with its attributes substituted, not yet its children.
  MitsubaElement element_of(pugi::xml_node node, const Source& source) {
    MitsubaElement element;
    element.tag = node.name();
    element.file = source.name;
    element.folder = source.folder;
    element.line = source.line_of(node.offset_debug());
    if (++element_count_ > kMaxMitsubaElements) {
      fail_at(element,
              "the scene has more than " + std::to_string(kMaxMitsubaElements) + " elements");
    }
    for (pugi::xml_attribute attribute : node.attributes()) {
      element.attributes.emplace_back(attribute.name(), attribute.value());
    }
    for (auto& [name, value] : element.attributes) {
      if (value.find('$') == std::string::npos) continue;
      std::string undefined;
      value = parameters_.substitute(value, undefined);
      if (!undefined.empty()) {
        fail_at(element, "undefined parameter $" + printable(undefined) +
                             " (declare it with <default name=\"" + printable(undefined) +
                             "\" value=\"...\"/>, or give -D " +
                             printable(undefined) + "=VALUE)");
      }
    }
    return element;
  }

  void read_children(pugi::xml_node node, const Source& source, MitsubaElement& parent, int depth,
                     int include_depth) {
    for (pugi::xml_node child : node.children()) {
      if (child.type() != pugi::node_element) continue;
      read_element(child, source, parent, depth, include_depth);
    }
  }

  void read_element(pugi::xml_node node, const Source& source, MitsubaElement& parent, int depth,
                    int include_depth) {
    add_element(element_of(node, source), node, source, parent, depth, include_depth);
  }

  /// Adds `element` (read from `node`) and its children to `parent`, or applies it when it is a
  /// <default> or an <include>.
  void add_element(MitsubaElement element, pugi::xml_node node, const Source& source,
                   MitsubaElement& parent, int depth, int include_depth) {
    if (depth >= kMaxMitsubaElementDepth) {
      fail_at(element,
              "elements nested more than " + std::to_string(kMaxMitsubaElementDepth) + " deep");
    }
    if (element.tag == "default") {
      expect_attributes(element, {"name", "value"});
      if (element.attribute("name")->empty()) fail_at(element, "name must not be empty");
      parameters_.declare(*element.attribute("name"), *element.attribute("value"));
      return;
    }
    if (element.tag == "include") {
      include(element, parent, depth, include_depth);
      return;
    }
    if (element.tag == "path") {
      add_search_folder(element, parent, depth);
      return;
    }
    read_children(node, source, element, depth + 1, include_depth);
    parent.children.push_back(std::move(element));
  }

  /// <path value="dir"/>: a folder searched first from now on (as Mitsuba's FileResolver).
  void add_search_folder(const MitsubaElement& element, const MitsubaElement& parent, int depth) {
    expect_attributes(element, {"value"});
    if (parent.tag != "scene" || depth != 1) {
      fail_at(element, "a <path> must be a child of the <scene>");
    }
    const std::string& value = *element.attribute("value");
    std::string folder = value.empty() || value == "." || value == "./"
                             ? element.folder
                             : join_bundle_path(element.folder, value, element.where(),
                                                resolver_.root_name()) +
                                   "/";
    resolver_.prepend(folder);
  }

  void include(const MitsubaElement& element, MitsubaElement& parent, int depth,
               int include_depth) {
    expect_attributes(element, {"filename"});
    if (include_depth + 1 >= kMaxMitsubaIncludeDepth) {
      fail_at(element,
              "includes nest more than " + std::to_string(kMaxMitsubaIncludeDepth) + " deep");
    }
    std::string path =
        resolver_.resolve(element, *element.attribute("filename"), element.folder);
    if (std::find(include_stack_.begin(), include_stack_.end(), path) != include_stack_.end()) {
      fail_at(element, "\"" + printable(path) + "\" includes itself");
    }
    std::string text = resolver_.read(path);
    const std::vector<std::string> search = resolver_.folders();
    if (std::find(files_read_.begin(), files_read_.end(), path) == files_read_.end()) {
      files_read_.push_back(path);
    }
    pugi::xml_document document;
    Source source(path, folder_of(path), text);
    pugi::xml_node root = parse(document, text, source);
    MitsubaElement root_element = element_of(root, source);
    check_version(root_element);
    include_stack_.push_back(path);
    if (root_element.tag == "scene") {
      read_children(root, source, parent, depth, include_depth + 1);
    } else {
      // The root's version is the file's, not a parameter of the element.
      std::erase_if(root_element.attributes, [](const auto& a) { return a.first == "version"; });
      add_element(std::move(root_element), root, source, parent, depth, include_depth + 1);
    }
    include_stack_.pop_back();
    resolver_.reset(search);
  }

  MitsubaFileResolver resolver_;
  Parameters parameters_;
  std::vector<std::string> include_stack_;  ///< the scene file, then the includes being read
  std::vector<std::string> files_read_;
  size_t element_count_ = 0;
};

}  // namespace

const std::string* MitsubaElement::attribute(std::string_view name) const {
  for (const auto& [key, value] : attributes) {
    if (key == name) return &value;
  }
  return nullptr;
}

std::string MitsubaElement::label() const {
  std::string text = "<" + printable(tag);
  for (std::string_view key : {"type", "id", "name"}) {
    if (const std::string* value = attribute(key)) {
      text += " " + std::string(key) + "=\"" + printable(*value) + "\"";
    }
  }
  return text + ">";
}

std::string MitsubaElement::where() const {
  return printable(file) + ": line " + std::to_string(line) + ": " + label();
}

void fail_at(const MitsubaElement& element, std::string_view message) {
  throw SceneError(element.where() + ": " + std::string(message));
}

MitsubaDocument read_mitsuba_document(std::string_view xml, const std::string& file_name,
                                      const FileReader& reader, const std::string& root_name,
                                      MitsubaReach reach) {
  return DocumentReader(reader, file_name, root_name, reach).read(xml, file_name);
}

}  // namespace tessera
