// The tokenizer of short texts (issue 13 item 17): fields with their columns, whole-field numbers.
#include <gtest/gtest.h>

#include "gyroflip/core/error.hpp"
#include "gyroflip/core/text.hpp"

namespace gyroflip::text {
namespace {

TEST(Text, SplitKeepsEmptyFieldsAndColumns) {
  const auto t = split(" 0 ,, 180\t", ',');
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].text, "0");
  EXPECT_EQ(t[0].column, 2u);
  EXPECT_EQ(t[1].text, "");
  EXPECT_EQ(t[2].text, "180");
  EXPECT_EQ(t[2].column, 7u);
  EXPECT_EQ(split("", ',').size(), 1u);
  EXPECT_EQ(split("a:b:c", ':').size(), 3u);
}

TEST(Text, NumbersAreWholeFiniteAndLocaleFree) {
  EXPECT_EQ(to_double("+2.5"), 2.5);
  EXPECT_EQ(to_double(" -1e-3 "), -1e-3);
  EXPECT_EQ(to_double("0x10"), std::nullopt);  // no hex, no trailing text
  EXPECT_EQ(to_double("1,5"), std::nullopt);   // never a decimal comma
  EXPECT_EQ(to_double("1e999"), std::nullopt);
  EXPECT_EQ(to_double("nan"), std::nullopt);
  EXPECT_EQ(to_double("inf"), std::nullopt);
  EXPECT_EQ(to_double(""), std::nullopt);
  EXPECT_EQ(to_unsigned("42"), 42u);
  EXPECT_EQ(to_unsigned("-1"), std::nullopt);
  EXPECT_EQ(to_unsigned("18446744073709551616"), std::nullopt);  // 2^64
  EXPECT_EQ(to_unsigned("3.0"), std::nullopt);
  token bad;
  EXPECT_FALSE(to_doubles("1, 2, x3", ',', &bad));
  EXPECT_EQ(bad.text, "x3");
  EXPECT_EQ(bad.column, 7u);
  EXPECT_EQ(*to_doubles("1,-2", ','), (std::vector<double>{1.0, -2.0}));
}

TEST(Text, PrintableEscapesControlAndInvalidBytesButKeepsUtf8) {
  EXPECT_EQ(printable("a\nb"), "a\\x0ab");
  EXPECT_EQ(printable("caf\xc3\xa9"), "caf\xc3\xa9");
  EXPECT_EQ(printable("bad\xff"), "bad\\xff");
  EXPECT_EQ(printable("\xc2\x85"), "\\xc2\\x85");  // C1 control NEL
  EXPECT_EQ(printable(std::string(100, 'x'), 10), std::string(10, 'x') + "... (90 more bytes)");
  EXPECT_TRUE(is_valid_utf8("caf\xc3\xa9"));
  EXPECT_FALSE(is_valid_utf8("\xed\xa0\x80"));  // a surrogate
}

}  // namespace
}  // namespace gyroflip::text
