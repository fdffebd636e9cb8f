// Scenes with the protocol's test double (adapters/fake_adapter.py) as an external solver, run
// in-process: for the external-solver and claim tests (harness_test defines
// PLDAMP_TEST_ADAPTERS).
#pragma once

#include "fixtures.hpp"

#include <string>
#include <utility>
#include <vector>

namespace pldamp::harness::testing {

// The fake adapter in `mode` as the [[solver]] labelled "fake", with its arguments after the
// mode ("STATE_FILE").
inline std::string fake_solver(const std::string& mode, const std::string& state = "") {
  return "[[solver]]\ncommand = [\"python3\", \"" PLDAMP_TEST_ADAPTERS "/fake_adapter.py\", \"" +
         mode + "\"" + (state.empty() ? "" : ", \"" + state + "\"") + "]\nlabel = \"fake\"\n";
}

// A scene of p = 1 and 1.5 × e = 0.3, 0.8 × v0 = 1, 2 (or `grid`) wanting e, δ_max, t_peak and τ
// (or `want`), with the fake adapter in `mode`, then `extra`.
inline std::string
scene_with(const std::string& mode, const std::string& extra = "", const std::string& state = "",
           const std::string& grid = "p = [1, 1.5]\ne = [0.3, 0.8]\nv0 = [1, 2]\n",
           const std::string& want = "\"e\", \"delta_max\", \"t_peak\", "
                                     "\"tau\"") {
  return "name = \"external\"\nwant = [" + want + "]\n[grid]\n" + grid +
         "[limits]\nmax_seconds = 0.5\n" + fake_solver(mode, state) + extra;
}

struct Ran {
  Plan plan;
  std::vector<Record> records;
};

inline Ran run_scene_text(const std::string& text) {
  const Plan plan = make_plan(parse_scene(text, (scratch() / "external.toml").string()));
  RunTotals totals;
  std::vector<Record> records = run_plan(plan, 2, totals);
  return {plan, std::move(records)};
}

} // namespace pldamp::harness::testing
