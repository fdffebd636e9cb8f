// report.md: the tables of report/sections.hpp in Markdown, fit for a CI log.
#include "report/sections.hpp"

#include "common/input.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pldamp::harness {
namespace {

// A text of the scene's (a name, a quote, a label) in a Markdown line or table cell: one line,
// control characters and bytes that are not UTF-8 escaped (a claim named with an ESC sequence
// reached report.md raw), a '|' that would end a cell escaped.
std::string md(std::string_view text) {
  std::string out;
  for (const char c : one_line(text)) {
    if (c == '|') {
      out += '\\';
    }
    out += c;
  }
  return out;
}

// A table in Markdown.
std::string markdown_table(const MapTable& table) {
  std::string out = "|";
  for (const std::string& head : table.header) {
    out.append(" ").append(md(head)).append(" |"); // (GCC 12 warns, falsely, on " " + md + " |")
  }
  out += "\n|";
  for (std::size_t c = 0; c < table.header.size(); ++c) {
    out += "---|";
  }
  for (const std::vector<std::string>& row : table.rows) {
    out += "\n|";
    for (const std::string& entry : row) {
      out.append(" ").append(md(entry)).append(" |");
    }
  }
  return out + "\n";
}

// The † footnote under the analytic map, one line per observable out of double's range.
std::string analytic_footnote(const Plan& plan) {
  const std::string lines = unrepresentable_note(plan);
  if (lines.empty()) {
    return "";
  }
  std::string out = "\n† an observable out of double's range (it under- or overflows there; not an "
                    "error of the closed form):\n\n";
  std::istringstream each(lines);
  for (std::string line; std::getline(each, line);) {
    out += "- " + line + "\n";
  }
  return out;
}

// A map as a Markdown table.
std::string markdown_map(const Plan& plan,
                         const std::function<std::string(std::size_t point)>& cell) {
  return markdown_table(map_table(plan, cell));
}

std::string step_study_markdown(const Plan& plan, const StepStudy& study) {
  std::string out = "\n## Time-step study: steps per contact for e within 1 %, 0.1 %, 0.01 %\n\n" +
                    step_study_description(study) + "\n";
  for (const StepSweep& sweep : study.sweeps) {
    out += fmt::format("\n### {}\n\n| p | order in e | 1 % | 0.1 % | 0.01 % | spread of e over "
                       "onset phases, coarsest → finest step |\n|---|---|---|---|---|---|\n",
                       sweep.line);
    const std::size_t e = study.e;
    for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
      out +=
          fmt::format("| {} | {} |", to_string_full(plan.scene.p[i]), short_number(sweep.order[i]));
      for (std::size_t t = 0; t < step_targets.size(); ++t) {
        out += fmt::format(" {} |", step_steps_text(plan, sweep, sweep.needed[i][t]));
      }
      out += fmt::format(" {} |\n", phase_spread_text(sweep, e, i));
    }
    out += "\nPer point, steps per contact for 1 % / 0.1 % / 0.01 %:\n\n" +
           markdown_table(step_points_table(plan, sweep)) + "\n";
  }
  out += "\nThe seed's Δt_crit and the tangent-stiffness bound (MATH.md §6), as steps per undamped "
         "contact τ0/Δt:";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    out += fmt::format(" p = {}: {:.3g} and {:.3g};", to_string_full(plan.scene.p[i]),
                       1 / study.dt_crit_over_tau0[i], 1 / study.dt_tangent_over_tau0[i]);
  }
  out.back() = '.';
  return out + "\n";
}

} // namespace

