// Metrological: a value and its std as a metrologist writes them. The expected texts are worked
// out by hand from the rule (std to two significant digits, the value to the same decimal place).
#include "html_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hrgbench::report::internal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void ExpectText(double value, double std_dev, const char* value_text, const char* std_text) {
  const ValueWithStd t = Metrological(value, std_dev);
  EXPECT_EQ(t.value, value_text) << value << " ± " << std_dev;
  EXPECT_EQ(t.std, std_text) << value << " ± " << std_dev;
}

TEST(Metrological, StdToTwoDigitsValueToTheSamePlace) {
  ExpectText(999.99934, 0.004712, "999.9993", "0.0047");
  ExpectText(-0.0010023555, 0.019013571, "-0.001", "0.019");
  ExpectText(12.3456, 1.26, "12.3", "1.3");
  ExpectText(5000.0, 52.3, "5000", "52");
}

TEST(Metrological, RoundingCarriesIntoTheNextDecade) {
  // 0.0996 to two digits is 0.10, not 0.100: the value keeps two decimals.
  ExpectText(1.23456, 0.0996, "1.23", "0.10");
  ExpectText(3.14159, 9.97, "3", "10");
}

TEST(Metrological, LargeStdInENotationWithTheLargerExponent) {
  // A std of 18931 to two digits is 1.9e4; fixed notation ("19000") would claim five digits.
  ExpectText(997.65, 18931.1, "0.1e4", "1.9e4");
  ExpectText(15671049.4, 297369402.0, "0.2e8", "3.0e8");
  ExpectText(-5.2152, 9834.9, "0.0e3", "9.8e3");  // rounds to zero: no sign
}

TEST(Metrological, SmallValueAndStdInENotation) {
  ExpectText(1.2594711e-5, 3.01e-6, "1.26e-5", "0.30e-5");
}

TEST(Metrological, ZeroAtThePrecisionShownHasNoSign) {
  ExpectText(-2.5618e-8, 0.0049813, "0.0000", "0.0050");
}

TEST(Metrological, WithoutAStdTheValueKeepsSixDigits) {
  EXPECT_EQ(Metrological(997.6499894659912, kNaN).value, "997.65");
  EXPECT_EQ(Metrological(997.6499894659912, 0.0).value, "997.65");
  EXPECT_EQ(Metrological(kNaN, 0.25).std, "0.25");
  EXPECT_EQ(Metrological(kNaN, 0.25).value, "\u2014");
}

TEST(TwoSignificant, StdAlone) {
  EXPECT_EQ(TwoSignificant(0.0049813), "0.0050");
  EXPECT_EQ(TwoSignificant(181.565), "1.8e2");
  EXPECT_EQ(TwoSignificant(kNaN), "\u2014");
}

}  // namespace
}  // namespace hrgbench::report::internal
