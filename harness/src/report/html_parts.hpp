// What report.html's pieces share (html.cpp, work_precision.cpp): escaping, gnuplot started per
// plot, each solver line's style, tables and figures.
#pragma once

#include "common/process.hpp"
#include "report/sections.hpp"

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness::html {

// Text for HTML: <, >, & and ' escaped.
std::string escape(std::string_view text);
// A gnuplot single-quoted string: nothing inside is interpreted but '' for a quote.
std::string gnuplot_string(std::string_view text);

// gnuplot, started per plot; the SVG it writes on stdout, or "". A page is built twice so that
// its plots are drawn side by side (report_html): once noting them (record(), svg returns ""),
// then after render(jobs) has drawn them all, `jobs` gnuplot processes at a time, from those.
class Gnuplot {
public:
  explicit Gnuplot(std::string program);
  bool available() const { return available_; }
  std::string svg(const std::string& script, int width, int height) const;
  void record() { recording_ = true; }
  void render(int jobs);

private:
  std::string draw(const std::string& full_script) const;
  std::string program_;
  bool available_ = false;
  bool recording_ = false;
  mutable std::vector<std::string> noted_;   // the scripts asked for while recording
  std::map<std::string, std::string> drawn_; // script → SVG, render's
};

struct Style {
  std::string colour;
  int marker, dash;
};
// The style of a scene's line-th solver line (html.cpp says how they are chosen).
Style style_of(std::size_t line);

// A solver's lines: configurations differing only in their sweep value (SolverConfig::line), in
// sweep order, with the style of their first appearance in the scene.
struct Line {
  std::string name;
  bool extended; // a precision wider than double
  Style style;
  std::vector<std::size_t> configs;
};
std::vector<Line> solver_lines(const Plan& plan);

// A plot's height with its legend below it, two entries a row: the plot keeps 400 pixels.
int key_height(int entries);

// `css_class`: "wrap" for a table of text that wraps within the page (External solvers).
std::string html_table(const MapTable& table, const std::string& css_class = "");
// A <figure> holding an SVG, or nothing when gnuplot drew none.
std::string figure_html(const std::string& svg, const std::string& caption = "");

// The work-precision section (work_precision.cpp): a part per series the scene chose
// (work_panels) with its plots per p, in double and, with `any_extended`, in extended
// precision; then report.md's table, folded.
std::string work_precision_html(const RunReport& report, const Gnuplot& gnuplot, bool any_extended);

} // namespace pldamp::harness::html
