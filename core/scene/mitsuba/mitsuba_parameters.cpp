#include "scene/mitsuba/mitsuba_parameters.h"

#include <algorithm>
#include <cctype>
#include <pugixml.hpp>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

bool is_parameter_name(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

/// `text` as the value of an XML attribute in double quotes.
std::string xml_attribute(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\n': out += "&#10;"; break;
      case '\r': out += "&#13;"; break;
      case '\t': out += "&#9;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

MitsubaParameter parse_mitsuba_define(std::string_view text) {
  const std::string where = "-D " + printable(std::string(text)) + ": ";
  const size_t equals = text.find('=');
  if (equals == std::string_view::npos) {
    throw SceneError(where + "write -D name=value");
  }
  MitsubaParameter parameter{std::string(text.substr(0, equals)),
                             std::string(text.substr(equals + 1))};
  if (!is_parameter_name(parameter.name)) {
    throw SceneError(where + "a parameter's name is letters, digits and '_' (as in $spp)");
  }
  if (parameter.value.find('$') != std::string::npos) {
    throw SceneError(where + "a value must not hold '$' (it is not substituted again)");
  }
  return parameter;
}

MitsubaParameters parse_mitsuba_defines(const std::vector<std::string>& texts) {
  MitsubaParameters parameters;
  for (const std::string& text : texts) {
    MitsubaParameter parameter = parse_mitsuba_define(text);
    for (const MitsubaParameter& earlier : parameters) {
      if (earlier.name == parameter.name) {
        throw SceneError("-D " + parameter.name + " given twice");
      }
    }
    parameters.push_back(std::move(parameter));
  }
  return parameters;
}

std::string with_mitsuba_parameters(std::string_view xml, const std::string& file_name,
                                    const MitsubaParameters& parameters) {
  if (parameters.empty()) return std::string(xml);
  pugi::xml_document document;
  const pugi::xml_parse_result parsed =
      document.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
  const pugi::xml_node root = document.document_element();
  // Malformed XML is reported by the scene reader, with its line; here it only matters where
  // the root's start tag ends.
  if (!parsed || !root) return std::string(xml);
  const ptrdiff_t start = root.offset_debug();
  if (start < 0 || size_t(start) >= xml.size()) {
    throw SceneError(printable(file_name) + ": malformed XML: no root element");
  }
  // The start tag ends at the first '>' outside a quoted attribute value.
  char quote = 0;
  size_t end = size_t(start);
  for (; end < xml.size(); ++end) {
    const char c = xml[end];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '>') {
      break;
    }
  }
  if (end == xml.size()) throw SceneError(printable(file_name) + ": malformed XML: root tag");
  if (xml[end - 1] == '/') return std::string(xml);  // <scene .../>: nothing to substitute
  std::string defaults;
  for (const MitsubaParameter& p : parameters) {
    defaults += "<default name=\"" + p.name + "\" value=\"" + xml_attribute(p.value) + "\"/>";
  }
  std::string out(xml.substr(0, end + 1));
  out += defaults;
  out += xml.substr(end + 1);
  return out;
}

}  // namespace tessera
