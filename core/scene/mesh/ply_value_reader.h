// Reading the values of a PLY body one at a time, in any of the three encodings.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "scene/mesh/ply_header.h"

namespace tessera {

/// A cursor over the data after a PLY header. Every read checks the bounds of the data and
/// throws SceneError("<name>: ...") naming the element and row being read (see locate()) when
/// the file ends early or, in ASCII, a value is not a number of the declared type.
class PlyValueReader {
 public:
  /// `data` is the body (after "end_header\n"); `first_line` is the line number of its first
  /// line, for ASCII messages.
  PlyValueReader(std::string_view data, PlyFormat format, std::string name, size_t first_line);

  /// Names the place for messages: row `row` (0-based) of element `element`.
  void locate(const std::string& element, uint64_t row) {
    element_ = &element;
    row_ = row;
  }

  /// A value of any type, as a double.
  double number(PlyType type);
  /// A value of an integer type.
  int64_t integer(PlyType type);
  /// Skips one value.
  void skip(PlyType type);
  /// Skips `count` rows of `row_bytes` bytes each (binary only; checked against the data).
  void skip_rows(uint64_t count, uint64_t row_bytes);

  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string_view next_token();
  const char* next_bytes(size_t size);
  std::string where() const;

  std::string_view data_;
  size_t pos_ = 0;
  PlyFormat format_;
  bool swap_;  ///< binary data in the other byte order than this machine's
  std::string name_;
  size_t line_;
  const std::string* element_ = nullptr;
  uint64_t row_ = 0;
};

}  // namespace tessera
