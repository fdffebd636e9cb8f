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

std::string impossible_answer(const solvers::Result<double>& answer, const SolverConfig& config,
                              const solvers::Problem<double>& problem,
                              const solvers::Options<double>& options) {
  using solvers::Outcome;
  const std::pair<const char*, const std::optional<double>*> values[] = {
      {"e", &answer.e},
      {"delta_max", &answer.delta_max},
      {"t_peak", &answer.t_peak},
      {"tau", &answer.tau},
      {"energy_load", &answer.energy_load},
      {"energy_unload", &answer.energy_unload}};
  const double allowance = answer_allowance(config, problem);
  const double energy_scale = solvers::ContactOde<double>(problem).energy_scale();
  for (const auto& [key, value] : values) {
    if (!*value) {
      continue;
    }
    const double x = **value;
    const bool infinite_tau = value == &answer.tau && x == std::numeric_limits<double>::infinity();
    if (infinite_tau && answer.outcome == Outcome::exited) {
      return "exited with tau = inf";
    }
    if (!std::isfinite(x) && !infinite_tau) {
      return fmt::format("{} = {}: not finite", key, full(x));
    }
    const bool energy = value == &answer.energy_load || value == &answer.energy_unload;
    if (energy && x < -allowance * energy_scale) {
      return fmt::format("energy gained: {} = {} (m v0^2/2 = {})", key, full(x),
                         full(energy_scale));
    }
    if (!energy && x < 0) {
      return fmt::format("{} = {}: negative", key, full(x));
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
  if (answer.e && *answer.e > 1 + allowance) {
    return fmt::format("energy gained: e = {} (allowed up to 1 + {:.3g})", full(*answer.e),
                       allowance);
  }
  const bool balanced = answer.outcome == Outcome::exited && answer.e && answer.energy_load &&
                        answer.energy_unload && !step_of(config, problem);
  if (balanced) {
    // ½ m v0² = ½ m (e v0)² + W (+ the spring's k δ^(p+1)/(p+1) at the force end's cut).
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
