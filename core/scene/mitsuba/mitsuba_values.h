// How Mitsuba writes numbers in attributes: value="0.5", value="1, 2, 3", value="1 2 3".
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tessera {

/// The items of a list attribute, split at commas and white space (empty items dropped), as
/// Mitsuba's tokenizer does.
std::vector<std::string_view> split_mitsuba_list(std::string_view text);

/// A finite double written in decimal (surrounding white space and a leading '+' allowed), or
/// nullopt. "inf", "nan", hexadecimal and trailing characters are refused.
std::optional<double> parse_mitsuba_float(std::string_view text);

/// A decimal integer in int64 range (surrounding white space allowed), or nullopt.
std::optional<int64_t> parse_mitsuba_integer(std::string_view text);

/// Exactly `count` numbers from a list attribute, or nullopt.
std::optional<std::vector<double>> parse_mitsuba_floats(std::string_view text, size_t count);

}  // namespace tessera
