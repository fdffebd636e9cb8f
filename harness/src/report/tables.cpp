// The reports' tables and notes, each built once and written by report.md and report.html alike.
#include "report/sections.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace pldamp::harness {

std::string short_number(const std::optional<double>& x, int digits) {
  if (!x) {
    return "–";
  }
  if (std::isinf(*x)) {
    return "inf";
  }
  return fmt::format("{:.{}g}", *x, digits + 1);
}

namespace {

// The damping points' columns: returning contacts by α_eff, then those that do not return (the
// seed's sinh branch) apart.
std::vector<std::size_t> damping_columns(const Plan& plan) {
  std::vector<std::size_t> columns(plan.scene.damping.size());
  std::iota(columns.begin(), columns.end(), 0);
  const auto alpha_eff = [&](std::size_t d) { return plan.points[d].alpha_eff; };
  std::stable_sort(columns.begin(), columns.end(), [&](std::size_t a, std::size_t b) {
    const bool over_a = plan.points[a].overdamped, over_b = plan.points[b].overdamped;
    return over_a != over_b ? !over_a : alpha_eff(a) < alpha_eff(b);
  });
  return columns;
}

} // namespace

MapTable map_table(const Plan& plan, const std::function<std::string(std::size_t point)>& cell) {
  const std::vector<std::size_t> columns = damping_columns(plan);
  const std::size_t dampings = plan.scene.damping.size();
  // No return (α_eff ≥ 1 for the seed's dashpot; beyond it, what the reference solve found).
  const auto overdamped = [&](std::size_t d) { return plan.points[d].overdamped; };
  const auto starts_overdamped = [&](std::size_t c) {
    return overdamped(columns[c]) && (c == 0 || !overdamped(columns[c - 1]));
  };
  MapTable table;
  table.header.emplace_back("p \\ α_eff");
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (starts_overdamped(c)) {
      table.header.emplace_back("overdamped:");
    }
    const Point& point = plan.points[columns[c]];
    table.header.push_back(short_number(point.alpha_eff, 3) + " (" + point.damping.label() + ")");
  }
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    std::vector<std::string> row{to_string_full(plan.scene.p[i])};
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (starts_overdamped(c)) {
        row.emplace_back();
      }
      row.push_back(cell(i * dampings + columns[c]));
    }
    table.rows.push_back(row);
  }
  return table;
}

double mean_analytic_seconds(const Plan& plan) {
  double sum = 0;
  for (const Cell& cell : plan.cells) {
    sum += plan.points[cell.point].analytic_seconds;
  }
  return plan.cells.empty() ? 0 : sum / double(plan.cells.size());
}

std::string step_steps_text(const Plan& plan, const StepSweep& sweep, const StepsNeeded& needed) {
  if (!needed.returns) {
    return "no return";
  }
  if (!needed.steps) {
    return fmt::format("> {}", *plan.configs[sweep.configs.back()].steps_per_contact);
  }
  return (needed.within_sweep && !needed.from_sweep ? "" : "≤ ") +
         fmt::format("{:.0f}", *needed.steps);
}

MapTable step_points_table(const Plan& plan, const StepSweep& sweep) {
  return map_table(plan, [&](std::size_t point) {
    std::string text;
    for (const StepsNeeded& needed : sweep.by_point[point]) {
      text += (text.empty() ? "" : " / ") + step_steps_text(plan, sweep, needed);
    }
    return text;
  });
}

std::string step_study_description(const StepStudy& study) {
  int phases = 0;
  bool from_sweep = false;
  for (const StepSweep& sweep : study.sweeps) {
    phases = std::max(phases, sweep.onset_phases);
    from_sweep = from_sweep || sweep.onset_phases == 0;
  }
  return fmt::format(
      "Steps per contact is (π δ_u/v0)/Δt, the `steps_per_contact` a scene and `pldamp solve` "
      "set (δ_u the undamped peak overlap); τ/Δt, each answer's true contact duration per step, "
      "is in report.json beside it. Each (p, damping) point's answer is that of a [[search]] over "
      "the sweep's range (judge/search.hpp): scanned from the finest step, 8 values a decade, then "
      "bisected at the first failure, each value's error the worst over every onset phase (sought "
      "from {} sampled: the jumps where the exit step changes bisected to 2^-52, each smooth "
      "maximum by Brent's method), and 8 values up to twice as tight checked, the answer sought "
      "again past any that fails{}. Per p, the worst over the grid's dampings. The order is the "
      "slope "
      "of the worst error in e against Δt over the finest half of the sweep.",
      phases > 0 ? phases : 8,
      from_sweep ? "; an external program's answer is read off its sweep (≤: the coarsest sweep "
                   "value from which every finer one held)"
                 : "");
}
std::string phase_spread_text(const StepSweep& sweep, std::size_t e, std::size_t p_index) {
  const std::optional<double>& coarsest = sweep.points[e][p_index].front().spread;
  const std::optional<double>& finest = sweep.points[e][p_index].back().spread;
  return coarsest || finest ? short_number(coarsest) + " → " + short_number(finest) : "–";
}

