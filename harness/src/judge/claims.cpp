#include "judge/claims.hpp"

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
namespace {

using analytic::Contact;
namespace seed = analytic::seed;

Contact<Exact> truth_contact(const ClaimCell& cell) {
  const Exact p(cell.p);
  const Contact<Exact> unit =
      seed_contact(p, cell.damping.kind, Exact(cell.damping.value), analytic::ContactEnd::overlap);
  return Contact<Exact>::from_damping(p, unit.damping(), Exact(cell.v0), Exact(cell.m),
                                      Exact(cell.k));
}

struct QuantityWants {
  unsigned analytic, solver;
  std::optional<double> solvers::Result<double>::*value;
};

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

// The claim's quantity at a contact: the closed form in Exact, or the solver's in double (its
// τ(α)/τ(0) from two solves). Throws std::runtime_error when the solver gives none.
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

// The largest (Most) or smallest (Least) value seen over a grid, and the cell it came from. NaN
// counts as the most extreme.
enum class Keep { most, least };
template <Keep keep>
class Extreme {
public:
  void see(double value, const std::string& where) {
    const bool beyond = keep == Keep::most ? !(value <= value_) : !(value >= value_);
    if (!seen_ || beyond) {
      seen_ = true;
      value_ = value;
      where_ = where;
    }
  }
  explicit operator bool() const { return seen_; }
  double value() const { return seen_ ? value_ : 0; }
  const std::string& where() const { return where_; }

private:
  bool seen_ = false;
  double value_ = 0;
  std::string where_;
};
using Largest = Extreme<Keep::most>;
using Smallest = Extreme<Keep::least>;

// At most a bound: measured = the largest, margin = bound / measured.
void conclude_at_most(Judgement& j, const Largest& largest, double bound) {
  j.measured = largest.value();
  j.holds = j.measured <= bound;
  if (j.measured > 0) {
    j.margin = bound / j.measured;
  }
  j.worst = largest.where();
}

// The cells where a relation's two sides are equal within its tolerance, described by p: "p = 1
// (every cell); p = 1.5, 2 at alpha_eff = 0".
class Ties {
public:
  void add(const ClaimCell& cell) { by_p_[cell.p].push_back(damping_text(cell.damping)); }
  long count() const {
    long n = 0;
    for (const auto& [p, dampings] : by_p_) {
      n += static_cast<long>(dampings.size());
    }
    return n;
  }
  std::string text(std::size_t cells_per_p) const {
    std::vector<std::pair<std::string, std::string>> groups; // (ps, where)
    for (const auto& [p, dampings] : by_p_) {
      std::string where;
      if (dampings.size() < cells_per_p) {
        std::vector<std::string> unique = dampings;
        unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
        where = " at " + fmt::format("{}", fmt::join(unique, ", "));
      } else {
        where = " (every cell)";
      }
      if (!groups.empty() && groups.back().second == where) {
        groups.back().first += ", " + verdict_number(p);
      } else {
        groups.emplace_back("p = " + verdict_number(p), where);
      }
    }
    std::string out;
    for (const auto& [ps, where] : groups) {
      out += (out.empty() ? "" : "; ") + ps + where;
    }
    return out;
  }

private:
  std::map<double, std::vector<std::string>> by_p_;
};

// A cell's two sides (quantity, formula), or why it has none (what computing them threw).
struct Sides {
  Exact a = 0, f = 0;
  std::optional<std::string> failure;
};

// A piece of a map shared among MPI ranks (run/workers.hpp), exact.
void put_piece(ByteWriter& out, const Sides& s) {
  put_real(out, s.a);
  put_real(out, s.f);
  Encoding<std::optional<std::string>>::put(out, s.failure);
}
void get_piece(ByteReader& in, Sides& s) {
  s.a = get_real<Exact>(in);
  s.f = get_real<Exact>(in);
  s.failure = Encoding<std::optional<std::string>>::get(in);
}

Judgement judge(const Scene& scene, const RelationClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>&, const Workers& workers) {
  Judgement j;
  j.grid = grid_text(grid);
  const std::vector<ClaimCell> cells = cells_of(grid);
  j.cells = static_cast<long>(cells.size());
  const double tolerance = claim.tolerance;
  const bool equal_within = claim.relation == Relation::equal_within;
  Ties ties;
  // equal_within: the largest difference; bounds: the smallest gap of all, and of the cells
  // that are not ties.
  Largest largest;
  Smallest smallest, smallest_apart;
  // equal_within, relative: the range of formula / quantity, which says how a formula is wrong.
  Smallest lowest_ratio;
  Largest highest_ratio;
  // The sides on the threads, then judged in the grid's order (common/parallel.hpp).
  const std::vector<Sides> sides = map_shared<Sides>(cells.size(), workers, [&](std::size_t i) {
    Sides s;
    try {
      const Contact<Exact> c = truth_contact(cells[i]);
      s.a = quantity_value(scene, claim.of, c);
      s.f = seed::evaluate(claim.formula, c);
    } catch (const std::exception& e) {
      s.failure = e.what();
    }
    return s;
  });
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const ClaimCell& cell = cells[i];
    const std::string where = cell_text(grid, cell);
    if (sides[i].failure) {
      add_without_value(j, where, *sides[i].failure, true);
      continue;
    }
    const Exact& a = sides[i].a;
    const Exact& f = sides[i].f;
    if (!isfinite(a) || !isfinite(f) || (f == 0 && !claim.absolute)) {
      add_without_value(j, where,
                        fmt::format("{} = {:.6g}, the formula {:.6g}",
                                    name_of(quantities, claim.of.quantity), static_cast<double>(a),
                                    static_cast<double>(f)),
                        true);
      continue;
    }
    if (equal_within) {
      if (!claim.absolute && a != 0) {
        const double ratio = static_cast<double>(f / a);
        lowest_ratio.see(ratio, where);
        highest_ratio.see(ratio, where);
      }
      const double d = static_cast<double>(claim.absolute ? abs(a - f) : abs(a / f - 1));
      largest.see(d, where);
      continue;
    }
    const Exact difference = claim.relation == Relation::lower_bound ? a - f : f - a;
    const double gap = static_cast<double>(claim.absolute ? difference : difference / abs(f));
    smallest.see(gap, where);
    if (std::abs(gap) <= tolerance) {
      ties.add(cell);
    } else {
      smallest_apart.see(gap, where);
    }
  }
  if (equal_within) {
    conclude_at_most(j, largest, tolerance);
    if (lowest_ratio && !j.holds) {
      j.note = fmt::format("formula / {} from {:.4g} ({}) to {:.4g} ({})",
                           name_of(quantities, claim.of.quantity), lowest_ratio.value(),
                           lowest_ratio.where(), highest_ratio.value(), highest_ratio.where());
    }
  } else {
    j.measured = smallest.value();
    j.holds = j.measured >= -tolerance;
    if (smallest_apart) {
      j.margin = smallest_apart.value();
    }
    j.worst = !j.holds || !smallest_apart ? smallest.where() : smallest_apart.where();
    if (ties.count() > 0) {
      const std::size_t per_p = grid.damping.size() * grid_scales(grid).size();
      j.note = fmt::format("equal within {:g} at {} of {} cells: {}", tolerance, ties.count(),
                           cells.size(), ties.text(per_p));
    }
  }
  conclude_without_value(j, false);
  return j;
}

// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = double(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// One point of an asymptotic claim: |a − f|, the side's accuracy and |f|, or what computing them
// threw.
struct Gap {
  double difference = 0, accuracy = 0, f = 0;
  std::optional<std::string> failure;
};

void put_piece(ByteWriter& out, const Gap& g) {
  out.put(g.difference);
  out.put(g.accuracy);
  out.put(g.f);
  Encoding<std::optional<std::string>>::put(out, g.failure);
}
void get_piece(ByteReader& in, Gap& g) {
  g.difference = in.get<double>();
  g.accuracy = in.get<double>();
  g.f = in.get<double>();
  g.failure = Encoding<std::optional<std::string>>::get(in);
}

Judgement judge(const Scene& scene, const AsymptoticClaim& claim, const ClaimGrid& grid,
                std::vector<MeasuredOrder>& orders, const Workers& workers) {
  Judgement j;
  // Not a structured binding: Clang 14 (the fuzz build) lets no lambda capture one (z_at).
  const double from = claim.range[0], to = claim.range[1];
  j.grid = fmt::format("p in {} x {} alpha_eff log-spaced over [{:g}, {:g}]: {} cells",
                       list_text(grid.p), claim.points, from, to, grid.p.size() * claim.points);
  j.cells = static_cast<long>(grid.p.size()); // a p fails whole: its cells are one
  // Below this relative difference the two sides are equal to the comparison's accuracy: the
  // truth's; for a solver, ten times its own error against the truth at that cell, measured (its
  // tolerance says nothing of a fixed-step scheme's error, nor exactly of an adaptive one's).
  const double equal = 1e-25;
  orders.clear();
  std::vector<std::string> notes;
  const CellScale scale = grid_scales(grid).front();
  const auto points = static_cast<std::size_t>(claim.points);
  const auto z_at = [&](std::size_t i) {
    return from * std::pow(to / from, double(i) / (claim.points - 1));
  };
  // Every (p, α_eff) on the threads, then each p judged in order (common/parallel.hpp); a p whose
  // point fails is judged no further, as before its later points were computed.
  const std::vector<Gap> gaps =
      map_shared<Gap>(grid.p.size() * points, workers, [&](std::size_t index) {
        Gap gap;
        try {
          const ClaimCell cell{grid.p[index / points],
                               {Damping::Kind::alpha_eff, z_at(index % points)},
                               scale.v0,
                               scale.m,
                               scale.k};
          const Contact<Exact> c = truth_contact(cell);
          const Exact a = quantity_value(scene, claim.of, c);
          const Exact f = seed::evaluate(claim.formula, c);
          gap.difference = static_cast<double>(abs(a - f));
          gap.accuracy = claim.of.solver
                             ? 10 * static_cast<double>(abs(a - truth_value(claim.of.quantity, c)))
                             : 0.0;
          gap.f = static_cast<double>(abs(f));
        } catch (const std::exception& e) {
          gap.failure = e.what();
        }
        return gap;
      });
  for (std::size_t pi = 0; pi < grid.p.size(); ++pi) {
    const double p = grid.p[pi];
    std::vector<double> log_z, log_difference;
    double smallest_z = 0, its_difference = 0;
    try {
      for (std::size_t i = 0; i < points; ++i) {
        const Gap& gap = gaps[pi * points + i];
        const double z = z_at(i);
        if (gap.failure) {
          throw std::runtime_error(*gap.failure);
        }
        const double difference = gap.difference, accuracy = gap.accuracy;
        if (!std::isfinite(difference) || !std::isfinite(accuracy)) {
          throw std::runtime_error("a side is not finite at alpha_eff = " + verdict_number(z));
        }
        if (difference <= std::max(equal * gap.f, accuracy)) {
          continue;
        }
        if (log_z.empty()) {
          smallest_z = z;
          its_difference = difference;
        }
        log_z.push_back(std::log(z));
        log_difference.push_back(std::log(difference));
      }
    } catch (const std::exception& e) {
      add_without_value(j, "p = " + verdict_number(p), e.what(), true);
      continue;
    }
    MeasuredOrder measured{p, std::nullopt, 0};
    if (log_z.size() >= 2) {
      measured.order = slope(log_z, log_difference);
      const double leading = std::max(1.0, std::round(*measured.order));
      measured.coefficient = its_difference / std::pow(smallest_z, leading);
      notes.push_back(fmt::format("p = {}: order {:.3f}, |difference| ~ {:.4g} alpha_eff^{:g}",
                                  verdict_number(p), *measured.order, measured.coefficient,
                                  leading));
    } else {
      if (claim.of.solver) {
        // Equal to the formula within the solver's own error at all but one point: the solver
        // cannot show the order, which is not the same as the exact agreement of the truth.
        add_without_value(j, "p = " + verdict_number(p),
                          "the solver's own error hides the difference from the formula at " +
                              std::to_string(claim.points - log_z.size()) + " of " +
                              std::to_string(claim.points) + " points",
                          false);
        continue;
      }
      notes.push_back(fmt::format("p = {}: equal within {:g}", verdict_number(p), equal));
    }
    orders.push_back(measured);
  }
  j.measured = std::numeric_limits<double>::infinity();
  for (const MeasuredOrder& o : orders) {
    if (o.order && *o.order < j.measured) {
      j.measured = *o.order;
      j.worst = "p = " + verdict_number(o.p);
    }
  }
  j.holds = j.measured >= claim.order - 0.05;
  if (std::isfinite(j.measured)) {
    j.margin = j.measured - claim.order;
  }
  j.note = fmt::format("{}", fmt::join(notes, "; "));
  conclude_without_value(j, false);
  return j;
}

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
