// Work precision in the reports: report.json's budgets.work_precision points (every observable and
// the worst of all), report.md's table and report.html's diagrams (the series the scene chose,
// [report] work_precision).
#include "report/html_parts.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace pldamp::harness {

using nlohmann::ordered_json;

ordered_json work_precision_json(const RunReport& report) {
  namespace key = schema::key;
  using schema::number_or_null;
  const Plan& plan = report.plan;
  ordered_json points = ordered_json::array();
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    for (const WorkPoint& point : report.budgets.work[c]) {
      ordered_json by_observable = ordered_json::object();
      for (std::size_t o = 0; o < plan.observables.size(); ++o) {
        const WorkError& error = point.observables[o];
        by_observable[plan.observables[o]->key] = {{key::max_rel, number_or_null(error.error)},
                                                   {key::cells_without, error.cells_without}};
      }
      points.push_back({{key::config, plan.configs[c].label()},
                        {key::solver, plan.configs[c].name},
                        {key::p, point.p},
                        {key::seconds, point.seconds},
                        {key::rhs_evals, point.rhs_evals},
                        {key::analytic_seconds, point.analytic_seconds},
                        {key::x_analytic, number_or_null(point.seconds / point.analytic_seconds)},
                        {key::max_rel, number_or_null(point.worst_of_all.error)},
                        {key::cells, point.cells},
                        {key::skipped_cells, point.skipped_cells},
                        {key::cells_without, point.worst_of_all.cells_without},
                        {key::by_observable, by_observable}});
    }
  }
  return points;
}

namespace {

// "3.1e-07", "3.1e-07 (3 of 15 cells without)", "–".
std::string work_error_text(const WorkError& error, long cells) {
  return short_number(error.error) +
         (error.cells_without > 0
              ? fmt::format(" ({} of {} cells without)", error.cells_without, cells)
              : "");
}

// "e", or "worst of all observables".
std::string work_panel_title(const WorkPanel& panel) {
  return panel.observable ? panel.key : "worst of all observables";
}

} // namespace

MapTable work_precision_table(const RunReport& report) {
  const Plan& plan = report.plan;
  const std::vector<WorkPanel> panels = work_panels(plan);
  MapTable table{{"p", "configuration", "rhs_evals / cell", "µs / cell", "× analytic"}, {}};
  for (const WorkPanel& panel : panels) {
    table.header.push_back(work_panel_title(panel));
  }
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    for (std::size_t c = 0; c < plan.configs.size(); ++c) {
      const WorkPoint& point = report.budgets.work[c][i];
      const bool run = point.cells > point.skipped_cells;
      std::vector<std::string> row{to_string_full(point.p), plan.configs[c].label(),
                                   run ? short_number(point.rhs_evals, 3) : "–",
                                   run ? short_number(point.seconds * 1e6, 3) : "–",
                                   run && point.analytic_seconds > 0
                                       ? short_number(point.seconds / point.analytic_seconds, 2)
                                       : "–"};
      for (const WorkPanel& panel : panels) {
        row.push_back(work_error_text(error_of(point, panel), point.cells));
      }
      table.rows.push_back(row);
    }
  }
  return table;
}

std::string work_precision_note(const Plan& plan) {
  const std::vector<WorkPanel> panels = work_panels(plan);
  std::string series; // "e and the worst of all observables"
  for (std::size_t i = 0; i < panels.size(); ++i) {
    const char* joint = i == 0 ? "" : i + 1 == panels.size() ? " and " : ", ";
    series += joint + (panels[i].observable ? panels[i].key : "the worst of all observables");
  }
  return fmt::format(
      "One row per p and configuration, as the work-precision diagrams: rhs_evals and µs per "
      "cell are the means over the cells run at that p (each record's fastest repeat), × "
      "analytic the time per cell as a multiple of the closed forms'; then the largest relative "
      "error over those cells of {} ([report] work_precision in the scene chooses them). A "
      "cell without a value (failed, skipped, not measured, without a truth) is counted beside "
      "the error, never hidden: \"(3 of 15 cells without)\"; for the worst of all observables, "
      "the cells without a value of any. report.json's work_precision has every observable.",
      series);
}

