#include "common/observables.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace pldamp::harness {
namespace {

constexpr auto measured(auto get) {
  return per_precision<MeasuredFn>(get);
}
constexpr auto exact(auto get) {
  return per_precision<ExactFn>(get);
}
// For an observable without a closed form at the force end (analytic_want_capped = 0).
constexpr auto no_closed_form = exact([](const auto& x) { return decltype(x.e){}; });

// Under the force end e and τ are the capped restitution and the cut time (MATH.md §4); the
// analytic layer splits the energy of the full contact only, so energy_unload has no closed form
// there.
constexpr std::array every_observable{
    Observable{.key = "e",
               .capped_key = "e_cap",
               .want_word = "e",
               .solver_want = solvers::want_e,
               .analytic_want = analytic::want_e,
               .analytic_want_capped = analytic::want_capped,
               .dimension = Dimension::none,
               .late_return = LateReturn::absolute,
               .measured_fn = measured([](const auto& r) { return r.e; }),
               .exact_fn = exact([](const auto& x) { return x.e; }),
               .exact_capped_fn = exact([](const auto& x) { return x.e_cap; }),
               .exact_log_fn = exact([](const auto& x) { return x.log_e; })},
    Observable{.key = "delta_max",
               .capped_key = "delta_max",
               .want_word = "delta_max",
               .solver_want = solvers::want_delta_max,
               .analytic_want = analytic::want_delta_max,
               .analytic_want_capped = analytic::want_delta_max,
               .dimension = Dimension::length,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.delta_max; }),
               .exact_fn = exact([](const auto& x) { return x.delta_max; }),
               .exact_capped_fn = exact([](const auto& x) { return x.delta_max; })},
    Observable{.key = "t_peak",
               .capped_key = "t_peak",
               .want_word = "t_peak",
               .solver_want = solvers::want_t_peak,
               .analytic_want = analytic::want_t_peak,
               .analytic_want_capped = analytic::want_t_peak,
               .dimension = Dimension::time,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.t_peak; }),
               .exact_fn = exact([](const auto& x) { return x.t_peak; }),
               .exact_capped_fn = exact([](const auto& x) { return x.t_peak; })},
    Observable{.key = "tau",
               .capped_key = "t_cut",
               .want_word = "tau",
               .solver_want = solvers::want_tau,
               .analytic_want = analytic::want_tau,
               .analytic_want_capped = analytic::want_capped,
               .dimension = Dimension::time,
               .late_return = LateReturn::unresolved,
               .measured_fn = measured([](const auto& r) { return r.tau; }),
               .exact_fn = exact([](const auto& x) { return x.tau; }),
               .exact_capped_fn = exact([](const auto& x) { return x.t_cut; }),
               .exact_log_fn = exact([](const auto& x) { return x.log_tau; })},
    Observable{.key = "energy_load",
               .capped_key = "energy_load",
               .want_word = "energy",
               .solver_want = solvers::want_energy,
               .analytic_want = analytic::want_energy,
               .analytic_want_capped = analytic::want_energy,
               .dimension = Dimension::energy,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.energy_load; }),
               .exact_fn = exact([](const auto& x) { return x.energy_load; }),
               .exact_capped_fn = exact([](const auto& x) { return x.energy_load; })},
    Observable{.key = "energy_unload",
               .capped_key = "energy_unload",
               .want_word = "energy",
               .solver_want = solvers::want_energy,
               .analytic_want = analytic::want_energy,
               .analytic_want_capped = 0,
               .dimension = Dimension::energy,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.energy_unload; }),
               .exact_fn = exact([](const auto& x) { return x.energy_unload; }),
               .exact_capped_fn = no_closed_form},
    // The total normal force's peak comes before the overlap's, so the force end shares it.
    Observable{.key = "normal_force_max",
               .capped_key = "normal_force_max",
               .want_word = "normal_force",
               .solver_want = solvers::want_normal_force,
               .analytic_want = analytic::want_normal_force,
               .analytic_want_capped = analytic::want_normal_force,
               .dimension = Dimension::force,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.normal_force_max; }),
               .exact_fn = exact([](const auto& x) { return x.normal_force_max; }),
               .exact_capped_fn = exact([](const auto& x) { return x.normal_force_max; })},
    Observable{.key = "t_normal_force_max",
               .capped_key = "t_normal_force_max",
               .want_word = "normal_force",
               .solver_want = solvers::want_normal_force,
               .analytic_want = analytic::want_normal_force,
               .analytic_want_capped = analytic::want_normal_force,
               .dimension = Dimension::time,
               .late_return = LateReturn::compared,
               .measured_fn = measured([](const auto& r) { return r.t_normal_force_max; }),
               .exact_fn = exact([](const auto& x) { return x.t_normal_force_max; }),
               .exact_capped_fn = exact([](const auto& x) { return x.t_normal_force_max; })},
};

} // namespace

std::span<const Observable> observable_table() {
  return every_observable;
}

std::vector<const Observable*> observables_of(unsigned solver_want) {
  std::vector<const Observable*> out;
  for (const Observable& observable : every_observable) {
    if (solver_want & observable.solver_want) {
      out.push_back(&observable);
    }
  }
  return out;
}

unsigned analytic_want_of(unsigned solver_want, solvers::End end) {
  unsigned want = 0;
  for (const Observable* observable : observables_of(solver_want)) {
    want |= observable->analytic_want_at(end);
  }
  return want;
}

const Observable* find_observable(std::string_view key) {
  const auto found =
      std::find_if(every_observable.begin(), every_observable.end(),
                   [&](const Observable& observable) { return observable.key == key; });
  return found == every_observable.end() ? nullptr : &*found;
}

std::string want_words(bool with_all) {
  std::string words;
  for (const Observable& observable : every_observable) {
    const std::string word(observable.want_word);
    if (words.empty() || ("|" + words + "|").find("|" + word + "|") == std::string::npos) {
      words += words.empty() ? "" : "|";
      words += word;
    }
  }
  return with_all ? words + "|all" : words;
}

unsigned parse_want(const std::vector<std::string>& words, const std::string& where,
                    bool with_all) {
  unsigned want = 0;
  for (const std::string& word : words) {
    unsigned bits = with_all && word == "all" ? unsigned(solvers::want_all) : 0;
    for (const Observable& observable : every_observable) {
      bits |= observable.want_word == word ? observable.solver_want : 0;
    }
    if (bits == 0) {
      throw std::invalid_argument("unknown observable in " + where + ", expected " +
                                  want_words(with_all) + " (got " + word + ")");
    }
    want |= bits;
  }
  return want;
}

} // namespace pldamp::harness
