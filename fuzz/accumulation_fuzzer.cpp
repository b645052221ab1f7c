// libFuzzer target: decoding a work unit's result (core/accum/accumulation_codec), the bytes a
// worker uploads and the server decodes before anything else (docs/reliability.md).
//
// Checks, besides crashes and ASan/UBSan findings, the codec's promises:
// - every refusal is a CodecError (never another exception, never a read out of bounds);
// - it never allocates more than the header's rectangle needs, and refuses rectangles above
//   max_pixels (here 2^16, so libFuzzer's memory limit would catch an allocation taken on trust);
// - what it accepts is consistent (arrays sized by the rectangle) and encodes back to bytes that
//   decode to the same values bit for bit.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>

#include "accum/accumulation_codec.h"

namespace {

[[noreturn]] void broken_promise(const char* what, const std::string& detail) {
  std::fprintf(stderr, "%s\n%s\n", what, detail.c_str());
  std::abort();
}

template <typename T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr int64_t kMaxPixels = int64_t(1) << 16;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  tessera::Accumulation acc;
  try {
    acc = tessera::decode_accumulation(bytes, kMaxPixels);
  } catch (const tessera::CodecError&) {
    return 0;
  } catch (const std::exception& e) {
    broken_promise("an exception other than CodecError escaped the decoder:", e.what());
  }
  const size_t pixels = acc.pixels();
  const int64_t rect_pixels =
      (int64_t(acc.rect.x1) - acc.rect.x0) * (int64_t(acc.rect.y1) - acc.rect.y0);
  if (int64_t(pixels) != rect_pixels || int64_t(pixels) > kMaxPixels || acc.rgb.size() != 3 * pixels || acc.lum2.size() != pixels ||
      acc.count.size() != pixels) {
    broken_promise("a decoded accumulation is inconsistent with its rectangle", "");
  }
  try {
    const tessera::Accumulation again =
        tessera::decode_accumulation(tessera::encode_accumulation(acc), kMaxPixels);
    if (!same_bits(acc.rgb, again.rgb) || !same_bits(acc.lum2, again.lum2) ||
        !same_bits(acc.count, again.count)) {
      broken_promise("encode(decode(x)) does not decode to the same bits", "");
    }
  } catch (const tessera::CodecError& e) {
    broken_promise("a decoded accumulation does not survive a re-encode:", e.what());
  }
  return 0;
}
