// report.html: one self-contained page. Plots are SVG drawn by gnuplot (its svg terminal) from
// data written inline into its script, and pasted into the page; gnuplot missing or failing
// leaves the tables and a note instead of the plots.
#include "report/report.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <unistd.h>

namespace pldamp::harness {
namespace {

std::string escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
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
    default:
      out += c;
    }
  }
  return out;
}

// Runs gnuplot on `script` (which must not set the output) and returns the SVG, or "".
class Gnuplot {
public:
  explicit Gnuplot(std::string program) : program_(std::move(program)) {
    available_ =
        !program_.empty() && std::system((program_ + " --version >/dev/null 2>&1").c_str()) == 0;
  }
  bool available() const { return available_; }

  std::string svg(const std::string& script, int width = 640, int height = 420) {
    if (!available_) {
      return "";
    }
    namespace fs = std::filesystem;
    const fs::path base = fs::temp_directory_path() / ("pldamp-plot-" + std::to_string(::getpid()) +
                                                       "-" + std::to_string(++n_));
    const fs::path script_path = base.string() + ".gp", svg_path = base.string() + ".svg";
    {
      std::ofstream out(script_path);
      out << "set terminal svg size " << width << "," << height
          << " dynamic enhanced font 'sans,11' background rgb 'white'\n"
          << "set output '" << svg_path.string() << "'\n"
          << script << "\nunset output\n";
    }
    const bool ok =
        std::system((program_ + " '" + script_path.string() + "' >/dev/null 2>&1").c_str()) == 0;
    std::string svg;
    if (ok) {
      std::ifstream in(svg_path);
      std::stringstream buffer;
      buffer << in.rdbuf();
      svg = buffer.str();
      const auto start = svg.find("<svg");
      svg = start == std::string::npos ? "" : svg.substr(start); // drop the XML prologue
    }
    std::error_code ignored;
    fs::remove(script_path, ignored);
    fs::remove(svg_path, ignored);
    return svg;
  }

private:
  std::string program_;
  bool available_ = false;
  int n_ = 0;
};

// A solver's lines: configurations sharing a name and precision, in sweep order.
std::map<std::string, std::vector<std::size_t>> solver_lines(const Plan& plan) {
  std::map<std::string, std::vector<std::size_t>> lines;
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    const SolverConfig& config = plan.configs[c];
    lines[config.name + (config.precision == "double" ? "" : " " + config.precision)].push_back(c);
  }
  return lines;
}

// Error against time (or rhs evaluations) at one p, one line per solver.
std::string work_precision_plot(Gnuplot& gnuplot, const RunReport& report, std::size_t p_index,
                                bool against_time) {
  std::ostringstream script;
  script << std::setprecision(17);
  script << "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\nset grid\n"
         << "set key outside right\nset xlabel '"
         << (against_time ? "wall time per collision [s]" : "rhs evaluations per collision")
         << "'\nset ylabel 'largest relative error'\nset title 'p = "
         << report.plan.scene.p[p_index] << "'\n";
  std::string plot = "plot ";
  int block = 0;
  for (const auto& [name, configs] : solver_lines(report.plan)) {
    std::ostringstream data;
    data << std::setprecision(17);
    int points = 0;
    for (const std::size_t c : configs) {
      const WorkPoint& w = report.budgets.work[c][p_index];
      if (w.error && *w.error > 0 && std::isfinite(*w.error) && w.seconds > 0) {
        data << (against_time ? w.seconds : w.rhs_evals) << " " << *w.error << "\n";
        ++points;
      }
    }
    if (points == 0) {
      continue;
    }
    script << "$d" << block << " << EOD\n" << data.str() << "EOD\n";
    plot += std::string(block ? ", " : "") + "$d" + std::to_string(block) +
            " with linespoints lw 2 pt 7 ps 0.8 title '" + name + "'";
    ++block;
  }
  if (block == 0) {
    return "";
  }
  script << plot << "\n";
  return gnuplot.svg(script.str());
}

// log10 of the largest relative error over p × α_eff for one configuration.
std::string error_map_plot(Gnuplot& gnuplot, const RunReport& report, std::size_t config) {
  const Plan& plan = report.plan;
  const std::size_t dampings = plan.scene.damping.size();
  std::ostringstream script, data;
  script << "set xlabel 'damping'\nset ylabel 'p'\nset cblabel 'log_{10} relative error'\n"
         << "set title '" << plan.configs[config].label()
         << "'\nset palette rgbformulae 22,13,-31\nset xrange [-0.5:" << dampings - 0.5
         << "]\nset yrange [-0.5:" << plan.scene.p.size() - 0.5 << "]\n";
  script << "set xtics rotate by 45 right (";
  for (std::size_t d = 0; d < dampings; ++d) {
    script << (d ? ", " : "") << "'" << plan.points[d].damping.label() << "' " << d;
  }
  script << ")\nset ytics (";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    script << (i ? ", " : "") << "'" << plan.scene.p[i] << "' " << i;
  }
  script << ")\n$map << EOD\n";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    for (std::size_t d = 0; d < dampings; ++d) {
      const std::optional<double> worst = worst_at(report.budgets, config, i * dampings + d);
      data << d << " " << i << " "
           << (worst && *worst > 0 && std::isfinite(*worst) ? std::log10(*worst) : NAN) << "\n";
    }
    data << "\n";
  }
  // One solid box per cell (vector output, no interpolation), its exponent printed on it.
  script << data.str()
         << "EOD\nplot $map using 1:2:(0.5):(0.5):3 with boxxyerror fs solid fc palette "
            "notitle, $map using 1:2:(sprintf('%.1f', $3)) with labels notitle\n";
  return gnuplot.svg(script.str(), 560, 380);
}

