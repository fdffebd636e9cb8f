// A measured trajectory judged (`pldamp check`): its observables against the closed forms
// (MATH.md §10.1), and the file against the parameters it is checked under (§10.2): a forgotten
// --m or --k, or another v0, would otherwise be reported as errors of −100 % in every
// observable, the code blamed for the arguments.
#include "judge/trajectory.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace pldamp::harness {
namespace {

// The reading estimates of §10.1 are estimates, not bounds (they cover the closed-form
// trajectory's errors at 40 samples per contact and more, and can miss by a factor of a few
// below): each is counted twice here.
constexpr double margin = 2;

// A measured quantity against the law the arguments state for it: the factor between them (≥ 1;
// infinite across a sign) and the factor the file allows, 1 + the relative allowance.
struct Against {
  double factor, allowed;
  bool contradicts() const { return !(factor <= allowed); }
};

Against against(double measured, double stated, double relative_allowance) {
  const double ratio = measured / stated;
  return {ratio > 0 ? std::max(ratio, 1 / ratio) : std::numeric_limits<double>::infinity(),
          1 + relative_allowance};
}

std::string number(double x) {
  return fmt::format("{:.4g}", x);
}

// "a factor 7e+09 where its sampling and digits allow 1 + 0.0034"
std::string by_how_much(const Against& a, const char* allowance) {
  return std::isfinite(a.factor) ? fmt::format("a factor {} where its {} allow 1 + {:.2g}",
                                               number(a.factor), allowance, a.allowed - 1)
                                 : std::string("of the opposite sign");
}

} // namespace

std::optional<std::string> contradiction(const TrajectoryObservables& x, const StatedContact& c) {
  if (const Extracted& speed = x.incoming_speed; speed.value) {
    const Against v0 =
        against(*speed.value, c.v0, margin * speed.sampling / std::abs(*speed.value));
    if (v0.contradicts()) {
      return fmt::format("the file's incoming speed is {} ({}), not --v0 {}: {}; {} (got --v0 {})",
                         to_string_full(*speed.value), x.incoming_from, to_string_full(c.v0),
                         by_how_much(v0, "sampling and digits"),
                         *speed.value > 0 ? "give --v0 " + to_string_full(*speed.value)
                                          : std::string("v must be d(delta)/dt, > 0 while loading"),
                         to_string_full(c.v0));
    }
  }
  if (!x.delta_max.value || !x.peak_acceleration.value) {
    return std::nullopt;
  }
  // At the peak v = 0: the damping force vanishes and F = k δ^p = −m δ''. Each side may be off by
  // twice its reading estimate and by its spread over the rows about the peak (a staggered
  // scheme's force belongs to a state up to two steps away).
  const double delta = *x.delta_max.value;
  const double law = std::pow(delta, c.p);
  const double law_allowance =
      c.p * (margin * x.delta_max.sampling + x.peak_overlap_spread) / delta;
  const double deceleration = -*x.peak_acceleration.value; // δ'' < 0 there
  const double deceleration_allowance =
      (margin * x.peak_acceleration.sampling + x.peak_acceleration_spread) / std::abs(deceleration);
  const char* rows = "sampling, digits and rows about the peak";
  if (const Extracted& force = x.peak_force; force.value) {
    const double force_allowance =
        (margin * force.sampling + x.peak_force_spread) / std::abs(*force.value);
    const Against stiffness = against(*force.value, c.k * law, force_allowance + law_allowance);
    if (stiffness.contradicts()) {
      return fmt::format("the file's force at the peak is {} delta^{}, not k delta^p with k = {} "
                         "({}): give --k, or check --p (got --k {})",
                         number(*force.value / law), number(c.p), to_string_full(c.k),
                         by_how_much(stiffness, rows), to_string_full(c.k));
    }
    const Against mass =
        against(*force.value, c.m * deceleration, force_allowance + deceleration_allowance);
    if (mass.contradicts()) {
      return fmt::format("the file's force at the peak is {} times its deceleration there, not "
                         "m = {} times ({}): give --m (got --m {})",
                         number(*force.value / deceleration), to_string_full(c.m),
                         by_how_much(mass, rows), to_string_full(c.m));
    }
    return std::nullopt;
  }
  const Against ratio =
      against(deceleration, c.k / c.m * law, deceleration_allowance + law_allowance);
  if (ratio.contradicts()) {
    return fmt::format("the file's deceleration at the peak is {} delta^{}, not (k/m) delta^p "
                       "with k/m = {} ({}): give --m and --k, whose ratio it fixes (got --m {} "
                       "--k {})",
                       number(deceleration / law), number(c.p), number(c.k / c.m),
                       by_how_much(ratio, rows), to_string_full(c.m), to_string_full(c.k));
  }
  return std::nullopt;
}

SampledJudgement judge_extracted(const Extracted& measured, const std::optional<Exact>& truth) {
  SampledJudgement j;
  if (!measured.value) {
    j.why_not = measured.missing;
    return j;
  }
  if (!truth) {
    j.why_not = "no closed form";
    return j;
  }
  using std::isfinite;
  if (!isfinite(*truth)) {
    j.why_not = "the truth is infinite (no return in finite time)";
    return j;
  }
  const Exact error = Exact(*measured.value) - *truth;
  const Exact scale = *truth == 0 ? Exact(1) : Exact(abs(*truth));
  j.error = static_cast<double>(error);
  j.relative_error = static_cast<double>(error / scale);
  j.relative_sampling = static_cast<double>(Exact(measured.sampling) / scale);
  j.explained = abs(error) <= Exact(measured.sampling);
  return j;
}

std::string verdict_name(const SampledJudgement& judgement) {
  if (!judgement.explained) {
    return "-";
  }
  return *judgement.explained ? "explained by sampling" : "beyond sampling";
}

} // namespace pldamp::harness
