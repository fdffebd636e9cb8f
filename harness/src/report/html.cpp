// report.html: one self-contained page. Plots are SVG drawn by gnuplot (its svg terminal, at a
// fixed size so the page lays them out at their natural size) from data written inline into its
// script: gnuplot is started with an argument vector, the script on its stdin and the SVG read
// from its stdout (common/process.hpp; no shell, no temporary file). gnuplot missing or failing
// leaves the tables and a note instead of the plots.
//
// Styles: every solver line of a scene (a solver in one precision) keeps one style on every plot,
// a colour of the Okabe–Ito palette (legible to colour-blind readers; its yellow left out, too
// faint on white), a marker and a dash pattern, so no two lines share all three. Work-precision
// plots put double and the extended precisions on separate panels (their errors lie 15 decades
// apart); error maps use a perceptually ordered sequential palette (viridis) with the exponent
// printed in each cell.
#include "report/html_parts.hpp"

#include "common/input.hpp"
#include "common/parallel.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace pldamp::harness {
namespace html {

Gnuplot::Gnuplot(std::string program) : program_(std::move(program)) {
  available_ = !program_.empty() && run_program({program_, "--version"}, "").succeeded();
}

std::string Gnuplot::svg(const std::string& script, int width, int height) const {
  if (!available_) {
    return "";
  }
  std::string full = fmt::format(
      "set terminal svg size {},{} fixed enhanced font 'sans,11' background rgb 'white'\n"
      "set output\n{}\n",
      width, height, script);
  if (recording_) {
    noted_.push_back(std::move(full));
    return "";
  }
  const auto drawn = drawn_.find(full);
  return drawn != drawn_.end() ? drawn->second : draw(full);
}

void Gnuplot::render(int jobs) {
  recording_ = false;
  std::vector<std::string> scripts = std::move(noted_);
  noted_.clear();
  std::sort(scripts.begin(), scripts.end());
  scripts.erase(std::unique(scripts.begin(), scripts.end()), scripts.end());
  std::vector<std::string> svgs(scripts.size());
  for_each_index(scripts.size(), jobs, [&](std::size_t i) { svgs[i] = draw(scripts[i]); });
  for (std::size_t i = 0; i < scripts.size(); ++i) {
    drawn_.emplace(std::move(scripts[i]), std::move(svgs[i]));
  }
}

std::string Gnuplot::draw(const std::string& full_script) const {
  const ProgramRun run = run_program({program_}, full_script);
  const auto start = run.out.find("<svg");
  return run.succeeded() && start != std::string::npos ? run.out.substr(start) : "";
}

std::string escape(std::string_view text) {
  // Control characters (but a line's end and a tab) and bytes that are not UTF-8 shown escaped,
  // as error lines show them: a scene named with an ESC and a NUL reached <title> raw.
  std::string shown;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = utf8_sequence(text.substr(i));
    const auto byte = static_cast<unsigned char>(text[i]);
    if (n == 0 || ((byte < 0x20 || byte == 0x7f) && text[i] != '\n' && text[i] != '\t')) {
      shown += one_line(text.substr(i, 1));
      ++i;
    } else if (hidden(code_point(text.substr(i, n)))) { // U+202E turned the title around
      shown += one_line(text.substr(i, n));
      i += n;
    } else {
      shown.append(text.substr(i, n));
      i += n;
    }
  }
  std::string out;
  for (const char c : shown) {
    switch (c) {
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '&':
      out += "&amp;";
      break;
    case '\'':
      out += "&#39;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

std::string gnuplot_string(std::string_view text) {
  std::string out = "'";
  for (const char c : text) {
    out += c == '\'' ? "''" : std::string(1, c);
  }
  return out + "'";
}

// Okabe & Ito's palette without yellow; gnuplot's filled markers, then the open ones.
constexpr std::array<const char*, 7> colours{"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                             "#E69F00", "#56B4E9", "#000000"};
constexpr std::array<int, 7> markers{7, 5, 9, 11, 13, 6, 4};

Style style_of(std::size_t line) {
  return {colours[line % colours.size()], markers[(line + line / colours.size()) % markers.size()],
          int(1 + line / colours.size() % 4)};
}

std::vector<Line> solver_lines(const Plan& plan) {
  std::vector<Line> lines;
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const std::string name = plan.configs[c].line();
    auto found = std::find_if(lines.begin(), lines.end(),
                              [&](const Line& line) { return line.name == name; });
    if (found == lines.end()) {
      lines.push_back({name, plan.configs[c].precision != "double", style_of(lines.size()), {}});
      found = lines.end() - 1;
    }
    found->configs.push_back(c);
  }
  return lines;
}

int key_height(int entries) {
  return 400 + 18 * ((entries + 1) / 2);
}

std::string html_table(const MapTable& table, const std::string& css_class) {
  std::string out = css_class.empty() ? "<table><tr>" : "<table class='" + css_class + "'><tr>";
  for (const std::string& head : table.header) {
    out += "<th>" + escape(head) + "</th>";
  }
  out += "</tr>\n";
  for (const std::vector<std::string>& row : table.rows) {
    out += "<tr>";
    for (const std::string& entry : row) {
      out += "<td>" + escape(entry) + "</td>";
    }
    out += "</tr>\n";
  }
  return out + "</table>\n";
}

std::string figure_html(const std::string& svg, const std::string& caption) {
  if (svg.empty()) {
    return "";
  }
  return "<figure>" + svg + (caption.empty() ? "" : "<figcaption>" + caption + "</figcaption>") +
         "</figure>\n";
}

} // namespace html

using namespace html;

namespace {

// The time-step study at one p, one observable: the worst error against Δt/τ per sweep, with
// the seed's Δt_crit and the tangent-stiffness bound (as fractions of the undamped τ0) marked.
std::string step_study_plot(const Gnuplot& gnuplot, const RunReport& report, std::size_t p_index,
                            std::size_t observable) {
  const Plan& plan = report.plan;
  const StepStudy& study = report.budgets.steps;
  std::ostringstream script;
  script << "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\nset grid\n"
         << "set key outside below left Left reverse maxcols 2 noenhanced\nset xlabel 'Δt / "
            "τ'\nset ylabel "
         << gnuplot_string("worst relative error in " +
                           std::string(plan.observables[observable]->key))
         << " noenhanced\nset title "
         << gnuplot_string(fmt::format("p = {}: {} against the step", plan.scene.p[p_index],
                                       plan.observables[observable]->key))
         << " noenhanced\n";
  std::string plot;
  int lines = 0;
  double x_low = std::numeric_limits<double>::infinity(), x_high = 0;
  for (std::size_t k = 0; k < study.sweeps.size(); ++k) {
    const StepSweep& sweep = study.sweeps[k];
    std::string data;
    for (const StepPoint& point : sweep.points[observable][p_index]) {
      if (point.error && *point.error > 0 && std::isfinite(*point.error) && point.dt_over_tau > 0) {
        data += fmt::format("{:.17g} {:.17g}\n", point.dt_over_tau, *point.error);
        x_low = std::min(x_low, point.dt_over_tau);
        x_high = std::max(x_high, point.dt_over_tau);
      }
    }
    if (data.empty()) {
      continue;
    }
    const Style style = style_of(k);
    ++lines;
    script << "$s" << k << " << EOD\n" << data << "EOD\n";
    plot += fmt::format("{}$s{} with linespoints lw 2 lc rgb '{}' pt {} ps 0.9 dt {} title {}",
                        plot.empty() ? "plot " : ", ", k, style.colour, style.marker, style.dash,
                        gnuplot_string(sweep.line));
  }
  if (plot.empty()) {
    return "";
  }
  // Labels right-aligned left of their lines, one above the other (the two lie close).
  const std::tuple<double, const char*, double> marks[] = {
      {study.dt_crit_over_tau0[p_index], "seed's Δt_crit/τ0", 0.95},
      {study.dt_tangent_over_tau0[p_index], "tangent bound/τ0", 0.88}};
  const double leftmost = std::min(std::get<0>(marks[0]), std::get<0>(marks[1]));
  for (const auto& [x, name, height] : marks) {
    x_high = std::max(x_high, x);
    script << fmt::format("set arrow from {0:.17g}, graph 0 to {0:.17g}, graph 1 nohead lw 1.5 "
                          "lc rgb '#555555' dt 2 front\nset label {1} at {2:.17g}, graph {3} "
                          "right offset -0.5,0 tc rgb '#555555' font ',9' noenhanced front\n",
                          x, gnuplot_string(name), leftmost, height);
  }
  script << fmt::format("set xrange [{:.17g}:{:.17g}]\n", x_low / 2, x_high * 2) << plot << "\n";
  return gnuplot.svg(script.str(), 640, key_height(lines));
}

// The viridis palette at 5 stops (perceptually ordered, legible in grey).
constexpr const char* viridis = "set palette defined (0 '#440154', 1 '#3B528B', 2 '#21908C', "
                                "3 '#5DC863', 4 '#FDE725')\n";

// log10 of the largest relative error over p × damping for one configuration, the exponent in
// each cell; an error of exactly 0 is printed as 0 and coloured as the best, a missing one as a
// dash on grey.
std::string error_map_plot(const Gnuplot& gnuplot, const RunReport& report, std::size_t config) {
  const Plan& plan = report.plan;
  const std::size_t dampings = plan.scene.damping.size();
  struct Entry {
    std::size_t d, i;
    std::optional<double> error;
  };
  std::vector<Entry> entries;
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    for (std::size_t d = 0; d < dampings; ++d) {
      const std::optional<double> worst = worst_at(report.budgets, config, i * dampings + d);
      entries.push_back({d, i, worst});
      if (worst && *worst > 0 && std::isfinite(*worst)) {
        lowest = std::min(lowest, std::log10(*worst));
        highest = std::max(highest, std::log10(*worst));
      }
    }
  }
  if (!std::isfinite(lowest)) { // every error 0, infinite or missing
    lowest = -17;
    highest = 0;
  }
  lowest = std::floor(lowest);
  highest = std::max(std::ceil(highest), lowest + 1);
  const double middle = (lowest + highest) / 2;
  std::string boxes, labels;
  for (const Entry& entry : entries) {
    if (!entry.error) {
      labels += fmt::format("{} {} \"–\" 3355443\n", entry.d, entry.i);
      continue;
    }
    const bool finite = std::isfinite(*entry.error);
    const double level = *entry.error > 0 && finite ? std::log10(*entry.error)
                         : finite                   ? lowest
                                                    : highest;
    boxes += fmt::format("{} {} {:.6g}\n", entry.d, entry.i, level);
    const std::string text = *entry.error == 0 ? "0"
                             : !finite         ? "inf"
                                               : fmt::format("{:.1f}", level);
    // Light text on the dark (low) half of viridis, dark text on the light half.
    labels +=
        fmt::format("{} {} \"{}\" {}\n", entry.d, entry.i, text, level < middle ? "16777215" : "0");
  }
  std::ostringstream script;
  script << "set xlabel 'damping'\nset ylabel 'p'\nset cblabel 'log_{10} relative error'\n"
         << "set title " << gnuplot_string(plan.configs[config].label()) << " noenhanced\n"
         << viridis << fmt::format("set cbrange [{}:{}]\n", lowest, highest)
         << fmt::format("set xrange [-0.5:{}]\nset yrange [-0.5:{}]\n", double(dampings) - 0.5,
                        double(plan.scene.p.size()) - 0.5)
         << "set object 1 rect from graph 0, graph 0 to graph 1, graph 1 behind fc rgb '#DDDDDD' "
            "fs solid noborder\nset xtics rotate by 45 right noenhanced (";
  for (std::size_t d = 0; d < dampings; ++d) {
    script << (d ? ", " : "") << gnuplot_string(plan.points[d].damping.label()) << " " << d;
  }
  script << ")\nset ytics (";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    script << (i ? ", " : "") << gnuplot_string(to_string_full(plan.scene.p[i])) << " " << i;
  }
  script << ")\n$boxes << EOD\n"
         << boxes << "EOD\n$labels << EOD\n"
         << labels << "EOD\n"
         << "plot $boxes using 1:2:(0.5):(0.5):3 with boxxyerror fs solid noborder fc palette "
            "notitle, $labels using 1:2:3:4 with labels tc rgb variable font ',9' notitle\n";
  return gnuplot.svg(script.str(), 620, 400);
}

// A seed figure: closed-form lines and the solver's points, a shared style per series pair.
std::string figure_plot(const Gnuplot& gnuplot, const Figure& figure) {
  std::ostringstream script;
  // The legend below the plot, as on the work-precision plots: a figure of five p and their
  // first orders has 16 entries, which beside the plot squeezed its axes to a third.
  script << "set grid\nset key outside below left Left reverse maxcols 2 noenhanced\n"
         << (figure.log_y ? "set logscale y\nset autoscale yfix\n" : "")
         << (figure.log_x ? "set logscale x\nset format x '%.0e'\n" : "") << "set title "
         << gnuplot_string(figure.title) << " noenhanced\nset xlabel "
         << gnuplot_string(figure.x_label) << " noenhanced\nset ylabel "
         << gnuplot_string(figure.y_label) << " noenhanced\n";
  std::string plot = "plot ";
  std::size_t pair = 0;
  for (std::size_t i = 0; i < figure.series.size(); ++i) {
    const Series& series = figure.series[i];
    // A new style at each closed form, and at points that follow points (two truths side by
    // side, the viscoelastic approximations' figure); a first order keeps its p's.
    if (i > 0 &&
        (series.closed_form || (!series.first_order && !figure.series[i - 1].closed_form))) {
      ++pair;
    }
    const Style style = style_of(pair);
    script << "$s" << i << " << EOD\n";
    for (const auto& [x, y] : series.points) {
      script << fmt::format("{:.17g} {:.17g}\n", x, y);
    }
    script << "EOD\n";
    plot +=
        fmt::format("{}$s{} {} lc rgb '{}' title {}", i ? ", " : "", i,
                    series.closed_form   ? fmt::format("with lines lw 2 dt {}", style.dash)
                    : series.first_order ? std::string("with lines lw 1 dt 2")
                                         : fmt::format("with points pt {} ps 0.9", style.marker),
                    style.colour, gnuplot_string(series.title));
  }
  script << plot << "\n";
  // Room below the 440-pixel plot for the legend, a row per series (long titles take one column).
  return gnuplot.svg(script.str(), 720, 440 + 17 * static_cast<int>(figure.series.size()));
}

// The time-step study: the table a DEM user quotes, then error against Δt/τ per p.
std::string step_study_html(const RunReport& report, const Gnuplot& gnuplot) {
  const Plan& plan = report.plan;
  const StepStudy& study = report.budgets.steps;
  std::string out = "<h2>Time-step study: steps per contact for e within 1 %, 0.1 %, 0.01 %</h2>\n"
                    "<p>" +
                    escape(step_study_description(study)) +
                    " The plots show the worst error against Δt/τ (τ each cell's true contact "
                    "duration, t_cut under the force cap) and mark the seed's Δt_crit and the "
                    "tangent-stiffness bound as fractions of the undamped τ0.</p>\n";
  MapTable table;
  table.header = {
      "sweep", "p", "order in e", "1 %", "0.1 %", "0.01 %", "spread of e over onset phases"};
  for (const StepSweep& sweep : study.sweeps) {
    for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
      std::vector<std::string> row{sweep.line, to_string_full(plan.scene.p[i]),
                                   short_number(sweep.order[i])};
      for (std::size_t t = 0; t < step_targets.size(); ++t) {
        row.push_back(step_steps_text(plan, sweep, sweep.needed[i][t]));
      }
      row.push_back(phase_spread_text(sweep, study.e, i));
      table.rows.push_back(row);
    }
  }
  out += html_table(table);
  for (const StepSweep& sweep : study.sweeps) {
    out += "<p>" + escape(sweep.line) +
           ", per point: steps per contact for 1 % / 0.1 % / 0.01 %</p>\n" +
           html_table(step_points_table(plan, sweep));
  }
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    for (const std::string_view key : {"e", "delta_max", "tau"}) {
      for (std::size_t o = 0; o < plan.observables.size(); ++o) {
        if (plan.observables[o]->key == key) {
          out += figure_html(step_study_plot(gnuplot, report, i, o));
        }
      }
    }
  }
  return out;
}

