// A double-double number: hi + lo with |lo| ≤ ulp(hi)/2, 106 bits from two doubles, the arithmetic
// of Dekker (1971) as Hida, Li & Bailey's QD library arranges it (the "accurate" addition). The
// taylor solver sums the middle orders of its float128 and 50-digit series in it (taylor.cpp):
// 106 bits are more than those orders need and cost several times less than software float128.
// Boost 1.74 has no such type (cpp_double_fp_backend came in Boost 1.86).
//
// Only what the recurrences use: +, −, ×, ÷, conversion from integers, doubles and wider types.
// Error-free transformations need each operation rounded as written: no -ffast-math, and the
// products use std::fma where the target has it (no Dekker split, which a contraction could
// spoil), Dekker's split elsewhere.
#pragma once

#include <cmath>
#include <cstddef>

namespace pldamp::solvers::detail {

class DoubleDouble {
public:
  constexpr DoubleDouble() = default;
  constexpr DoubleDouble(double value) : hi_(value) {} // NOLINT: a double is exact in it
  explicit constexpr DoubleDouble(int value) : hi_(value) {}
  explicit constexpr DoubleDouble(std::size_t value) : hi_(static_cast<double>(value)) {}

  // The nearest double-double to a wider value (float128, cpp_bin_float_50).
  template <class Wide>
  static DoubleDouble from(const Wide& x) {
    const double hi = static_cast<double>(x);
    return quick_sum(hi, static_cast<double>(x - Wide(hi)));
  }
  template <class Wide>
  Wide to() const {
    return Wide(hi_) + Wide(lo_);
  }
  double hi() const { return hi_; }

  friend DoubleDouble operator+(const DoubleDouble& a, const DoubleDouble& b) {
    double s_err = 0, t_err = 0;
    const double s = two_sum(a.hi_, b.hi_, s_err);
    const double t = two_sum(a.lo_, b.lo_, t_err);
    DoubleDouble r = quick_sum(s, s_err + t);
    return quick_sum(r.hi_, r.lo_ + t_err);
  }
  friend DoubleDouble operator-(const DoubleDouble& a) { return {-a.hi_, -a.lo_}; }
  friend DoubleDouble operator-(const DoubleDouble& a, const DoubleDouble& b) { return a + -b; }
  friend DoubleDouble operator*(const DoubleDouble& a, const DoubleDouble& b) {
    double err = 0;
    const double p = two_product(a.hi_, b.hi_, err);
    return quick_sum(p, err + (a.hi_ * b.lo_ + a.lo_ * b.hi_));
  }
  friend DoubleDouble operator/(const DoubleDouble& a, const DoubleDouble& b) {
    // Three quotient digits, each from the remainder of the last (QD's accurate division).
    const double q1 = a.hi_ / b.hi_;
    DoubleDouble r = a - b * DoubleDouble(q1);
    const double q2 = r.hi_ / b.hi_;
    r = r - b * DoubleDouble(q2);
    const double q3 = r.hi_ / b.hi_;
    return quick_sum(q1, q2) + DoubleDouble(q3);
  }
  DoubleDouble& operator+=(const DoubleDouble& b) { return *this = *this + b; }

private:
  constexpr DoubleDouble(double hi, double lo) : hi_(hi), lo_(lo) {}

  // s + err = a + b exactly (Knuth).
  static double two_sum(double a, double b, double& err) {
    const double s = a + b;
    const double b_virtual = s - a;
    err = (a - (s - b_virtual)) + (b - b_virtual);
    return s;
  }
  // a + b when |a| ≥ |b| (Dekker), normalised.
  static DoubleDouble quick_sum(double a, double b) {
    const double s = a + b;
    return {s, b - (s - a)};
  }
  // p + err = a b exactly.
  static double two_product(double a, double b, double& err) {
    const double p = a * b;
#ifdef __FMA__
    err = std::fma(a, b, -p);
#else
    constexpr double splitter = 134217729.0; // 2^27 + 1
    const double ta = splitter * a, tb = splitter * b;
    const double a_hi = ta - (ta - a), a_lo = a - a_hi;
    const double b_hi = tb - (tb - b), b_lo = b - b_hi;
    err = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo;
#endif
    return p;
  }

  double hi_ = 0, lo_ = 0;
};

} // namespace pldamp::solvers::detail