namespace html {
namespace {

// The closed forms in double at one p: their cost per cell and their worst representable error
// in the panel's observable (or in any).
struct ClosedForm {
  double seconds = 0;
  std::optional<double> error;
};
ClosedForm closed_form_at(const Plan& plan, std::size_t p_index, const WorkPanel& panel) {
  ClosedForm out;
  long cells = 0;
  const std::size_t dampings = plan.scene.damping.size();
  for (const Cell& cell : plan.cells) {
    if (cell.point / dampings == p_index) {
      const Point& point = plan.points[cell.point];
      out.seconds += point.analytic_seconds;
      ++cells;
      const std::optional<double> error =
          panel.observable ? point.analytic[*panel.observable].error : analytic_worst(point);
      if (error && (!out.error || *error > *out.error)) {
        out.error = error;
      }
    }
  }
  out.seconds /= double(std::max(cells, 1L));
  return out;
}

enum class Axis { time, rhs_evals };

// Error in the panel's observable (or the worst of all) against time (or rhs evaluations) at
// one p, one line per solver in double or in extended precision, with the closed forms as
// references: their cost per cell (a vertical line, on time axes) and their own error in double
// (a horizontal line).
std::string work_precision_plot(const Gnuplot& gnuplot, const RunReport& report,
                                std::size_t p_index, const WorkPanel& panel, Axis axis,
                                bool extended) {
  const Plan& plan = report.plan;
  std::ostringstream script;
  script << "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\nset grid\n"
         << "set key outside below left Left reverse maxcols 2 noenhanced\nset xlabel "
         << (axis == Axis::time ? "'wall time per collision [s]'"
                                : "'rhs evaluations per collision'")
         << "\nset ylabel "
         << gnuplot_string(panel.observable ? "largest relative error in " + panel.key
                                            : std::string("largest relative error, any observable"))
         << " noenhanced\nset title "
         << gnuplot_string(fmt::format("p = {}, {}: {}", plan.scene.p[p_index],
                                       extended ? "extended precision" : "double precision",
                                       work_panel_title(panel)))
         << " noenhanced\n";
  std::string plot;
  int block = 0;
  // The ranges cover the data and the references (gnuplot would clip a reference outside).
  double x_low = std::numeric_limits<double>::infinity(), x_high = 0, y_low = x_low, y_high = 0;
  auto cover = [](double& low, double& high, double value) {
    low = std::min(low, value);
    high = std::max(high, value);
  };
  for (const Line& line : solver_lines(plan)) {
    if (line.extended != extended) {
      continue;
    }
    std::string data;
    for (const std::size_t c : line.configs) {
      const WorkPoint& w = report.budgets.work[c][p_index];
      const double x = axis == Axis::time ? w.seconds : w.rhs_evals;
      const std::optional<double>& error = error_of(w, panel).error;
      if (error && *error > 0 && std::isfinite(*error) && x > 0) {
        data += fmt::format("{:.17g} {:.17g}\n", x, *error);
        cover(x_low, x_high, x);
        cover(y_low, y_high, *error);
      }
    }
    if (data.empty()) {
      continue;
    }
    script << "$d" << block << " << EOD\n" << data << "EOD\n";
    plot += fmt::format("{}$d{} with linespoints lw 2 lc rgb '{}' pt {} ps 0.9 dt {} title {}",
                        plot.empty() ? "plot " : ", ", block, line.style.colour, line.style.marker,
                        line.style.dash, gnuplot_string(line.name));
    ++block;
  }
  if (block == 0) {
    return "";
  }
  const ClosedForm closed = closed_form_at(plan, p_index, panel);
  const bool cost_line = axis == Axis::time && closed.seconds > 0;
  const bool error_line = !extended && closed.error && *closed.error > 0;
  if (cost_line) {
    cover(x_low, x_high, closed.seconds);
    script << fmt::format("set arrow from {0:.17g}, graph 0 to {0:.17g}, graph 1 nohead lw 1.5 "
                          "lc rgb '#555555' dt 2 front\n"
                          "set label 'closed forms' at {0:.17g}, graph 0.97 left offset 0.4,0 "
                          "tc rgb '#555555' font ',9' noenhanced front\n",
                          closed.seconds);
  }
  if (error_line) {
    cover(y_low, y_high, *closed.error);
    script << fmt::format("set arrow from graph 0, first {0:.17g} to graph 1, first {0:.17g} "
                          "nohead lw 1.5 lc rgb '#555555' dt 3 front\n"
                          "set label 'closed forms'' own error' at graph 0.02, first {0:.17g} "
                          "offset 0,0.7 tc rgb '#555555' font ',9' noenhanced front\n",
                          *closed.error);
  }
  // Half a decade of room on each side (a whole one above, for the labels).
  script << fmt::format("set xrange [{:.17g}:{:.17g}]\nset yrange [{:.17g}:{:.17g}]\n", x_low / 3,
                        x_high * 3, y_low / 3, y_high * 10);
  script << plot << "\n";
  return gnuplot.svg(script.str(), 640, key_height(block));
}

// Under a work-precision plot: the records at its p that gave the panel no value, counted per
// configuration drawn (the first three named), or "" when every cell gave one.
std::string without_caption(const RunReport& report, std::size_t p_index, const WorkPanel& panel,
                            bool extended) {
  const Plan& plan = report.plan;
  long without = 0, cells = 0;
  std::vector<std::string> named;
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    if ((plan.configs[c].precision != "double") != extended) {
      continue;
    }
    const WorkPoint& point = report.budgets.work[c][p_index];
    const long missing = error_of(point, panel).cells_without;
    cells += point.cells;
    without += missing;
    if (missing > 0) {
      named.push_back(fmt::format("{} {} of {}", plan.configs[c].label(), missing, point.cells));
    }
  }
  if (without == 0) {
    return "";
  }
  std::string listed;
  for (std::size_t i = 0; i < named.size() && i < 3; ++i) {
    listed += (i ? "; " : "") + named[i];
  }
  return fmt::format("{} of {} records at this p gave no {} (failed, skipped, not measured or "
                     "without a truth; {}{}): each point is the worst over the others.",
                     without, cells, panel.observable ? panel.key : "observable", listed,
                     named.size() > 3 ? fmt::format("; and {} more", named.size() - 3) : "");
}

} // namespace