std::string report_markdown(const RunReport& report) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  std::ostringstream out;
  out << "# pldamp report: " << md(plan.scene.name) << "\n\n";
  if (report.made != nullptr) {
    out << "Made by " << md(provenance_line(*report.made)) << " (scene text "
        << report.made->scene_checksum << ").\n\n";
  }
  out << "Scene `" << md(plan.scene.path) << "`, end " << name_of(contact_ends, plan.scene.end)
      << ": " << plan.cells.size() << " cells × " << plan.configs.size()
      << " solver configurations, " << report.totals.solver_runs << " solver runs, "
      << report.totals.rhs_evals << " rhs evaluations, "
      << short_number(report.totals.wall_seconds, 3) << " s. " << budgets.failed_records
      << " failed records.\n\n**How to read this report.** " << how_to_read << "\n\n";
  if (!plan.scene.contacts.empty()) {
    out << "## Contacts from materials\n\n"
        << markdown_table(contacts_table(report)) << "\n"
        << markdown_table(contact_truth_table(report)) << "\n"
        << contacts_note(report) << "\n\n";
  }
  if (!budgets.claims.empty()) {
    out << "## Claims\n\n| claim | where | verdict | worst case | measured | bound | margin | ten "
           "times denser |\n|---|---|---|---|---|---|---|---|\n";
    for (const ClaimRow& row : claim_rows(report)) {
      out << "| " << md(row.name) << " | " << md(row.where) << " | **" << row.verdict << "** | "
          << md(row.worst) << " | " << row.measured << " | " << row.bound << " | " << row.margin
          << " | " << row.denser << " |\n";
    }
    out << "\n";
    for (const ClaimRow& row : claim_rows(report)) {
      out << "- **" << md(row.name) << "** (" << row.kind << "; " << md(row.subject) << "). "
          << (row.quote.empty() ? "" : "\"" + md(row.quote) + "\" ") << "Judged over " << row.grid
          << ". Measured: " << row.meaning << "."
          << (row.note.empty() ? "" : " " + md(row.note) + ".")
          << (row.without_value.empty() ? "" : " " + row.without_value) << "\n";
    }
    out << "\n";
  }
  if (!budgets.searches.empty()) {
    out << "## Searches: the loosest setting that keeps a bound\n\n"
        << markdown_table(search_table(report)) << "\n"
        << search_table_note(report) << "\n\n";
  }
  if (const MapTable external = external_table(report); !external.rows.empty()) {
    out << "## External solvers\n\n" << markdown_table(external) << "\n";
  }
  if (const MapTable checked = trajectory_table(report); !checked.rows.empty()) {
    out << "## Trajectories checked\n\n" << markdown_table(checked) << "\n";
  }
  out << "## Worst relative error over the grid\n\n"
      << markdown_table(error_table(report)) << "\n## Cost per cell\n\n"
      << markdown_table(cost_table(report));
  out << "\n" << budget_table_note(plan) << "\n";
  out << "\n## Work precision: cost against error, per p\n\n"
      << markdown_table(work_precision_table(report)) << "\n"
      << work_precision_note(plan) << "\n";
  if (!budgets.steps.sweeps.empty()) {
    out << step_study_markdown(plan, budgets.steps);
  }
  out << "\n## Worst relative error per p × α_eff, per configuration\n";
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    out << "\n### " << plan.configs[c].label() << "\n\n"
        << markdown_map(
               plan, [&](std::size_t point) { return short_number(worst_at(budgets, c, point)); });
  }
  out << "\n## The analytic layer in double against " << precision_name<Exact>()
      << " (relative error, worst observable)\n\n"
      << markdown_map(plan,
                      [&](std::size_t point) {
                        const Point& at = plan.points[point];
                        return short_number(analytic_worst(at)) +
                               (not_representable(plan, at).empty() ? "" : " †");
                      })
      << analytic_footnote(plan);
  if (!report.figures.empty()) {
    out << "\n## The seed's figures: solver against closed form\n\n| figure | largest deviation "
           "|\n|---|---|\n";
    for (const Figure& figure : report.figures) {
      out << "| " << figure.title << " | "
          << (figure.failure.empty() ? short_number(figure.deviation) + " in " + figure.deviation_of
                                     : "failed: " + figure.failure)
          << " |\n";
    }
    for (const Figure& figure : report.figures) {
      if (figure.table_header.empty()) {
        continue;
      }
      out << "\n"
          << figure.title << "\n\n"
          << markdown_table(MapTable{figure.table_header, figure.table_rows});
    }
  }
  if (budgets.failed_records > 0) {
    out << "\n## Failed records\n\n";
    long shown = 0;
    for (const Record& record : report.records) {
      if (record.failed() && shown++ < 20) {
        out << "- " << schema::record_key(record_id(plan, record)) << ": " << record.outcome_name()
            << (record.failure.empty() ? "" : " (" + record.failure + ")") << "\n";
      }
    }
  }
  return out.str();
}

} // namespace pldamp::harness
