#include "scene/mesh/ply_value_reader.h"

#include <bit>
#include <charconv>
#include <cstring>
#include <limits>

#include "scene/message_text.h"
#include "scene/scene_error.h"

namespace tessera {
namespace {

template <typename T>
T load(const char* bytes, bool swap) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, bytes, sizeof(T));
  if (swap) {
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

/// The range of values an integer type holds, to refuse "300" for a uchar.
void integer_range(PlyType type, int64_t& min, int64_t& max) {
  switch (type) {
    case PlyType::int8:
      min = -128, max = 127;
      break;
    case PlyType::uint8:
      min = 0, max = 255;
      break;
    case PlyType::int16:
      min = -32768, max = 32767;
      break;
    case PlyType::uint16:
      min = 0, max = 65535;
      break;
    case PlyType::int32:
      min = std::numeric_limits<int32_t>::min(), max = std::numeric_limits<int32_t>::max();
      break;
    default:
      min = 0, max = std::numeric_limits<uint32_t>::max();
      break;
  }
}

}  // namespace

PlyValueReader::PlyValueReader(std::string_view data, PlyFormat format, std::string name,
                               size_t first_line)
    : data_(data),
      format_(format),
      swap_((format == PlyFormat::binary_big_endian) != (std::endian::native == std::endian::big)),
      name_(std::move(name)),
      line_(first_line) {}

std::string PlyValueReader::where() const {
  std::string place =
      element_ ? "element " + printable(*element_) + ", row " + std::to_string(row_) : "data";
  if (format_ == PlyFormat::ascii) place = "line " + std::to_string(line_) + " (" + place + ")";
  return place;
}

void PlyValueReader::fail(const std::string& message) const {
  throw SceneError(name_ + ": " + where() + ": " + message);
}

std::string_view PlyValueReader::next_token() {
  while (pos_ < data_.size() && is_space(data_[pos_])) {
    if (data_[pos_] == '\n') ++line_;
    ++pos_;
  }
  if (pos_ == data_.size()) fail("unexpected end of file");
  size_t start = pos_;
  while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
  return data_.substr(start, pos_ - start);
}

const char* PlyValueReader::next_bytes(size_t size) {
  if (data_.size() - pos_ < size) fail("unexpected end of file");
  const char* bytes = data_.data() + pos_;
  pos_ += size;
  return bytes;
}

double PlyValueReader::number(PlyType type) {
  if (ply_type_is_integer(type)) return static_cast<double>(integer(type));
  if (format_ == PlyFormat::ascii) {
    std::string_view token = next_token();
    double value = 0;
    auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size()) {
      fail("expected a number (got \"" + printable(token) + "\")");
    }
    return value;
  }
  if (type == PlyType::float32) return load<float>(next_bytes(4), swap_);
  return load<double>(next_bytes(8), swap_);
}

int64_t PlyValueReader::integer(PlyType type) {
  if (!ply_type_is_integer(type)) fail("expected an integer type");
  if (format_ == PlyFormat::ascii) {
    std::string_view token = next_token();
    int64_t value = 0;
    auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    int64_t min, max;
    integer_range(type, min, max);
    if (error != std::errc() || end != token.data() + token.size() || value < min || value > max) {
      fail("expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) +
           "] (got \"" + printable(token) + "\")");
    }
    return value;
  }
  const char* bytes = next_bytes(ply_type_size(type));
  switch (type) {
    case PlyType::int8:
      return load<int8_t>(bytes, false);
    case PlyType::uint8:
      return load<uint8_t>(bytes, false);
    case PlyType::int16:
      return load<int16_t>(bytes, swap_);
    case PlyType::uint16:
      return load<uint16_t>(bytes, swap_);
    case PlyType::int32:
      return load<int32_t>(bytes, swap_);
    default:
      return load<uint32_t>(bytes, swap_);
  }
}

void PlyValueReader::skip(PlyType type) {
  if (format_ == PlyFormat::ascii) {
    number(type);  // still checked: a skipped value that is not a number is a broken file
  } else {
    next_bytes(ply_type_size(type));
  }
}

void PlyValueReader::skip_rows(uint64_t count, uint64_t row_bytes) {
  // Counts were checked against the file size by parse_ply_header; check again, cheaply.
  if (row_bytes != 0 && count > (data_.size() - pos_) / row_bytes) fail("unexpected end of file");
  pos_ += count * row_bytes;
}

}  // namespace tessera
