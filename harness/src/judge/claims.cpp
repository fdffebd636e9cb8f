#include "judge/claims.hpp"

#include "judge/claim_parts.hpp"

#include "judge/solve.hpp"
#include "run/workers.hpp"
#include "truth/plan.hpp"
#include "truth/point_bytes.hpp"

#include "pldamp/analytic/instances.hpp" // instantiated once: this unit compiled in 25 s, now 9
#include "pldamp/analytic/observables.hpp"
#include "pldamp/analytic/seed.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace pldamp::harness {

namespace claim_parts {

Contact<Exact> truth_contact(const ClaimCell& cell) {
  const Exact p(cell.p);
  const Contact<Exact> unit =
      seed_contact(p, cell.damping.kind, Exact(cell.damping.value), analytic::ContactEnd::overlap);
  return Contact<Exact>::from_damping(p, unit.damping(), Exact(cell.v0), Exact(cell.m),
                                      Exact(cell.k));
}

QuantityWants wants_of(Quantity quantity) {
  using R = solvers::Result<double>;
  switch (quantity) {
  case Quantity::e:
    return {analytic::want_e, solvers::want_e, &R::e};
  case Quantity::delta_max:
    return {analytic::want_delta_max, solvers::want_delta_max, &R::delta_max};
  case Quantity::t_peak:
    return {analytic::want_t_peak, solvers::want_t_peak, &R::t_peak};
  case Quantity::tau:
  case Quantity::tau_ratio:
    return {analytic::want_tau, solvers::want_tau, &R::tau};
  case Quantity::energy_load:
    return {analytic::want_energy, solvers::want_energy, &R::energy_load};
  case Quantity::energy_unload:
    break;
  }
  return {analytic::want_energy, solvers::want_energy, &R::energy_unload};
}

Exact truth_value(Quantity quantity, const Contact<Exact>& c) {
  const analytic::Observables<Exact> o = analytic::observables(c, wants_of(quantity).analytic);
  switch (quantity) {
  case Quantity::e:
    return *o.e;
  case Quantity::delta_max:
    return *o.delta_max;
  case Quantity::t_peak:
    return *o.t_peak;
  case Quantity::tau:
    return *o.tau;
  case Quantity::tau_ratio:
    return *o.tau_ratio;
  case Quantity::energy_load:
    return *o.energy_load;
  case Quantity::energy_unload:
    break;
  }
  return *o.energy_unload;
}

Exact quantity_value(const Scene& scene, const MeasuredQuantity& of, const Contact<Exact>& c) {
  if (!of.solver) {
    return truth_value(of.quantity, c);
  }
  const QuantityWants wants = wants_of(of.quantity);
  const char* name = name_of(quantities, of.quantity).data();
  Inputs in{static_cast<double>(c.p()), static_cast<double>(c.alpha()), static_cast<double>(c.v0()),
            static_cast<double>(c.m()), static_cast<double>(c.k())};
  const double value = solved_value(*of.solver, in, wants.solver, wants.value, name, scene.limits);
  if (of.quantity != Quantity::tau_ratio) {
    return Exact(value);
  }
  in.alpha = 0;
  return Exact(value) /
         Exact(solved_value(*of.solver, in, wants.solver, wants.value, name, scene.limits));
}

void conclude_at_most(Judgement& j, const Largest& largest, double bound) {
  j.measured = largest.value();
  j.holds = j.measured <= bound;
  if (j.measured > 0) {
    j.margin = bound / j.measured;
  }
  j.worst = largest.where();
}

} // namespace claim_parts

namespace {

using namespace claim_parts;
using claim_parts::judge; // beside this unit's judges, not hidden by them
namespace seed = analytic::seed;

// A cell's measurement, or why it has none.
struct CellValue {
  double value = 0;
  std::optional<std::string> failure;
};

void put_piece(ByteWriter& out, const CellValue& c) {
  out.put(c.value);
  Encoding<std::optional<std::string>>::put(out, c.failure);
}
void get_piece(ByteReader& in, CellValue& c) {
  c.value = in.get<double>();
  c.failure = Encoding<std::optional<std::string>>::get(in);
}

Judgement judge(const Scene& scene, const RecoveredParameterClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>&, const Workers& workers) {
  Judgement j;
  j.grid = grid_text(grid);
  Largest worst;
  const std::vector<ClaimCell> cells = cells_of(grid);
  j.cells = static_cast<long>(cells.size());
  // The bisections on the threads, then judged in the grid's order (common/parallel.hpp).
  const std::vector<CellValue> off =
      map_shared<CellValue>(cells.size(), workers, [&](std::size_t i) {
        const ClaimCell& cell = cells[i];
        CellValue d;
        try {
          const double found = alpha_by_bisection(
              claim.config, {cell.p, 0, cell.v0, cell.m, cell.k}, cell.damping.value, scene.limits);
          const Exact formula = seed::alpha_of_e(Exact(cell.p), Exact(cell.damping.value));
          d.value = static_cast<double>(abs(Exact(found) / formula - 1));
        } catch (const std::exception& e) {
          d.failure = e.what();
        }
        return d;
      });
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string where = cell_text(grid, cells[i]);
    if (off[i].failure) {
      add_without_value(j, where, *off[i].failure, true);
    } else {
      worst.see(off[i].value, where);
    }
  }
  conclude_at_most(j, worst, claim.bound);
  conclude_without_value(j, false);
  return j;
}

