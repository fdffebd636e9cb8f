#include "judge/plan_size.hpp"

#include "common/input.hpp"
#include "common/observables.hpp"
#include "judge/claim_grid.hpp"
#include "judge/claims.hpp"
#include "judge/search.hpp"
#include "judge/step_study.hpp"
#include "truth/plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace pldamp::harness {

namespace {

double claim_grid_cells(const ClaimGrid& grid) {
  const double scales = grid.scales.empty()
                            ? double(grid.v0.size()) * double(grid.m.size()) * double(grid.k.size())
                            : double(grid.scales.size());
  return double(grid.p.size()) * double(grid.damping.size()) * scales;
}

// The solver runs of a claim judged on cells of its own, at what each costs per cell
// (claims.hpp): a bound on a solver over a grid of its own, or ten times denser, solved for it
// alone; a solve or two per cell of a solver's relation (a closed-form evaluation, of about a
// solve's cost, for the truth's), a bisection (about 20 solves) for a recovered α, and for a
// largest stable step a scan up from τ/1000 by 1.5 to 50 τ and 12 bisections (at most 40 steps
// tried, each over 9 sampled onset phases and the refinement to every phase: judge/solve.cpp).
double claim_runs(const Claim& claim) {
  const auto over = [&](auto&& cells) {
    return cells(claim.grid) + (claim.denser ? cells(denser_grid(claim.grid)) : 0);
  };
  const auto solves_over = [&](double solves) { return solves * over(claim_grid_cells); };
  // τ(α)/τ(0) of a solver: two solves.
  const auto solves_of = [](const MeasuredQuantity& of) {
    return of.solver && of.quantity == Quantity::tau_ratio ? 2.0 : 1.0;
  };
  return std::visit(
      [&](const auto& stated) -> double {
        using Kind = std::decay_t<decltype(stated)>;
        if constexpr (std::is_same_v<Kind, BoundClaim>) {
          return stated.config.onset_phases *
                 ((stated.own_grid ? claim_grid_cells(claim.grid) : 0) +
                  (claim.denser ? claim_grid_cells(denser_grid(claim.grid)) : 0));
        } else if constexpr (std::is_same_v<Kind, ConventionClaim>) {
          return 0; // closed forms
        } else if constexpr (std::is_same_v<Kind, RelationClaim>) {
          return solves_over(solves_of(stated.of));
        } else if constexpr (std::is_same_v<Kind, AsymptoticClaim>) {
          return solves_of(stated.of) *
                 over([&](const ClaimGrid& grid) { return double(grid.p.size()) * stated.points; });
        } else if constexpr (std::is_same_v<Kind, RecoveredParameterClaim>) {
          return solves_over(20);
        } else {
          return solves_over(40 * (9 + phase_refinement_runs));
        }
      },
      claim.kind);
}

} // namespace

// The grid's cells, counted before any is built (as a double: a hostile grid overflows long).
double grid_cells(const Scene& scene) {
  const double scales = scene.contacts.empty() ? double(scene.v0.size()) * double(scene.m.size()) *
                                                     double(scene.k.size())
                                               : double(scene_scales(scene).size());
  return double(scene.p.size()) * double(scene.damping.size()) * scales;
}

// The solves of a scene's claims judged on grids of their own (claim_runs) and of its searches and
// time-step study, estimated: one process makes them in a shard set (merge), the ranks share them
// under MPI.
double claim_and_search_runs(const Scene& scene) {
  double runs = step_study_runs_estimate(scene); // the time-step study's searches
  for (const Claim& claim : scene.claims) {
    runs += claim_runs(claim);
  }
  for (const Search& search : scene.searches) {
    runs += search_runs_estimate(search);
  }
  return runs;
}