std::string page(const RunReport& report, const Gnuplot& gnuplot) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>pldamp: "
      << escape(plan.scene.name)
      << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:90em}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:2px "
         "6px;text-align:right;white-space:nowrap}th{background:#eee}td:first-child{text-align:"
         "left}"
         ".holds{color:#070}.fails{color:#b00;font-weight:bold}"
         "figure{display:inline-block;vertical-align:top;margin:0.5em}"
         "details.map{display:inline-block;vertical-align:top;margin:0.2em 0.5em}"
         "details.map summary{cursor:pointer;font-family:monospace}"
         // An inline-block sizes to its content: the plot keeps its natural size inside.
         "details.map figure svg{max-width:none}"
         "details.map:not([open]){margin:0.2em 0.5em 0.2em 0}"
         "figure svg{display:block;max-width:100%;height:auto}"
         // A caption wraps within its plot's width instead of widening the figure.
         "figcaption{width:0;min-width:100%;font-size:0.9em}"
         "p.read{max-width:60em;line-height:1.4}"
         // The claim table's words wrap, left-aligned; its numbers stay on one line.
         "table.claims td{text-align:left;white-space:normal;vertical-align:top}"
         "table.wrap td{text-align:left;white-space:normal;vertical-align:top}"
         // A wide table of numbers: its headers wrap, its rows stay on one line.
         "table.headwrap th{white-space:normal;vertical-align:bottom}"
         "table.claims td.number{text-align:right;white-space:nowrap}"
         "ul.claims{max-width:75em;line-height:1.35}ul.claims li{margin:0.4em 0}"
         "@media print{body{margin:0;max-width:none}figure{break-inside:avoid}"
         "h2{break-after:avoid}}</style></head><body>\n";
  out << "<h1>pldamp report: " << escape(plan.scene.name) << "</h1>\n";
  if (report.made != nullptr) {
    out << "<p class='made'>Made by <code>" << escape(provenance_line(*report.made))
        << "</code> (scene text " << report.made->scene_checksum << ").</p>\n";
  }
  out << "<p>Scene <code>" << escape(plan.scene.path) << "</code>: " << plan.cells.size()
      << " cells × " << plan.configs.size() << " solver configurations, "
      << report.totals.solver_runs << " solver runs, " << report.totals.rhs_evals
      << " rhs evaluations, " << short_number(report.totals.wall_seconds, 3) << " s; "
      << budgets.failed_records
      << " failed records.</p>\n<p class='read'><strong>How to read this report.</strong> "
      << escape(how_to_read) << "</p>\n";
  if (!gnuplot.available()) {
    out << "<p><strong>gnuplot was not found: the plots were skipped.</strong></p>\n";
  }
  if (!plan.scene.contacts.empty()) {
    out << "<h2>Contacts from materials</h2>\n"
        << html_table(contacts_table(report)) << html_table(contact_truth_table(report), "headwrap")
        << "<p>" << escape(contacts_note(report)) << "</p>\n";
  }
  if (!budgets.claims.empty()) {
    out << "<h2 id='claims'>Claims</h2>\n<table class='claims'><tr><th>claim</th><th>where</th>"
           "<th>verdict</th>"
           "<th>worst case</th><th>measured</th><th>bound</th><th>margin</th><th>ten times "
           "denser</th></tr>\n";
    const std::vector<ClaimRow> rows = claim_rows(report);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const ClaimRow& row = rows[i];
      // The claim's name links to its figure, or else to its details below the table.
      const std::string target =
          row.figure.empty() ? fmt::format("claim-{}", i) : fmt::format("fig-{}", row.figure);
      out << "<tr><td><a href='#" << target << "'>" << escape(row.name) << "</a></td><td>"
          << escape(row.where) << "</td><td class='" << (row.holds ? "holds" : "fails") << "'>"
          << escape(row.verdict) << "</td><td>" << escape(row.worst) << "</td><td class='number'>"
          << row.measured << "</td><td class='number'>" << row.bound << "</td><td class='number'>"
          << row.margin << "</td><td>" << escape(row.denser) << "</td></tr>\n";
    }
    out << "</table>\n<ul class='claims'>\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const ClaimRow& row = rows[i];
      out << "<li id='claim-" << i << "'><strong>" << escape(row.name) << "</strong> ("
          << escape(row.kind) << "; " << escape(row.subject) << "). "
          << (row.quote.empty() ? "" : fmt::format("<q>{}</q> ", escape(row.quote)))
          << "Judged over " << escape(row.grid) << ". Measured: " << escape(row.meaning) << "."
          << (row.note.empty() ? "" : fmt::format(" {}.", escape(row.note)))
          << (row.without_value.empty() ? "" : fmt::format(" {}", escape(row.without_value)))
          << "</li>\n";
    }
    out << "</ul>\n";
  }
  const bool any_extended =
      std::any_of(plan.configs.begin(), plan.configs.end(),
                  [](const SolverConfig& c) { return c.precision != "double"; });
  out << work_precision_html(report, gnuplot, any_extended);
  if (!budgets.searches.empty()) {
    out << "<h2>Searches: the loosest setting that keeps a bound</h2>\n"
        << html_table(search_table(report)) << "<p class='read'>"
        << escape(search_table_note(report)) << "</p>\n";
  }
  if (const MapTable external = external_table(report); !external.rows.empty()) {
    out << "<h2>External solvers</h2>\n" << html_table(external, "wrap");
  }
  if (const MapTable checked = trajectory_table(report); !checked.rows.empty()) {
    out << "<h2>Trajectories checked</h2>\n" << html_table(checked, "wrap");
  }
  out << "<h2>Worst relative error over the grid</h2>\n"
      << html_table(error_table(report)) << "<h2>Cost per cell</h2>\n"
      << html_table(cost_table(report));
  out << "<p class='read'>" << escape(budget_table_note(plan)) << "</p>\n";
  if (!budgets.steps.sweeps.empty()) {
    out << step_study_html(report, gnuplot);
  }
  // Every configuration's map, each folded under its label; each solver's last (tightest)
  // configuration open, the others a click away.
  out << "<h2>Error maps over p × damping, per configuration</h2>\n<p>The largest relative "
         "error of any observable at each p and damping (over v0, m, k). Each solver's last "
         "configuration is shown; click a configuration to show or hide its map.</p>\n";
  for (const bool last : {true, false}) {
    bool introduced = last; // the folded ones under a line of their own, before the first
    for (std::size_t c = 0; c < plan.configs.size(); ++c) {
      if (last_of_its_solver(plan, c) != last) {
        continue;
      }
      if (!introduced) {
        out << "<p>The other configurations:</p>\n";
        introduced = true;
      }
      out << "<details class='map'" << (last ? " open" : "") << "><summary>"
          << escape(plan.configs[c].label()) << "</summary>"
          << figure_html(error_map_plot(gnuplot, report, c)) << "</details>\n";
    }
  }
  out << "<h2>The closed forms in double against " << precision_name<Exact>()
      << "</h2>\n<p>The worst relative error of the closed forms computed in double, over the "
         "observables wanted; they cost "
      << short_number(mean_analytic_seconds(plan) * 1e6, 2) << " µs per cell.</p>\n"
      << html_table(map_table(plan, [&](std::size_t point) {
           const Point& at = plan.points[point];
           return short_number(analytic_worst(at)) +
                  (not_representable(plan, at).empty() ? "" : " †");
         }));
  if (const std::string notes = unrepresentable_note(plan); !notes.empty()) {
    out << "<p>† an observable out of double's range (it under- or overflows there; not an error "
           "of the closed form):</p>\n<ul>";
    std::istringstream each(notes);
    for (std::string line; std::getline(each, line);) {
      out << "<li>" << escape(line) << "</li>";
    }
    out << "</ul>\n";
  }
  if (!report.figures.empty()) {
    out << "<h2>The seed's figures: solver (points) against closed form (lines)</h2>\n";
    for (const Figure& figure : report.figures) {
      if (!figure.failure.empty()) {
        out << "<p class='fails'>" << escape(figure.title) << " failed: " << escape(figure.failure)
            << "</p>\n";
        continue;
      }
      out << "<div id='fig-" << escape(figure.kind) << "'>"
          << figure_html(figure_plot(gnuplot, figure), "largest deviation " +
                                                           short_number(figure.deviation) + " in " +
                                                           escape(figure.deviation_of));
      if (!figure.table_header.empty()) {
        out << html_table(MapTable{figure.table_header, figure.table_rows}, "wrap");
      }
      out << "</div>\n";
    }
  }
  out << "<p>Every configuration's maps and each record are in report.json and report.csv.</p>\n"
         "</body></html>\n";
  return out.str();
}

} // namespace

// On more than one thread the page is built once to note its plots, which are then drawn `jobs`
// at a time (a gnuplot process each, 30 ms of start-up: a nightly's 110 plots took 3.6 s one
// after another), and built again with them; building a page without its plots takes
// milliseconds. On one, each plot is drawn where the page asks for it.
std::string report_html(const RunReport& report, const std::string& gnuplot_program, int jobs) {
  Gnuplot gnuplot(gnuplot_program);
  if (gnuplot.available() && jobs > 1) {
    gnuplot.record();
    (void)page(report, gnuplot);
    gnuplot.render(jobs);
  }
  return page(report, gnuplot);
}

} // namespace pldamp::harness
