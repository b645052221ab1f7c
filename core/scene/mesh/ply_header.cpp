#include "scene/mesh/ply_header.h"

#include <charconv>
#include <sstream>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

/// Headers are small; a file whose first 1 MiB holds no end_header is not a PLY file we read.
constexpr size_t kMaxHeaderBytes = 1 << 20;

struct HeaderLine {
  size_t number;  ///< 1-based
  std::vector<std::string> words;
};

[[noreturn]] void fail(const std::string& name, size_t line, const std::string& message) {
  throw SceneError(name + ": line " + std::to_string(line) + ": " + message);
}

PlyType parse_type(const std::string& word, const std::string& name, size_t line) {
  static const std::pair<const char*, PlyType> kTypes[] = {
      {"char", PlyType::int8},      {"int8", PlyType::int8},       {"uchar", PlyType::uint8},
      {"uint8", PlyType::uint8},    {"short", PlyType::int16},     {"int16", PlyType::int16},
      {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},   {"int", PlyType::int32},
      {"int32", PlyType::int32},    {"uint", PlyType::uint32},     {"uint32", PlyType::uint32},
      {"float", PlyType::float32},  {"float32", PlyType::float32}, {"double", PlyType::float64},
      {"float64", PlyType::float64}};
  for (const auto& [text, type] : kTypes) {
    if (word == text) return type;
  }
  fail(name, line, "unknown property type \"" + printable(word) + "\"");
}

PlyFormat parse_format(const HeaderLine& line, const std::string& name) {
  if (line.words.size() != 3) fail(name, line.number, "expected \"format <encoding> 1.0\"");
  if (line.words[2] != "1.0" && line.words[2] != "1") {
    fail(name, line.number, "unsupported PLY version " + printable(line.words[2]));
  }
  const std::string& encoding = line.words[1];
  if (encoding == "ascii") return PlyFormat::ascii;
  if (encoding == "binary_little_endian") return PlyFormat::binary_little_endian;
  if (encoding == "binary_big_endian") return PlyFormat::binary_big_endian;
  fail(name, line.number, "unknown format \"" + printable(encoding) + "\"");
}

PlyElement parse_element(const HeaderLine& line, const std::string& name) {
  if (line.words.size() != 3) fail(name, line.number, "expected \"element <name> <count>\"");
  PlyElement element;
  element.name = line.words[1];
  const std::string& count = line.words[2];
  auto [end, error] = std::from_chars(count.data(), count.data() + count.size(), element.count);
  if (error != std::errc() || end != count.data() + count.size()) {
    fail(name, line.number, "bad element count \"" + printable(count) + "\"");
  }
  return element;
}

PlyProperty parse_property(const HeaderLine& line, const std::string& name) {
  const std::vector<std::string>& w = line.words;
  PlyProperty property;
  if (w.size() == 5 && w[1] == "list") {
    property.is_list = true;
    property.count_type = parse_type(w[2], name, line.number);
    property.type = parse_type(w[3], name, line.number);
    property.name = w[4];
    if (!ply_type_is_integer(property.count_type)) {
      fail(name, line.number, "list count type must be an integer type");
    }
  } else if (w.size() == 3) {
    property.type = parse_type(w[1], name, line.number);
    property.name = w[2];
  } else {
    fail(name, line.number, "expected \"property <type> <name>\" or \"property list ...\"");
  }
  return property;
}

/// Splits the header into lines of words; sets `data_offset` past "end_header".
std::vector<HeaderLine> split_header(std::string_view bytes, const std::string& name,
                                     size_t& data_offset) {
  std::vector<HeaderLine> lines;
  size_t pos = 0;
  while (pos < bytes.size() && pos < kMaxHeaderBytes) {
    size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) break;
    std::string text(bytes.substr(pos, end - pos));
    if (!text.empty() && text.back() == '\r') text.pop_back();
    pos = end + 1;
    HeaderLine line{lines.size() + 1, {}};
    std::istringstream words(text);
    for (std::string word; words >> word;) line.words.push_back(word);
    if (line.words.size() == 1 && line.words[0] == "end_header") {
      data_offset = pos;
      return lines;
    }
    lines.push_back(std::move(line));
  }
  throw SceneError(name + ": the header has no end_header line");
}

/// Refuses counts that cannot fit in the data: a hostile header must not make us allocate.
void check_counts_fit(const PlyHeader& header, size_t data_size, const std::string& name) {
  long double needed = 0;  // can exceed 2^64 with hostile counts
  for (const PlyElement& element : header.elements) {
    needed += static_cast<long double>(element.count) * element.min_row_size(header.format);
    if (needed > static_cast<long double>(data_size)) {
      throw SceneError(name + ": element \"" + printable(element.name) + "\" declares " +
                       std::to_string(element.count) + " rows, which cannot fit in the file (" +
                       std::to_string(data_size) + " bytes of data)");
    }
  }
}

}  // namespace

size_t ply_type_size(PlyType type) {
  switch (type) {
    case PlyType::int8:
    case PlyType::uint8:
      return 1;
    case PlyType::int16:
    case PlyType::uint16:
      return 2;
    case PlyType::int32:
    case PlyType::uint32:
    case PlyType::float32:
      return 4;
    case PlyType::float64:
      return 8;
  }
  return 0;
}

bool ply_type_is_integer(PlyType type) {
  return type != PlyType::float32 && type != PlyType::float64;
}

int PlyElement::find(std::string_view property_name) const {
  for (size_t i = 0; i < properties.size(); ++i) {
    if (properties[i].name == property_name) return static_cast<int>(i);
  }
  return -1;
}

uint64_t PlyElement::min_row_size(PlyFormat format) const {
  uint64_t size = 0;
  for (const PlyProperty& p : properties) {
    if (format == PlyFormat::ascii) {
      size += 1;  // at least one character per value (a list: its count)
    } else {
      size += ply_type_size(p.is_list ? p.count_type : p.type);
    }
  }
  return size;
}

const PlyElement* PlyHeader::find(std::string_view element_name) const {
  for (const PlyElement& element : elements) {
    if (element.name == element_name) return &element;
  }
  return nullptr;
}

PlyHeader parse_ply_header(std::string_view bytes, const std::string& name) {
  if (!bytes.starts_with("ply\n") && !bytes.starts_with("ply\r\n")) {
    throw SceneError(name + ": not a PLY file (it does not start with \"ply\")");
  }
  PlyHeader header;
  std::vector<HeaderLine> lines = split_header(bytes, name, header.data_offset);
  bool has_format = false;
  for (size_t i = 1; i < lines.size(); ++i) {
    const HeaderLine& line = lines[i];
    if (line.words.empty()) continue;
    const std::string& keyword = line.words[0];
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      if (has_format) fail(name, line.number, "second format line");
      header.format = parse_format(line, name);
      has_format = true;
    } else if (keyword == "element") {
      PlyElement element = parse_element(line, name);
      if (header.find(element.name)) {
        fail(name, line.number, "element \"" + printable(element.name) + "\" declared twice");
      }
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail(name, line.number, "property before any element");
      header.elements.back().properties.push_back(parse_property(line, name));
    } else {
      fail(name, line.number, "unexpected \"" + printable(keyword) + "\" in the header");
    }
  }
  if (!has_format) throw SceneError(name + ": the header has no format line");
  check_counts_fit(header, bytes.size() - header.data_offset, name);
  return header;
}

}  // namespace tessera
