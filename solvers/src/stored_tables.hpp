// The (p, β) tables of two_power_series.hpp that a process would otherwise build first thing:
// computed once, by the build itself in float128, and kept in the source (stored_tables.cpp,
// written by generate_stored_tables.cpp; the test `stored_tables_regenerate` writes it again and
// requires the same bytes, and TwoPowerSeries.StoredTablesAreTheBuiltOnesBitForBit requires the
// same coefficients). Building a float128 table to degree 40 takes ~25 ms, 25 times a collision:
// the viscoelastic contact's first truth in a process paid it (MATH.md §12.3).
//
// Each float128 is kept as its two 64-bit words in std::bit_cast order (the little-endian
// layout of x86-64 and AArch64, where the generator ran); a big-endian target builds instead.
#pragma once

#include <cstdint>
#include <span>

namespace pldamp::solvers::detail {

struct StoredTable {
  std::uint64_t p[2], beta[2];         // the float128 words of p and β
  int degree;                          // D: Y's triangle i + j ≤ D, W̃'s i + j ≤ D + 1
  std::span<const std::uint64_t> y, w; // two words per coefficient, Triangle order
};

extern const std::span<const StoredTable> stored_tables;

} // namespace pldamp::solvers::detail
