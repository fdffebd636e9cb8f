// The observables the harness compares, in one table: their keys (scene `want` words and claims,
// JSON, CSV, report tables: all in this order), which solver and analytic Want bits produce them,
// where each is found in a solver's Result and in the closed forms (overlap end and force end),
// and their physical dimension, by which the unit-scale truth is scaled to a cell (MATH.md §7).
//
// Adding an observable: its Result field and Want bit (solvers/problem.hpp) and its measurement
// in the solvers, its closed form in analytic/observables.hpp, and one row in observables.cpp.
#pragma once

#include "pldamp/analytic/observables.hpp"
#include "pldamp/solvers/problem.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace pldamp::harness {

// How a value scales with v0, m, k from the unit-scale truth (MATH.md §7).
enum class Dimension { none, length, time, energy, force };

// How a solver's no_exit is judged on a contact that does return, too late or too slowly for the
// solver to tell (just below critical damping e is ~e^-2000 and τ lies beyond the horizon).
enum class LateReturn {
  compared,   // as any value
  absolute,   // the absolute error stands for the relative one (e read as 0)
  unresolved, // not compared (τ = ∞ against a finite τ beyond the horizon)
};

template <SupportedReal Real>
using MeasuredFn = std::optional<Real> (*)(const solvers::Result<Real>&);
template <SupportedReal Real>
using ExactFn = std::optional<Real> (*)(const analytic::Observables<Real>&);

namespace detail {
template <template <class> class Fn, class... Reals>
std::tuple<Fn<Reals>...> per_precision_of(RealList<Reals...>);
} // namespace detail

// One function pointer per supported precision.
template <template <class> class Fn>
using PerPrecision = decltype(detail::per_precision_of<Fn>(Precisions{}));

// Instantiates a captureless generic lambda for every precision.
template <template <class> class Fn, class Lambda>
constexpr PerPrecision<Fn> per_precision(Lambda lambda) {
  PerPrecision<Fn> out{};
  for_each_precision([&]<class Real>() { std::get<Fn<Real>>(out) = lambda; });
  return out;
}

struct Observable {
  std::string_view key;          // JSON, CSV and claims: "e"
  std::string_view capped_key;   // `solve --end force` JSON: "e_cap"
  std::string_view want_word;    // the word that asks for it in `want`: "energy" for both energies
  unsigned solver_want;          // solvers::Want bit
  unsigned analytic_want;        // analytic::Want bits at the overlap end
  unsigned analytic_want_capped; // at the force end; 0: no closed form there
  Dimension dimension;
  LateReturn late_return;
  PerPrecision<MeasuredFn> measured_fn;
  PerPrecision<ExactFn> exact_fn, exact_capped_fn;
  // The closed form's logarithm at the overlap end, where the value itself can leave a type's
  // range (e ~ e^-2221 and τ just below critical damping); none: no such form.
  std::optional<PerPrecision<ExactFn>> exact_log_fn = std::nullopt;

  template <SupportedReal Real>
  std::optional<Real> measured(const solvers::Result<Real>& result) const {
    return std::get<MeasuredFn<Real>>(measured_fn)(result);
  }
  template <SupportedReal Real>
  std::optional<Real> exact(const analytic::Observables<Real>& closed, solvers::End end) const {
    if (end == solvers::End::force) {
      return analytic_want_capped == 0 ? std::nullopt
                                       : std::get<ExactFn<Real>>(exact_capped_fn)(closed);
    }
    return std::get<ExactFn<Real>>(exact_fn)(closed);
  }
  // ln of the closed form at the overlap end, for observables that have that form.
  template <SupportedReal Real>
  std::optional<Real> exact_log(const analytic::Observables<Real>& closed) const {
    return exact_log_fn ? std::get<ExactFn<Real>>(*exact_log_fn)(closed) : std::nullopt;
  }
  unsigned analytic_want_at(solvers::End end) const {
    return end == solvers::End::force ? analytic_want_capped : analytic_want;
  }
  std::string_view key_at(solvers::End end) const {
    return end == solvers::End::force ? capped_key : key;
  }
};

// Every observable, in report order.
std::span<const Observable> observable_table();

// The observables a solver Want bit set selects, in table order.
std::vector<const Observable*> observables_of(unsigned solver_want);

// The analytic Want bits behind a solver Want bit set at a contact end.
unsigned analytic_want_of(unsigned solver_want, solvers::End end);

// The observable of that key, or nullptr.
const Observable* find_observable(std::string_view key);

// "e|delta_max|t_peak|tau|energy": the words `want` takes (with_all: and "all").
std::string want_words(bool with_all);

// The solver Want bits of a list of want words (0 for an empty list); throws
// std::invalid_argument "unknown observable in <where>, expected <want_words> (got WORD)".
unsigned parse_want(const std::vector<std::string>& words, const std::string& where, bool with_all);

} // namespace pldamp::harness
