// Quoting input in messages: numbers and text as a SceneError (scene_error.h) writes them, one
// line and short, whatever the input holds. Used by every scene format and by the server's
// refusals.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace tessera {

/// Decimal text of `x` for messages: the shortest that reads back as `x` ("1.2", "1e+300",
/// "inf"), or rounded to `significant` digits when given (for measured values).
std::string format_number(double x, int significant = 0);

/// The most bytes of one piece of input a message quotes (printable()).
inline constexpr size_t kQuotedInputBytes = 200;

/// `text` for a message that quotes input: control characters (NUL included) written as \xNN,
/// so that the message stays one line and whole, and at most `max_bytes` of it (before escaping),
/// cut at a UTF-8 character boundary and ended with "…", so that a 50 MB key makes a short
/// message.
std::string printable(std::string_view text, size_t max_bytes = kQuotedInputBytes);

/// printable() without the length bound, for text that is written out whole (the comment line
/// of a converted scene).
std::string printable_whole(std::string_view text);

}  // namespace tessera
