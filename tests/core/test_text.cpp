// The tokenizer of short texts (issue 13 item 17): fields with their columns, whole-field numbers.
#include <cmath>

#include <gtest/gtest.h>

#include "gyroflip/core/digits.hpp"
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

// The direction controls (Trojan Source, CVE-2021-42574) and the line separators are shown, not
// kept: they would reorder or split a message or a page around them. Other scripts and the
// joiners they need are kept.
TEST(Text, DirectionControlsAreMadeVisible) {
  EXPECT_EQ(visible_controls("a\xe2\x80\xae"
                             "b\xe2\x80\xac"
                             "c"),
            "a\\u202eb\\u202cc");                                               // RLO, PDF
  EXPECT_EQ(visible_controls("\xe2\x81\xa6x\xe2\x81\xa9"), "\\u2066x\\u2069");  // LRI, PDI
  EXPECT_EQ(visible_controls("\xe2\x80\x8f\xd8\x9c\xef\xbb\xbf"),
            "\\u200f\\u061c\\ufeff");  // RLM, ALM, BOM
  EXPECT_EQ(visible_controls("1\xe2\x80\xa8"
                             "2\xe2\x80\xa9"),
            "1\\u20282\\u2029");
  for (const char* kept : {"\xd7\x90\xd7\x91", "caf\xc3\xa9", "\xe2\x80\x8d", "\xe2\x80\x94",
                           "\xe2\x80\xa7", "\xe2\x80\xaf", "\xe2\x80", "\xd8"})
    EXPECT_EQ(visible_controls(kept), kept);  // Hebrew, e-acute, ZWJ, em dash, neighbours, cut
  EXPECT_EQ(printable("seed: 1\xe2\x80\xae"
                      "evil"),
            "seed: 1\\u202eevil");
}

}  // namespace
}  // namespace gyroflip::text

// Third review of issue 31: "-0.00000 ± 0.00098" (a negative zero), and errors that dropped their
// significant trailing zeros ("0.001" where calibrate prints 0.0010). One formatter: the digits
// of the error, else the fallback's significant digits, trailing zeros kept.
TEST(Digits, ValuesTakeTheirErrorsDigitsWithoutANegativeZero) {
  EXPECT_EQ(gyroflip::digits_of_error(-1e-6, 0.00098).first, "0.00000");
  EXPECT_EQ(gyroflip::digits_of_error(-6e-6, 0.00098).first, "-0.00001");
  EXPECT_EQ(gyroflip::digits_of_error(0.0032, 0.001).second, "0.0010");
  EXPECT_EQ(gyroflip::to_digits_of(0.00326975, 0.000812, 6), "0.00327");
  EXPECT_EQ(gyroflip::to_digits_of(0.5032524, 0.0, 6), "0.503252");
  EXPECT_EQ(gyroflip::to_digits_of(0.25, std::nan(""), 4), "0.2500");
  EXPECT_EQ(gyroflip::to_digits_of(std::nan(""), 0.1, 4), "–");
  EXPECT_EQ(gyroflip::significant(0.0006, 2), "0.00060");
  EXPECT_EQ(gyroflip::significant(0.4, 2), "0.40");
}

// Issue 31: a report page's column held "8.6e-06" beside "0.000010", and a slope of 0 degrees of
// freedom read "4.28589e-05": the pages print every number in fixed notation.
TEST(Digits, FixedSignificantKeepsOneNotationAtAnySize) {
  EXPECT_EQ(gyroflip::fixed_significant(8.6e-6, 2), "0.0000086");
  EXPECT_EQ(gyroflip::fixed_significant(1.0e-5, 2), "0.000010");
  EXPECT_EQ(gyroflip::fixed_significant(-4.28589e-5, 3), "-0.0000429");
  EXPECT_EQ(gyroflip::fixed_significant(1234.0, 3), "1230");
  EXPECT_EQ(gyroflip::fixed_significant(9.96, 2), "10");
  EXPECT_EQ(gyroflip::fixed_significant(0.0, 2), "0.0");
  EXPECT_EQ(gyroflip::fixed_significant(-1e-20, 2), "0.000000000000000");  // 15 decimals, no -0
  EXPECT_EQ(gyroflip::to_digits_of(4.42171e-6, 0.0, 3), "0.00000442");
}

// Fifth review of issue 31, F12: a 9e99 sample gave dN "-4500000000000000520805...032" (97 fixed
// digits, most invented). Past a million: one exponent, the error's two digits.
TEST(Digits, HugeValuesTakeScientificNotationWithTheErrorsDigits) {
  const auto [v, u] = gyroflip::digits_of_error(-4.5e96, 5.2e96);
  EXPECT_EQ(v, "-4.5e+96");
  EXPECT_EQ(u, "5.2e+96");
  EXPECT_EQ(gyroflip::digits_of_error(1234567.0, 0.35).first, "1.23456700e+06");
  EXPECT_EQ(gyroflip::digits_of_error(5e2, 3.1e7).first, "0.0e+07");
  EXPECT_EQ(gyroflip::digits_of_error(999999.0, 0.5).first, "999999.00");  // below: fixed
}
