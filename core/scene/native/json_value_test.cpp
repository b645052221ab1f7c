// printable(): how a message quotes input (core/scene/message_text.h).
#include "scene/native/json_value.h"

#include <gtest/gtest.h>

#include <string>

#include "scene/native/native_test_support.h"

namespace tessera {
namespace {

TEST(PrintableInput, ShortTextIsKeptWithControlCharactersEscaped) {
  EXPECT_EQ(printable("plain"), "plain");
  EXPECT_EQ(printable(std::string("a\0b\nc", 5)), "a\\x00b\\x0ac");
  EXPECT_EQ(printable(std::string(kQuotedInputBytes, 'k')), std::string(kQuotedInputBytes, 'k'));
}

TEST(PrintableInput, LongTextIsCutAndMarked) {
  const std::string quoted = printable(std::string(50'000'000, 'k'));
  EXPECT_EQ(quoted, std::string(kQuotedInputBytes, 'k') + "\u2026");
}

TEST(PrintableInput, TheCutNeverSplitsAUtf8Character) {
  // 199 ASCII bytes, then a 3-byte character across the 200-byte bound.
  const std::string text = std::string(kQuotedInputBytes - 1, 'a') + "\u20ac" + "tail";
  EXPECT_EQ(printable(text), std::string(kQuotedInputBytes - 1, 'a') + "\u2026");
  EXPECT_EQ(printable_whole(text), text);
}

TEST(PrintableInput, AnUnknownKeyOfAnyLengthMakesAShortMessage) {
  const std::string message =
      testing::error_of(testing::scene_with_shapes("", "\"" + std::string(1'000'000, 'x') + "\": 1, "));
  EXPECT_LT(message.size(), 1000u) << message.substr(0, 300);
  EXPECT_NE(message.find("unknown key"), std::string::npos) << message.substr(0, 300);
  EXPECT_NE(message.find("\u2026"), std::string::npos) << message.substr(0, 300);
}

}  // namespace
}  // namespace tessera