std::string unrepresentable_note(const Plan& plan) {
  std::string lines;
  for (const Point& point : plan.points) {
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const AnalyticCheck& check = point.analytic[o];
      if (!check.representable) {
        const std::string key(plan.observables[o]->key);
        lines += fmt::format(
            "p={} {}: {} is not representable in double{}\n", to_string_full(point.p),
            point.damping.label(), key,
            check.log_error ? "; ln " + key + " errs " + short_number(check.log_error) : "");
      }
    }
  }
  return lines;
}

namespace {

bool any_overdamped(const Plan& plan) {
  return std::any_of(plan.points.begin(), plan.points.end(),
                     [](const Point& point) { return point.overdamped; });
}

} // namespace

std::vector<ClaimRow> claim_rows(const RunReport& report) {
  const std::vector<Verdict>& claims = report.budgets.claims;
  std::vector<std::size_t> order(claims.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = i;
  }
  // An unexpected verdict first, then the failing claims, then those that hold.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    auto rank = [&](const Verdict& v) { return v.unexpected() ? 0 : v.holds ? 2 : 1; };
    return rank(claims[a]) < rank(claims[b]);
  });
  std::vector<ClaimRow> rows;
  for (const std::size_t i : order) {
    const Verdict& v = claims[i];
    ClaimRow row;
    row.name = v.name;
    row.kind = v.kind;
    row.subject = v.observable + ", " + v.config;
    row.where = v.where.empty() ? "–" : v.where;
    row.quote = v.quote;
    row.figure = v.figure;
    row.holds = v.holds;
    row.unexpected = v.unexpected();
    row.verdict =
        verdict_text(v) + (v.unexpected()
                               ? (v.expect_holds ? ", unexpected" : ", unexpected: pinned as fails")
                               : (v.holds ? "" : " (expected)"));
    row.worst = v.worst.empty() ? "–" : v.worst;
    row.measured = short_number(v.measured, 3);
    row.bound = short_number(v.bound);
    row.margin = short_number(v.margin);
    row.denser =
        !v.denser ? "–"
        : v.denser->holds == v.holds
            ? verdict_text(*v.denser) + ", unchanged (" + short_number(v.denser->measured, 3) + ")"
            : verdict_text(*v.denser) + ": CHANGED (" + short_number(v.denser->measured, 3) +
                  " at " + v.denser->worst + ")";
    row.grid = v.grid + (v.denser ? "; denser: " + v.denser->grid : "");
    row.note = v.note;
    // Every cell without a value that the verdict keeps (the first 20), with why.
    for (const Judgement* j :
         {static_cast<const Judgement*>(&v), v.denser ? &*v.denser : nullptr}) {
      if (j == nullptr || j->without_value.empty()) {
        continue;
      }
      std::string listed;
      for (const CellWithoutValue& c : j->without_value) {
        listed += (listed.empty() ? "" : "; ") + c.cell + " (" + c.why + ")";
      }
      const long more = j->failed_cells + j->missing_cells - long(j->without_value.size());
      row.without_value +=
          fmt::format("{}Without a value{}: {}{}.", row.without_value.empty() ? "" : " ",
                      j == &v ? "" : " on the denser grid", listed,
                      more > 0 ? fmt::format("; and {} more", more) : "");
    }
    row.meaning = v.meaning;
    rows.push_back(row);
  }
  return rows;
}

std::string budget_table_note(const Plan& plan) {
  return fmt::format(
      "Worst cell: where the configuration's largest relative error is (its observable in "
      "brackets). rhs_evals / cell: the mean right-hand-side and Jacobian evaluations per "
      "collision{}. µs / cell: the mean over the cells of each record's fastest repeat{}. "
      "× analytic: the time per cell as a multiple of the closed forms' for the same observables "
      "in double ({} µs per cell).",
      any_overdamped(plan) ? ", underdamped and overdamped cells apart (an overdamped contact "
                             "never returns: its solve runs until its energy is below the "
                             "noise or to the horizon)"
                           : "",
      plan.scene.repeats > 1
          ? fmt::format("; slowest repeat: how much slower the slowest was (the noise of the "
                        "machine); a run of {} s of CPU or more is timed once",
                        short_number(plan.scene.repeat_below, 3))
          : "",
      short_number(mean_analytic_seconds(plan) * 1e6, 2));
}

