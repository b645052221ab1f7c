// Mitsuba's command-line parameters, `-D name=value` (docs/mitsuba.md, "Parameters"): the values
// of a scene's `$name` parameters given by the user, which override the scene's <default>s.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tessera {

/// One `-D name=value`.
struct MitsubaParameter {
  std::string name;   ///< letters, digits and '_', not empty
  std::string value;  ///< any text without '$'
};

/// In the order given on the command line; no name twice.
using MitsubaParameters = std::vector<MitsubaParameter>;

/// Reads the text of one `-D` option, "name=value" (split at the first '='; the value may be
/// empty and may hold further '='). Throws SceneError("-D <text>: ...") when there is no '=',
/// the name is empty or holds anything but letters, digits and '_', or the value holds a '$'
/// (a parameter's value is never substituted again).
MitsubaParameter parse_mitsuba_define(std::string_view text);

/// parse_mitsuba_define on each text, refusing a name given twice ("-D spp given twice").
MitsubaParameters parse_mitsuba_defines(const std::vector<std::string>& texts);

/// The Mitsuba 3 XML text `xml` of the scene file `file_name` with one
/// `<default name="n" value="v"/>` per parameter written right after the root element's start
/// tag, on the same line (every later line keeps its number, so messages still name the lines
/// of the file on disk). Since the first declaration of a parameter wins, these override the
/// scene's own <default>s, as Mitsuba's `-D` does; a bundle carries this text, so the farm
/// reads the scene as `tessera-worker render` does. Returns `xml` unchanged when `parameters`
/// is empty or the root element is empty (`<scene .../>` uses no parameter). Throws SceneError
/// ("<file_name>: malformed XML ...") when no root start tag can be found.
std::string with_mitsuba_parameters(std::string_view xml, const std::string& file_name,
                                    const MitsubaParameters& parameters);

}  // namespace tessera
