#include "run/answers.hpp"

#include "pldamp/core/validate.hpp"
#include "pldamp/solvers/contact_ode.hpp"

#include <boost/math/constants/constants.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pldamp::harness {
namespace {

// A program given neither rtol nor a step: its own default, taken as this rtol.
constexpr double default_program_rtol = 1e-6;

std::string full(double x) {
  return to_string_full(x);
}

} // namespace

std::optional<double> step_of(const SolverConfig& config, const solvers::Problem<double>& problem) {
  if (config.dt) {
    return config.dt;
  }
  if (config.steps_per_contact) {
    return boost::math::constants::pi<double>() *
           solvers::ContactOde<double>(problem).time_scale() / double(*config.steps_per_contact);
  }
  return std::nullopt;
}

double answer_allowance(const SolverConfig& config, const solvers::Problem<double>& problem) {
  const solvers::ContactOde<double> ode(problem);
  if (const std::optional<double> step = step_of(config, problem)) {
    const double omega_squared =
        ode.k() * ode.p() * std::pow(ode.delta_scale(), ode.p() - 1) / ode.m();
    return std::min(omega_squared * *step * *step / 8, 0.25);
  }
  double tolerance = config.rtol.value_or(default_program_rtol);
  if (config.atol) {
    tolerance = std::max({tolerance, *config.atol / ode.delta_scale(), *config.atol / ode.v0(),
                          *config.atol / ode.energy_scale()});
  }
  return std::min(10000 * tolerance, std::sqrt(tolerance)) +
         1000 * std::numeric_limits<double>::epsilon();
}

// What no damping allows. The dashpot only takes energy (its power c δ^β δ'² ≥ 0 for α, β ≥ 0), so
// ½ m v² + k δ^(p+1)/(p+1) never exceeds ½ m v0². From that alone:
// - 0 < δ_max ≤ δ_u, k δ_u^(p+1)/(p+1) = ½ m v0² (δ_u is ContactOde's delta_scale): at the peak
//   v = 0 and the spring holds at most all the energy; δ_max > 0 since δ'(0) = v0 > 0.
// - t_peak > 0 and δ_max ≤ v0 t_peak: while compressing (δ > 0, v ≥ 0) the spring and the dashpot
//   both push back, so v' ≤ 0, v ≤ v0 and δ(t) ≤ v0 t.
// - τ > t_peak: the contact ends unloading (δ = 0 is reached at v < 0; at the force end
//   k δ^p + c δ^β δ' = 0 needs δ' < 0), after the peak.
// - At the overlap end, τ ≥ 2 δ_max/v0: the compression takes t_peak ≥ δ_max/v0, and the return
//   over δ_max at a speed |v| ≤ v0 (the energy again) at least δ_max/v0 more. At the force end
//   the cut comes while δ > 0: no such bound.
// Each bound gets the allowance e gets (answer_allowance), so that a coarse but honest scheme
// passes. δ_max's also gets a fixed step's onset: a program stepping Δt may first see the contact
// up to v0 Δt deep, still at v0 (the onset phase), holding k (v0 Δt)^(p+1)/(p+1) beyond ½ m v0²;
// with e's allowance on the speed, δ_max^(p+1) ≤ (1 + a)² (δ_u^(p+1) + (v0 Δt)^(p+1)), at most
// ((1 + a)(δ_u + v0 Δt))^(p+1). δ_u (1 + a) alone refused pldamp's own DEM schemes undamped at
// p = 1 from 4 to 50 steps per contact (leapfrog's amplitude is δ_u/√(1 − (ωΔt)²/4), beyond
// δ_u (1 + (ωΔt)²/8): 1.087 δ_u at 4 steps, a = 0.077) and verlet-predicted at e = 0.9, 6 steps,
// onset phase 0.9 (δ_max = 1.107 δ_u, a = 0.034).

std::string impossible_value(std::string_view key, double value, const SolverConfig& config,
                             const solvers::Problem<double>& problem) {
  const double allowance = answer_allowance(config, problem);
  const solvers::ContactOde<double> ode(problem);
  const bool duration = key == "tau", energy = key == "energy_load" || key == "energy_unload";
  if (!std::isfinite(value) && !(duration && value == std::numeric_limits<double>::infinity())) {
    return fmt::format("{} = {}: not finite", key, full(value));
  }
  if (energy && value < -allowance * ode.energy_scale()) {
    return fmt::format("energy gained: {} = {} (m v0^2/2 = {})", key, full(value),
                       full(ode.energy_scale()));
  }
  if (!energy && value < 0) {
    return fmt::format("{} = {}: negative", key, full(value));
  }
  if (key == "e" && value > 1 + allowance) {
    return fmt::format("energy gained: e = {} (allowed up to 1 + {:.3g})", full(value), allowance);
  }
  if ((key == "delta_max" || key == "t_peak" || duration) && !(value > 0)) {
    return fmt::format("{} = {}: not positive (the contact begins at v0 > 0)", key, full(value));
  }
  if (key == "delta_max") {
    const double delta_u = ode.delta_scale();
    const double most =
        (1 + allowance) * (delta_u + ode.v0() * step_of(config, problem).value_or(0));
    if (value > most) {
      return fmt::format("energy gained: delta_max = {} above the undamped peak delta_u = {} "
                         "(allowed up to {})",
                         full(value), full(delta_u), full(most));
    }
  }
  return {};
}