namespace {
// ", phase 0.3359" (report.json has every digit, which `solve --onset-phase` takes), or nothing.
std::string phase_text(const std::optional<double>& phase) {
  return phase ? fmt::format(", phase {:.4g}", *phase) : std::string();
}
} // namespace

MapTable search_table(const RunReport& report) {
  MapTable table;
  table.header = {
      "search", "group",       "loosest value", "first value beyond", "measured there", "bound",
      "trials", "solver runs", "note"};
  for (const SearchResult& search : report.budgets.searches) {
    for (const SearchGroup& group : search.groups) {
      table.rows.push_back(
          {search.name, group.group,
           group.loosest ? fmt::format("{} = {:.3g}", search.parameter, *group.loosest)
                         : "none in the range",
           group.failing
               ? fmt::format("{:.3g}", *group.failing) +
                     (group.failing_measured ? " (" + short_number(group.failing_measured, 3) +
                                                   phase_text(group.failing_onset_phase) + ")"
                                             : "")
               : "–",
           short_number(group.measured, 3) + phase_text(group.worst_onset_phase) +
               (group.worst.empty() ? "" : " at " + group.worst),
           short_number(search.bound), std::to_string(group.trials),
           std::to_string(group.solver_runs), group.note.empty() ? "–" : group.note});
    }
  }
  return table;
}

std::string search_table_note(const RunReport& report) {
  std::string out;
  for (const SearchResult& search : report.budgets.searches) {
    out += fmt::format(
        "{}{}: {} of {}, keeping {} at most {:g}{}.", out.empty() ? "" : " ", search.name,
        search.parameter, search.line, search.measure, search.bound,
        search.quote.empty() ? "" : fmt::format(" (\"{}\", {})", search.quote, search.where));
  }
  return out + (out.empty()
                    ? ""
                    : " Scanned from the range's tight end at 8 values a decade and bisected on "
                      "the parameter's logarithm at the first failure, then 8 values up to "
                      "twice as tight checked: the loosest value kept the bound, the next one "
                      "tried broke it (its error and onset phase in brackets; report.json has "
                      "the phases to the last digit).");
}

MapTable trajectory_table(const RunReport& report) {
  MapTable table{{"trajectory", "inputs", "observable", "measured", "truth", "rel error",
                  "sampling (rel)", "verdict"},
                 {}};
  if (report.trajectories == nullptr) {
    return table;
  }
  for (const TrajectoryCheck& check : *report.trajectories) {
    if (!check.failure.empty()) {
      table.rows.push_back(
          {check.label, check.inputs, "–", "failed: " + check.failure, "", "", "", ""});
      continue;
    }
    for (const TrajectoryRow& row : check.rows) {
      table.rows.push_back(
          {check.label, check.inputs, row.key, row.value ? short_number(row.value, 9) : "missing",
           short_number(row.truth, 9), short_number(row.judgement.relative_error),
           short_number(row.judgement.relative_sampling),
           row.judgement.explained ? verdict_name(row.judgement) : row.judgement.why_not});
    }
  }
  return table;
}

