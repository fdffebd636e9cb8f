// The claims judged on two sides of a relation (a quantity against a formula, cell by cell) and
// on an asymptotic gap shrinking with the grid's parameter (judge/claims.hpp).
#include "judge/claim_parts.hpp"

#include "judge/solve.hpp"
#include "truth/point_bytes.hpp"

#include "pldamp/analytic/instances.hpp" // the closed forms instantiated once, not here
#include "pldamp/analytic/seed.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace pldamp::harness::claim_parts {

namespace {

namespace seed = analytic::seed;

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

} // namespace

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

} // namespace pldamp::harness::claim_parts
