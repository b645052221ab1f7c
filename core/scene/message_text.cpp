#include "scene/message_text.h"

#include <charconv>
#include <cmath>

namespace tessera {

std::string format_number(double x, int significant) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  auto result = significant > 0 ? std::to_chars(buffer, buffer + sizeof buffer, x,
                                                std::chars_format::general, significant)
                                : std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string printable_whole(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      static const char kHex[] = "0123456789abcdef";
      out += {'\\', 'x', kHex[byte >> 4], kHex[byte & 15]};
    } else {
      out += c;
    }
  }
  return out;
}

std::string printable(std::string_view text, size_t max_bytes) {
  if (text.size() <= max_bytes) return printable_whole(text);
  size_t cut = max_bytes;
  // Back over UTF-8 continuation bytes (10xxxxxx) so that no character is split.
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xc0) == 0x80) --cut;
  return printable_whole(text.substr(0, cut)) + "\u2026";
}

}  // namespace tessera