// A seed figure: closed-form lines and the solver's points.
std::string figure_plot(Gnuplot& gnuplot, const Figure& figure) {
  std::ostringstream script;
  script << std::setprecision(17) << "set grid\nset key outside right\nset title '" << figure.title
         << "' noenhanced\nset xlabel '" << figure.x_label << "' noenhanced\nset ylabel '"
         << figure.y_label << "' noenhanced\n";
  // A closed form and the solver's points after it share a colour.
  std::string plot = "plot ";
  int colour = 0;
  for (std::size_t i = 0; i < figure.series.size(); ++i) {
    const Series& series = figure.series[i];
    colour += series.closed_form || colour == 0 ? 1 : 0;
    script << "$s" << i << " << EOD\n";
    for (const auto& [x, y] : series.points) {
      script << x << " " << y << "\n";
    }
    script << "EOD\n";
    plot += std::string(i ? ", " : "") + "$s" + std::to_string(i) +
            (series.closed_form ? " with lines lw 2" : " with points pt 6 ps 0.9") + " lc " +
            std::to_string(colour) + " title '" + series.title + "' noenhanced";
  }
  script << plot << "\n";
  return gnuplot.svg(script.str(), 720, 440);
}

} // namespace

std::string report_html(const RunReport& report, const std::string& gnuplot_program) {
  const Plan& plan = report.plan;
  const Budgets& budgets = report.budgets;
  Gnuplot gnuplot(gnuplot_program);
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>pldamp: "
      << escape(plan.scene.name)
      << "</title>\n<style>body{font-family:sans-serif;margin:2em;max-width:80em}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:2px "
         "6px;text-align:right}th{background:#eee}.holds{color:#070}.fails{color:#b00;font-weight:"
         "bold}figure{display:inline-block;margin:0.5em}</style></head><body>\n";
  out << "<h1>pldamp report: " << escape(plan.scene.name) << "</h1>\n<p>Scene <code>"
      << escape(plan.scene.path) << "</code>: " << plan.cells.size() << " cells × "
      << plan.configs.size() << " solver configurations, " << report.totals.solver_runs
      << " solver runs, " << report.totals.rhs_evals << " rhs evaluations, "
      << short_number(report.totals.wall_seconds, 3) << " s; " << budgets.failed_records
      << " failed records.</p>\n";
  if (!gnuplot.available()) {
    out << "<p><strong>gnuplot was not found: the plots were skipped.</strong></p>\n";
  }
  out << "<h2>Claims</h2>\n<table><tr><th>claim</th><th>observable</th><th>solver</th><th>bound</"
         "th><th>measured</th><th>verdict</th><th>margin</th><th>supported</th></tr>\n";
  for (const Verdict& v : budgets.claims) {
    out << "<tr><td>" << escape(v.name) << "</td><td>" << v.observable << "</td><td>"
        << escape(v.config) << "</td><td>" << short_number(v.bound) << "</td><td>"
        << short_number(v.measured) << "</td><td class='"
        << (v.holds ? "holds'>holds" : "fails'>fails") << "</td><td>" << short_number(v.margin)
        << "</td><td>" << short_number(v.supported, 0) << "</td></tr>\n";
  }
  out << "</table>\n<h2>Work-precision</h2>\n";
  for (std::size_t i = 0; i < plan.scene.p.size(); ++i) {
    for (const bool against_time : {true, false}) {
      const std::string svg = work_precision_plot(gnuplot, report, i, against_time);
      if (!svg.empty()) {
        out << "<figure>" << svg << "</figure>\n";
      }
    }
  }
  out << "<h2>Worst relative error over the grid</h2>\n<table><tr><th>configuration</th>";
  for (const Observable* observable : plan.observables) {
    out << "<th>" << observable->key << "</th>";
  }
  out << "</tr>\n";
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    out << "<tr><td>" << escape(plan.configs[c].label()) << "</td>";
    for (std::size_t o = 0; o < plan.observables.size(); ++o) {
      out << "<td>" << short_number(budgets.worst[c][o].rel) << "</td>";
    }
    out << "</tr>\n";
  }
  out << "</table>\n<h2>Error maps over p × damping (each solver's last configuration)</h2>\n";
  for (std::size_t c = 0; c < plan.configs.size(); ++c) {
    if (last_of_its_solver(plan, c)) {
      const std::string svg = error_map_plot(gnuplot, report, c);
      if (!svg.empty()) {
        out << "<figure>" << svg << "</figure>\n";
      }
    }
  }
  if (!report.figures.empty()) {
    out << "<h2>The seed's figures: solver (points) against closed form (lines)</h2>\n";
    for (const Figure& figure : report.figures) {
      if (!figure.failure.empty()) {
        out << "<p class='fails'>" << escape(figure.title) << " failed: " << escape(figure.failure)
            << "</p>\n";
        continue;
      }
      out << "<figure>" << figure_plot(gnuplot, figure) << "<figcaption>largest deviation "
          << short_number(figure.deviation) << " in " << escape(figure.deviation_of)
          << "</figcaption></figure>\n";
    }
  }
  out << "<p>Every configuration's maps, the analytic layer's own budget and each record are in "
         "report.json and report.csv.</p>\n</body></html>\n";
  return out.str();
}

} // namespace pldamp::harness