MapTable external_table(const RunReport& report) {
  const Plan& plan = report.plan;
  MapTable table{{"external solver", "program", "says of itself", "run", "skipped", "failed",
                  "truth of its own dashpot", "largest difference from its replica"},
                 {}};
  struct Row {
    long run = 0, failed = 0;
    std::map<std::string, long> skipped, notes; // each reason and how many records it has
    std::optional<double> from_replica;
    std::string where; // the replica and the observable of the largest difference
  };
  std::vector<std::string> lines;
  std::vector<Row> rows;
  for (const Record& record : report.records) {
    const SolverConfig& config = plan.configs[record.config];
    if (!config.external()) {
      continue;
    }
    auto found = std::find(lines.begin(), lines.end(), config.line());
    if (found == lines.end()) {
      lines.push_back(config.line());
      rows.emplace_back();
      std::string program;
      for (const std::string& arg : config.command) {
        program += (program.empty() ? "" : " ") + arg;
      }
      const std::vector<std::string>& said = report.totals.external;
      table.rows.push_back(
          {config.line(), program, record.config < said.size() ? said[record.config] : ""});
      found = lines.end() - 1;
    }
    Row& row = rows[static_cast<std::size_t>(found - lines.begin())];
    if (record.skipped()) {
      ++row.skipped[record.skip_reason];
      continue;
    }
    ++row.run;
    row.failed += record.failed() ? 1 : 0;
    if (!record.note.empty()) {
      ++row.notes[record.note];
    }
    for (std::size_t o = 0; o < record.replica_difference.size(); ++o) {
      const std::optional<double>& difference = record.replica_difference[o];
      if (difference && !(*difference <= row.from_replica.value_or(-1.0))) {
        row.from_replica = difference;
        row.where = config.replica + ", " + std::string(plan.observables[o]->key);
      }
    }
  }
  // "21 (reason)", or with several reasons "28: 21 reason; 7 another".
  const auto counted = [](const std::map<std::string, long>& reasons) {
    long total = 0;
    std::string text;
    for (const auto& [reason, n] : reasons) {
      total += n;
      text += (text.empty() ? "" : "; ") + std::to_string(n) + " " + reason;
    }
    if (reasons.size() == 1) {
      return std::to_string(total) + " (" + reasons.begin()->first + ")";
    }
    return std::to_string(total) + (reasons.empty() ? "" : ": " + text);
  };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    table.rows[i].push_back(std::to_string(row.run));
    table.rows[i].push_back(counted(row.skipped));
    table.rows[i].push_back(std::to_string(row.failed));
    table.rows[i].push_back(counted(row.notes));
    table.rows[i].push_back(
        row.where.empty() ? "–" : short_number(row.from_replica) + " (" + row.where + ")");
  }
  return table;
}

MapTable error_table(const RunReport& report) {
  const Plan& plan = report.plan;
  MapTable table;
  table.header.emplace_back("configuration");
  for (const Observable* observable : plan.observables) {
    table.header.emplace_back(observable->key);
  }
  table.header.emplace_back("worst cell");
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    std::vector<std::string> row{plan.configs[c].label()};
    std::optional<double> largest_error;
    std::string worst_cell = "–";
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      const Worst& worst = report.budgets.worst[c][o];
      row.push_back(short_number(worst.rel));
      if (worst.rel && (!largest_error || *worst.rel > *largest_error)) {
        largest_error = worst.rel;
        worst_cell = fmt::format("{} ({})", worst.cell, plan.observables[o]->key);
      }
    }
    row.push_back(worst_cell);
    table.rows.push_back(row);
  }
  return table;
}

MapTable cost_table(const RunReport& report) {
  const Plan& plan = report.plan;
  const bool overdamped = any_overdamped(plan), repeats = plan.scene.repeats > 1;
  MapTable table;
  table.header = {"configuration",
                  overdamped ? "rhs_evals / cell, underdamped" : "rhs_evals / cell"};
  if (overdamped) {
    table.header.emplace_back("rhs_evals / cell, overdamped");
  }
  table.header.push_back(fmt::format("µs / cell (fastest of ≤ {})", plan.scene.repeats));
  if (repeats) {
    table.header.emplace_back("slowest repeat");
  }
  table.header.emplace_back("× analytic");
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const Cost& cost = report.budgets.cost[c];
    const auto per_cell = [](const RegimeCost& regime) {
      return regime.cells > 0 ? short_number(regime.rhs_evals, 3) : std::string("–");
    };
    std::vector<std::string> row{plan.configs[c].label(), per_cell(cost.underdamped)};
    if (overdamped) {
      row.push_back(per_cell(cost.overdamped));
    }
    const double cells = double(cost.underdamped.cells + cost.overdamped.cells);
    const auto mean = [&](double RegimeCost::*seconds) {
      return (cost.underdamped.*seconds * double(cost.underdamped.cells) +
              cost.overdamped.*seconds * double(cost.overdamped.cells)) /
             cells;
    };
    const double fastest = mean(&RegimeCost::seconds), slowest = mean(&RegimeCost::seconds_slowest);
    row.push_back(short_number(fastest * 1e6, 3));
    if (repeats) {
      row.push_back(fastest > 0 ? fmt::format("+{:.0f} %", 100 * (slowest / fastest - 1)) : "–");
    }
    row.push_back(short_number(times_analytic(report.budgets.work[c]), 2));
    table.rows.push_back(row);
  }
  return table;
}

} // namespace pldamp::harness
