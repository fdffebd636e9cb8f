// Validation at the API boundary (convention 4 of DESIGN.md): every public entry point checks its
// arguments and throws std::invalid_argument whose message names the parameter and prints the
// offending value at full precision, e.g. "p must be >= 1 (got 0.5)". The CLI prints that message
// after "error: " and exits 2.
#pragma once

#include "pldamp/core/real_types.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

namespace pldamp {

template <SupportedReal Real>
std::string to_string_full(const Real& value) {
  using std::isnan;
  if (isnan(value)) {
    return "nan";
  }
  std::ostringstream out;
  out << std::setprecision(round_trip_digits<Real>()) << value;
  return out.str();
}

// Throws "<what> (got <value>)" unless `ok`.
template <SupportedReal Real>
void require(bool ok, const std::string& what, const Real& value) {
  if (!ok) {
    throw std::invalid_argument(what + " (got " + to_string_full(value) + ")");
  }
}

template <SupportedReal Real>
void require_finite(const std::string& name, const Real& value) {
  using std::isfinite;
  require(static_cast<bool>(isfinite(value)), name + " must be finite", value);
}

template <SupportedReal Real>
void require_positive(const std::string& name, const Real& value) {
  require_finite(name, value);
  require(value > 0, name + " must be > 0", value);
}

} // namespace pldamp