std::string impossible_answer(const solvers::Result<double>& answer, const SolverConfig& config,
                              const solvers::Problem<double>& problem,
                              const solvers::Options<double>& options) {
  using solvers::Outcome;
  const double infinity = std::numeric_limits<double>::infinity();
  if (answer.outcome == Outcome::exited && answer.tau == infinity) {
    return "exited with tau = inf";
  }
  const std::pair<std::string_view, const std::optional<double>*> values[] = {
      {"e", &answer.e},
      {"delta_max", &answer.delta_max},
      {"t_peak", &answer.t_peak},
      {"tau", &answer.tau},
      {"energy_load", &answer.energy_load},
      {"energy_unload", &answer.energy_unload},
      {"t_normal_force_max", &answer.t_normal_force_max}};
  // normal_force_max is held to being finite only: pldamp's own arkode-erk8 at rtol 1e-2 reports
  // a negative one (p = 1.5, α = 1.5), which a sign check would call impossible (left for its own
  // issue).
  if (answer.normal_force_max && !std::isfinite(*answer.normal_force_max)) {
    return "normal_force_max = " + full(*answer.normal_force_max) + ": not finite";
  }
  for (const auto& [key, value] : values) {
    if (*value) {
      if (std::string why = impossible_value(key, **value, config, problem); !why.empty()) {
        return why;
      }
    }
  }
  if (answer.outcome == Outcome::peak &&
      (options.want & (solvers::want_e | solvers::want_tau | solvers::want_energy)) != 0) {
    return "outcome peak, but the problem wants what comes after the peak (e, tau or "
           "energy_unload): peak answers a problem that wants delta_max and t_peak only";
  }
  if (answer.outcome == Outcome::no_exit && answer.e && *answer.e != 0) {
    return "no_exit with e = " + full(*answer.e) + " (no return is e = 0)";
  }
  // The bounds between values (above impossible_value): the overlap grows no faster than v0, and
  // at the overlap end it also shrinks no faster.
  const double allowance = answer_allowance(config, problem);
  const double v0 = problem.v0;
  const std::optional<double>&delta_max = answer.delta_max, &t_peak = answer.t_peak;
  const bool returned = answer.tau && *answer.tau != infinity; // no_exit's τ = ∞ bounds nothing
  const double tau = answer.tau.value_or(infinity);
  if (delta_max && t_peak && *delta_max > v0 * *t_peak * (1 + allowance)) {
    return fmt::format("delta_max = {} above v0 t_peak = {}: compressed faster than v0 (allowed "
                       "up to 1 + {:.3g} times)",
                       full(*delta_max), full(v0 * *t_peak), allowance);
  }
  if (t_peak && returned && !(tau > *t_peak)) {
    return fmt::format("tau = {} not after t_peak = {}: a contact ends after its peak", full(tau),
                       full(*t_peak));
  }
  // The total force peaks at or before the overlap: at the overlap's peak (δ' = 0) its rate is
  // c δ^β δ'' ≤ 0, and the contact has ended by τ. (A force peak after τ was kept, t = 1e6 beside
  // τ = 3.2.)
  // A fixed step samples both peaks on its steps: one step later is its grain.
  if (const std::optional<double>& t_force = answer.t_normal_force_max; t_force) {
    const double step = step_of(config, problem).value_or(0);
    if (t_peak && *t_force > *t_peak * (1 + allowance) + step) {
      return fmt::format("t_normal_force_max = {} after t_peak = {}: the force peaks at or "
                         "before the overlap (allowed up to 1 + {:.3g} times and a step)",
                         full(*t_force), full(*t_peak), allowance);
    }
    if (returned && !(*t_force <= tau + step)) {
      return fmt::format("t_normal_force_max = {} not before tau = {}", full(*t_force), full(tau));
    }
  }
  if (options.end == solvers::End::overlap && delta_max && returned &&
      tau < 2 * *delta_max / v0 * (1 - allowance)) {
    return fmt::format("tau = {} below 2 delta_max/v0 = {}: in and out faster than v0 (allowed "
                       "down to 1 - {:.3g} times)",
                       full(tau), full(2 * *delta_max / v0), allowance);
  }
  const bool balanced = answer.outcome == Outcome::exited && answer.e && answer.energy_load &&
                        answer.energy_unload && !step_of(config, problem);
  if (balanced) {
    // ½ m v0² = ½ m (e v0)² + W (+ the spring's k δ^(p+1)/(p+1) at the force end's cut).
    const double energy_scale = solvers::ContactOde<double>(problem).energy_scale();
    const double imbalance =
        *answer.e * *answer.e + (*answer.energy_load + *answer.energy_unload) / energy_scale - 1;
    const bool force_end = options.end == solvers::End::force;
    if (force_end ? imbalance > allowance : !(std::abs(imbalance) <= allowance)) {
      return fmt::format("energy balance off by {} of m v0^2/2 (allowed {:.3g})", full(imbalance),
                         allowance);
    }
  }
  return {};
}

std::vector<std::string> settings_not_honoured(const SolverConfig& config,
                                               const std::vector<std::string>& honours) {
  const auto honoured = [&](const std::string& key) {
    return std::find(honours.begin(), honours.end(), key) != honours.end();
  };
  std::vector<std::string> sent;
  if (config.steps_per_contact && !honoured("dt")) {
    sent.emplace_back("steps_per_contact");
  }
  if (config.dt) {
    sent.emplace_back("dt");
  }
  if (config.onset_phases > 1) {
    sent.emplace_back("onset_phase");
  }
  if (config.rtol) {
    sent.emplace_back("rtol");
  }
  if (config.atol) {
    sent.emplace_back("atol");
  }
  if (!config.options.empty()) {
    const nlohmann::json options = nlohmann::json::parse(config.options);
    for (const auto& [key, value] : options.items()) {
      sent.push_back("options." + key);
    }
  }
  std::vector<std::string> ignored;
  std::copy_if(sent.begin(), sent.end(), std::back_inserter(ignored),
               [&](const std::string& key) { return !honoured(key); });
  return ignored;
}

} // namespace pldamp::harness
