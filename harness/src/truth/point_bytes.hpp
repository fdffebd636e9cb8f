// A plan's points as bytes, bit for bit (every Exact truth, every double): under MPI each rank
// computes a share of the points and the ranks exchange them (run/distribution.cpp), so that a
// truth, a float128 reference solve among them, is computed once in a run, not once a rank.
#pragma once

#include "common/bytes.hpp"
#include "truth/plan.hpp"

#include <boost/math/special_functions/sign.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// A binary floating-point value of any precision, exactly: its class and sign (a NaN's too, not
// its payload), then (finite and non-zero) its exponent and its significand as an integer in 64-bit
// pieces, all formed and read back by exact operations (frexp, ldexp, and sums of integers the type
// represents exactly).
template <class Real>
void put_real(ByteWriter& out, const Real& x) {
  using std::frexp, std::ldexp, std::floor, std::isnan, std::isinf;
  enum : std::uint8_t { finite, zero, infinite, not_a_number };
  const std::uint8_t kind = isnan(x) ? not_a_number : isinf(x) ? infinite : x == 0 ? zero : finite;
  out.put<std::uint8_t>(kind);
  out.put<std::uint8_t>(boost::math::signbit(x) ? 1 : 0);
  if (kind != finite) {
    return;
  }
  constexpr int digits = std::numeric_limits<Real>::digits;
  int exponent = 0;
  Real significand = ldexp(frexp(x < 0 ? Real(-x) : x, &exponent), digits); // an integer
  out.put<std::int32_t>(exponent);
  const Real piece_size = ldexp(Real(1), 64);
  for (int bits = 0; bits < digits; bits += 64) {
    const Real high = floor(significand / piece_size);
    out.put<std::uint64_t>(static_cast<std::uint64_t>(Real(significand - high * piece_size)));
    significand = high;
  }
}

template <class Real>
Real get_real(ByteReader& in) {
  using std::ldexp;
  const auto kind = in.get<std::uint8_t>();
  const auto negative = in.get<std::uint8_t>();
  if (kind > 3 || negative > 1) {
    in.corrupt();
  }
  const Real sign = negative == 1 ? Real(-1) : Real(1);
  if (kind == 1) {
    return sign * Real(0);
  }
  if (kind == 2) {
    return sign * std::numeric_limits<Real>::infinity();
  }
  if (kind == 3) { // its sign kept: a report prints a NaN's ("-nan"), the payload not
    return negative == 1 ? -std::numeric_limits<Real>::quiet_NaN()
                         : std::numeric_limits<Real>::quiet_NaN();
  }
  constexpr int digits = std::numeric_limits<Real>::digits;
  const auto exponent = in.get<std::int32_t>();
  Real significand = 0;
  for (int bits = 0; bits < digits; bits += 64) {
    significand += ldexp(Real(in.get<std::uint64_t>()), bits);
  }
  return sign * ldexp(significand, exponent - digits);
}

// One point's bytes, and the point read back from them.
void put_point(ByteWriter& out, const Point& point);
Point get_point(ByteReader& in);

// Appends `points` to `bytes`; read_points reads them back (InputError naming `source` when the
// bytes end early or hold what no writer writes).
void append_points(std::string& bytes, std::span<const Point> points);
std::vector<Point> read_points(std::string_view bytes, const std::string& source);

} // namespace pldamp::harness
