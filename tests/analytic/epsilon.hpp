// Errors against a reference in units of the type's ε, per group, the way Boost.Math's own tests
// report theirs (its test/handle_test_result.hpp): every comparison is recorded in its group
// (precision, region of the reference, observable); each group's largest error, with the row that
// gave it, and its RMS are printed, passing or not, and checked against a table of the errors
// expected. Boost falls back to 1 ε for a group without an entry; here a group without one fails,
// naming what to measure: a new precision or region must be measured and entered, never judged by
// a bound meant for another.
#pragma once

#include "support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::testing {

// The largest and the RMS error expected over a region's comparisons of one observable, in ε of
// the precision (its precision_name()); observable "*" covers the region's observables that have
// no row of their own.
struct ExpectedEpsilon {
  std::string_view precision, region, observable;
  double max, rms;
};

template <SupportedReal Real>
class EpsilonErrors {
public:
  // Records relative_error(got, want) in ε of Real; `row` says which comparison it was. With a
  // condition number κ (|d ln want/d ln input|), in ε·max(1, κ): the error the rounding of the
  // input alone would make is then 1.
  template <class Want>
  void record(std::string_view region, std::string_view observable, const Real& got,
              const Want& want, const std::string& row, double condition = 1) {
    record_error(region, observable,
                 relative_error(got, want) / eps<Real>() / std::max(1.0, std::abs(condition)), row);
  }

  // Records an error already measured in ε of Real (e.g. one that counts a subnormal's ulps).
  void record_error(std::string_view region, std::string_view observable, double error,
                    const std::string& row) {
    Group& group = group_of(region, observable);
    ++group.count;
    if (!(error <= group.max)) { // NaN too: it is the worst
      group.max = std::isnan(error) ? INFINITY : error;
      group.worst = row;
    }
    group.sum_squares += std::isnan(error) ? INFINITY : error * error;
  }

  // Prints every group, "quad z<0.99 e: max 3.1 ε (line 57: ...), rms 0.82 ε over 64", then
  // checks each against the table's row for it (its observable's, else the region's "*"). Fails
  // when the table has no row for the precision, or none for a group, and for a row of the
  // precision that no group used (a region renamed or gone).
  void check(std::span<const ExpectedEpsilon> table) const {
    const std::string precision(precision_name<Real>());
    for (const Group& group : groups_) {
      std::printf("%s %s %s: max %.3g ε (%s), rms %.3g ε over %zu\n", precision.c_str(),
                  group.region.c_str(), group.observable.c_str(), group.max, group.worst.c_str(),
                  group.rms(), group.count);
    }
    std::fflush(stdout);
    if (std::none_of(table.begin(), table.end(),
                     [&](const ExpectedEpsilon& row) { return row.precision == precision; })) {
      ADD_FAILURE() << "the table has no row for " << precision
                    << ": measure its errors (printed above) and add them";
      return;
    }
    std::vector<bool> used(table.size(), false);
    for (const Group& group : groups_) {
      const std::string name = precision + " " + group.region + " " + group.observable;
      const std::ptrdiff_t found = row_for(table, group);
      if (found < 0) {
        ADD_FAILURE() << "no row for " << name << " (nor for " << group.region
                      << " *): measure it (printed above) and add a row to the table";
        continue;
      }
      const ExpectedEpsilon& expected = table[static_cast<std::size_t>(found)];
      used[static_cast<std::size_t>(found)] = true;
      EXPECT_LE(group.max, expected.max) << name << ", worst at " << group.worst;
      EXPECT_LE(group.rms(), expected.rms) << name;
    }
    for (std::size_t i = 0; i < table.size(); ++i) {
      if (table[i].precision == precision && !used[i]) {
        ADD_FAILURE() << "the row for " << precision << " " << table[i].region << " "
                      << table[i].observable << " matches no comparison";
      }
    }
  }

private:
  struct Group {
    std::string region, observable;
    double max = 0, sum_squares = 0;
    std::size_t count = 0;
    std::string worst = "none";

    double rms() const { return std::sqrt(sum_squares / static_cast<double>(count)); }
  };
  std::vector<Group> groups_; // in the order first recorded

  Group& group_of(std::string_view region, std::string_view observable) {
    for (Group& group : groups_) {
      if (group.region == region && group.observable == observable) {
        return group;
      }
    }
    return groups_.emplace_back(
        Group{.region = std::string(region), .observable = std::string(observable)});
  }

  // The index of the table's row for the group, −1 for none.
  static std::ptrdiff_t row_for(std::span<const ExpectedEpsilon> table, const Group& group) {
    std::ptrdiff_t any = -1;
    for (std::size_t i = 0; i < table.size(); ++i) {
      const ExpectedEpsilon& row = table[i];
      if (row.precision != precision_name<Real>() || row.region != group.region) {
        continue;
      }
      if (row.observable == group.observable) {
        return static_cast<std::ptrdiff_t>(i);
      }
      if (row.observable == "*") {
        any = static_cast<std::ptrdiff_t>(i);
      }
    }
    return any;
  }
};

} // namespace pldamp::testing