// The solver runs a scene asks for: cells × (each configuration's onset phases) × repeats, claim
// configurations included; and claim_and_search_runs.
double planned_runs(const Scene& scene) {
  // Per cell: each configuration at each onset phase (claim configurations as make_plan adds
  // them), pldamp's own solvers once per timing repeat (an external program answers once:
  // run.cpp).
  double per_cell = 0;
  for (const SolverConfig& config : plan_configs(scene)) {
    per_cell += config.onset_phases * (config.external() ? 1 : scene.repeats);
  }
  return grid_cells(scene) * per_cell + claim_and_search_runs(scene);
}

// The plan's size, refused beyond the limit before anything is built. The grid's runs are shared
// among `shares` processes (shards or ranks), and among MPI ranks (`judging_shared`) the claims'
// and searches' solves too (run/workers.hpp), which a shard set's merge makes in one process:
// the limit counts one process's.
void check_plan_size(const Scene& scene, const std::string& scene_path, double shares,
                     bool judging_shared) {
  const double runs = planned_runs(scene);
  const double judging = claim_and_search_runs(scene);
  const double grid_runs = runs - judging;
  // The largest share of the grid: a shard of N holds ceil(cells / N) cells.
  const double cells = grid_cells(scene);
  const double grid_share = cells > 0 ? grid_runs * std::ceil(cells / shares) / cells : 0;
  const double per_process = grid_share + (judging_shared ? judging / shares : judging);
  if (per_process > double(scene.limits.max_runs)) {
    throw InputError(fmt::format(
        "the plan has {:.0f} solver runs{}, above the limit of {}: shrink the grid, raise the "
        "limit with --max-runs or [limits] max_runs{} (got {})",
        runs,
        shares <= 1 ? ""
        : judging_shared
            ? fmt::format(", {:.0f} in the largest share of {:.0f} ranks", per_process, shares)
            : fmt::format(", {:.0f} in one of {:.0f} processes (a share of the grid's {:.0f} and "
                          "the {:.0f} of the claims, searches and time-step study, estimated, "
                          "which one process makes)",
                          per_process, shares, grid_runs, judging),
        scene.limits.max_runs, shares > 1 ? "" : ", or share it with --shard or mpirun",
        scene_path));
  }
}

// The plan's size, printed first.
void print_plan_size(const Scene& scene, std::ostream& out) {
  const double runs = planned_runs(scene);
  const double cells = grid_cells(scene);
  // report.json's size, a record a line: about 500 bytes and 125 more per observable wanted
  // (measured: 875 bytes a record for 3 observables, 1 165 for the nightly's 7). The records live
  // in a file that is unlinked as it is made, not in memory (run/record_store.hpp). It said
  // "about 602 MB of records", an in-memory size no run had since.
  const double configs = double(plan_configs(scene).size()); // as the summary counts them
  const double megabytes =
      cells * configs * (500 + 125 * double(observables_of(scene.want).size())) / 1e6;
  const auto grid_claims =
      std::count_if(scene.claims.begin(), scene.claims.end(), [](const Claim& c) {
        const BoundClaim* bound = std::get_if<BoundClaim>(&c.kind);
        const ConventionClaim* convention = std::get_if<ConventionClaim>(&c.kind);
        return bound ? bound->own_grid || c.denser : !convention || convention->own_grid;
      });
  // With repeats, an upper bound: a run of repeat_below or more is not repeated. Not with a
  // search or a time-step study, whose solves are estimated (a fixed-step search's onset phases
  // grow where its answer does not settle).
  const bool searches = !scene.searches.empty() || step_study_runs_estimate(scene) > 0;
  out << fmt::format("{}: {:.0f} cells x {:.0f} solver configurations{}: {}{:.0f} solver runs "
                     "(onset phases, repeats{} included); report.json about {:.3g} MB\n",
                     one_line(scene.name), cells, configs,
                     grid_claims > 0 ? fmt::format(", {} claims on grids of their own", grid_claims)
                                     : "",
                     searches            ? "about "
                     : scene.repeats > 1 ? "at most "
                                         : "",
                     runs,
                     grid_claims > 0 || searches
                         ? " and the solves of the claims on grids of their own, the searches and "
                           "the time-step study, estimated"
                         : "",
                     megabytes)
      << std::flush;
}

} // namespace pldamp::harness