// A cell of a stability claim: the largest stable Δt over the formula's, and e's relative error
// at the formula's Δt (none: unstable there); or why it has no answer.
struct StableAtBound {
  double ratio = 0;
  std::optional<double> e_off;
  std::optional<std::string> failure;
};

void put_piece(ByteWriter& out, const StableAtBound& s) {
  out.put(s.ratio);
  out.put(s.e_off);
  Encoding<std::optional<std::string>>::put(out, s.failure);
}
void get_piece(ByteReader& in, StableAtBound& s) {
  s.ratio = in.get<double>();
  s.e_off = in.optional();
  s.failure = Encoding<std::optional<std::string>>::get(in);
}

StableAtBound stable_at_bound(const Scene& scene, const StabilityClaim& claim,
                              const ClaimCell& cell) {
  const Contact<Exact> c = truth_contact(cell);
  if (c.mu() <= 0) {
    return {0, std::nullopt, "alpha_eff >= 1: the contact does not return"};
  }
  const double tau = static_cast<double>(analytic::contact_duration(c));
  const double bound = claim.fraction * static_cast<double>(seed::evaluate(claim.formula, c));
  const double e = static_cast<double>(analytic::restitution(c));
  const Inputs in{cell.p, static_cast<double>(c.alpha()), cell.v0, cell.m, cell.k};
  const StableStep stable = largest_stable_dt(claim.config, in, scene.limits, tau);
  std::string limit = stable.limit;
  const solvers::Result<double> at_bound =
      solve_unchecked(claim.config, in, solvers::want_e, scene.limits, {}, bound);
  if (at_bound.outcome == solvers::Outcome::step_limit ||
      at_bound.outcome == solvers::Outcome::time_limit) {
    limit = fmt::format("{} at dt = {:.4g}", solvers::outcome_name(at_bound.outcome), bound);
  }
  if (!limit.empty()) {
    return {0, std::nullopt, limit};
  }
  StableAtBound out{stable.dt / bound, std::nullopt, std::nullopt};
  if (at_bound.outcome == solvers::Outcome::exited && at_bound.e && *at_bound.e <= 1) {
    out.e_off = std::abs(*at_bound.e / e - 1);
  }
  return out;
}

Judgement judge(const Scene& scene, const StabilityClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>&, const Workers& workers) {
  Judgement j;
  j.grid = grid_text(grid);
  Smallest smallest;
  Largest largest, worst_e;
  long unstable_at_bound = 0;
  const std::vector<ClaimCell> cells = cells_of(grid);
  j.cells = static_cast<long>(cells.size());
  // The scans on the threads, then judged in the grid's order (common/parallel.hpp).
  const std::vector<StableAtBound> found =
      map_shared<StableAtBound>(cells.size(), workers, [&](std::size_t i) {
        return stable_at_bound(scene, claim, cells[i]);
      });
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::string where = cell_text(grid, cells[i]);
    if (found[i].failure) {
      add_without_value(j, where, *found[i].failure, true);
      continue;
    }
    smallest.see(found[i].ratio, where);
    largest.see(found[i].ratio, where);
    if (found[i].e_off) {
      worst_e.see(*found[i].e_off, where);
    } else {
      ++unstable_at_bound;
    }
  }
  j.measured = smallest.value();
  j.holds = j.measured >= 1;
  j.margin = j.measured;
  j.worst = smallest.where();
  if (smallest) {
    const std::string bound_name =
        (claim.fraction != 1 ? fmt::format("{:g} ", claim.fraction) : std::string()) +
        std::string(seed::info_of(claim.formula).name);
    j.note = fmt::format(
        "largest stable dt / {} from {:.3g} ({}) to {:.3g} ({}); at dt = {}: ", bound_name,
        smallest.value(), smallest.where(), largest.value(), largest.where(), bound_name);
    if (unstable_at_bound > 0) {
      j.note += fmt::format("unstable (no return, or energy gained) in {} of {} cells",
                            unstable_at_bound, cells.size());
    }
    if (worst_e) {
      j.note += fmt::format("{}e off by up to {:.3g} ({})", unstable_at_bound > 0 ? "; " : "",
                            worst_e.value(), worst_e.where());
    }
  }
  conclude_without_value(j, false);
  return j;
}