std::string work_precision_html(const RunReport& report, const Gnuplot& gnuplot,
                                bool any_extended) {
  const Plan& plan = report.plan;
  const std::vector<WorkPanel> panels = work_panels(plan);
  std::string out =
      "<h2>Work-precision</h2>\n<p class='read'>Each line is a solver, each point one of its "
      "configurations: the mean cost per cell against the largest relative error at that p of "
      "one observable, or of any (the worst of all, which one ill-conditioned observable can "
      "dominate). The scene's [report] work_precision chooses them; report.json has every "
      "observable. The dashed grey lines are the closed forms: their time per cell in double "
      "and their own error in double.</p>\n";
  for (const WorkPanel& panel : panels) {
    out += "<h3>" +
           escape(panel.observable ? "The error in " + panel.key : "The worst of all observables") +
           "</h3>\n";
    for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
      for (const bool extended : {false, true}) {
        if (extended && !any_extended) {
          continue;
        }
        const std::string caption = escape(without_caption(report, i, panel, extended));
        std::string shown;
        for (const Axis axis : {Axis::time, Axis::rhs_evals}) {
          if (!extended || axis == Axis::time) {
            shown += figure_html(work_precision_plot(gnuplot, report, i, panel, axis, extended),
                                 caption);
          }
        }
        if (shown.empty() && gnuplot.available()) {
          out += fmt::format("<p>p = {}, {}: no configuration gave {} a point to draw (a "
                             "positive, finite error). {}</p>\n",
                             to_string_full(plan.scene.p[i]), extended ? "extended" : "double",
                             escape(panel.key), caption);
        }
        out += shown;
      }
    }
  }
  return out + "<details><summary>The work-precision table</summary>" +
         html_table(work_precision_table(report)) + "<p class='read'>" +
         escape(work_precision_note(plan)) + "</p></details>\n";
}

} // namespace html
} // namespace pldamp::harness