// The verdict's grid-independent fields of each kind: what it measures, of what, against what.
struct Described {
  std::string observable, config;
  double bound;
  bool worse_when_lower;
  std::string meaning;
};

std::string error_meaning(const ErrorBound& error) {
  return fmt::format("the {} {} error over the grid; margin = bound / measured",
                     error.quantile == 1 ? std::string("largest")
                                         : fmt::format("{:g} quantile of the", error.quantile),
                     error.relative ? "relative" : "absolute");
}

std::string config_text(const MeasuredQuantity& of) {
  return of.solver ? of.solver->label() : "truth (closed forms, float128)";
}

Described describe(const BoundClaim& claim) {
  return {claim.observable, claim.config.label(), claim.error.bound, false,
          error_meaning(claim.error)};
}

Described describe(const ConventionClaim& claim) {
  return {"e", claim.convention + (claim.limit_damping ? " limit_damping" : ""), claim.error.bound,
          false, error_meaning(claim.error)};
}

Described describe(const RelationClaim& claim) {
  const bool equal_within = claim.relation == Relation::equal_within;
  return {fmt::format("{} {} {}", name_of(quantities, claim.of.quantity),
                      name_of(relations, claim.relation), seed::info_of(claim.formula).name),
          config_text(claim.of), claim.tolerance, !equal_within,
          !equal_within
              ? "the smallest gap (quantity - formula) / |formula| (formula - quantity for "
                "an upper bound), negative where the bound is crossed; margin = the "
                "smallest gap among cells not equal within the tolerance"
          : claim.absolute ? "the largest |quantity - formula|; margin = tolerance / measured"
                           : "the largest |quantity / formula - 1|; margin = tolerance / measured"};
}

Described describe(const AsymptoticClaim& claim) {
  return {fmt::format("{} vs {}", name_of(quantities, claim.of.quantity),
                      seed::info_of(claim.formula).name),
          config_text(claim.of), claim.order, true,
          "the smallest order over p at which the two sides agree as alpha_eff -> 0; margin = "
          "measured - the order the claim implies"};
}

Described describe(const RecoveredParameterClaim& claim) {
  return {"alpha by bisection vs seed alpha(e)", claim.config.label(), claim.bound, false,
          "the largest |alpha found / seed alpha(e) - 1|; margin = bound / measured"};
}

Described describe(const StabilityClaim& claim) {
  return {"largest stable dt vs " +
              (claim.fraction != 1 ? fmt::format("{:g} ", claim.fraction) : std::string()) +
              std::string(seed::info_of(claim.formula).name),
          claim.config.label(), 1, true,
          "the smallest ratio largest stable dt / the formula's dt; margin = that ratio (>= 1: "
          "the bound is conservative)"};
}

// A claim of the kinds judged on a grid of their own, over `grid`.
Judgement judge_kind(const Scene& scene, const Claim& claim, const ClaimGrid& grid,
                     std::vector<MeasuredOrder>& orders, const Workers& workers) {
  return std::visit(
      [&](const auto& stated) -> Judgement {
        if constexpr (std::decay_t<decltype(stated)>::claim_kind == ClaimKind::bound) {
          throw std::logic_error(
              "a bound claim is judged from the plan's records (judge/budget.cpp)");
        } else {
          return judge(scene, stated, grid, orders, workers);
        }
      },
      claim.kind);
}

} // namespace

Verdict verdict_of(const Claim& claim) {
  const Described described =
      std::visit([](const auto& stated) { return describe(stated); }, claim.kind);
  const BoundClaim* bound = std::get_if<BoundClaim>(&claim.kind);
  Verdict v;
  v.name = claim.name;
  v.kind = std::string(name_of(claim_kinds, claim.claim_kind()));
  v.where = claim.where;
  v.quote = claim.quote;
  v.figure = claim.figure.value_or("");
  v.expect_holds = claim.expect_holds;
  v.allow_missing = bound != nullptr && bound->allow_missing;
  v.bound = described.bound;
  v.meaning = described.meaning;
  v.worse_when_lower = described.worse_when_lower;
  v.observable = described.observable;
  v.config = described.config;
  return v;
}

Verdict judge_on_grid(const Scene& scene, const Claim& claim, const Workers& workers) {
  Verdict verdict = verdict_of(claim);
  static_cast<Judgement&>(verdict) = judge_kind(scene, claim, claim.grid, verdict.orders, workers);
  if (claim.denser) {
    std::vector<MeasuredOrder> orders;
    verdict.denser = judge_kind(scene, claim, denser_grid(claim.grid), orders, workers);
  }
  return verdict;
}

} // namespace pldamp::harness
