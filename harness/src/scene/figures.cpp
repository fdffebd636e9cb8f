// [[figure]]: the seed's figures (judge/figures.hpp), each over its own lists.
#include "scene/reader.hpp"

#include "pldamp/core/domain.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <tuple>

namespace pldamp::harness::scene_reading {
namespace {

// The published approximations of viscoelastic Hertz against the truth, which is the reference
// solve (taylor in float128, MATH.md §12.2) over alpha_eff = [from, to].
void read_restitution_figure(const Reader& reader, const toml::table& entry, const toml::node& item,
                             FigureSpec& figure) {
  reader.only(entry, {scene_keys::restitution_figure}, "[[figure]] restitution_approximations");
  const toml::node* ps = entry.get("p");
  const toml::node* range = entry.get("alpha_eff");
  if (ps == nullptr || range == nullptr) {
    reader.fail(item, "[[figure]] restitution_approximations needs p = 1.5 and alpha_eff = "
                      "[from, to]");
  }
  figure.p = reader.numbers(*ps, "p");
  reader.require(figure.p == std::vector<double>{1.5}, *ps,
                 "the published approximations are of viscoelastic Hertz: p must be 1.5",
                 figure.p.front());
  figure.alpha_eff = reader.numbers(*range, "alpha_eff");
  if (figure.alpha_eff.size() != 2 || !(figure.alpha_eff[0] > 0) ||
      !(figure.alpha_eff[0] < figure.alpha_eff[1]) || !(figure.alpha_eff[1] <= 10)) {
    reader.fail(*range, "alpha_eff must be [from, to] with 0 < from < to <= 10");
  }
  figure.config.name = "taylor";
  figure.config.precision = std::string(precision_name<NarrowestWithDigits10<30>>());
}

} // namespace

void read_figures(const Reader& reader, const toml::node& node, Scene& scene) {
  for (const toml::node& item : reader.entries(node, "figure")) {
    const toml::table& entry = reader.table(item, "[[figure]]");
    reader.only(entry, {scene_keys::figure}, "[[figure]]");
    FigureSpec figure;
    if (entry.get("kind") == nullptr) {
      reader.fail(item, "[[figure]] needs a kind");
    }
    const std::string kind = reader.string(*entry.get("kind"), "kind");
    figure.kind = reader.choice_of(*entry.get("kind"), kind, figure_kinds, "figure");
    if (figure.kind == FigureKind::restitution_approximations) {
      read_restitution_figure(reader, entry, item, figure);
      scene.figures.push_back(figure);
      continue;
    }
    figure.config = base_config(reader, entry, "solver", "[[figure]]", item);
    const solvers::SolverInfo& info = solvers::solver_named(figure.config.name);
    refuse_untaken_step_keys(reader, entry, info, "a figure runs it at 50 steps per contact");
    if (info.fixed_step) {
      figure.config.steps_per_contact = 50;
    }
    if (const toml::node* rtol = entry.get("rtol")) {
      figure.config.rtol = reader.number_in(*rtol, "rtol", rtol_range);
    }
    // tau_ratio is drawn against alpha_eff, the others at target e (judge/figures.cpp).
    const bool by_alpha_eff = figure.kind == FigureKind::tau_ratio;
    for (const char* key : {"p", by_alpha_eff ? "alpha_eff" : "e"}) {
      if (entry.get(key) == nullptr) {
        reader.fail(item, "[[figure]] " + kind + " needs " + key);
      }
    }
    if (const toml::node* unused = entry.get(by_alpha_eff ? "e" : "alpha_eff")) {
      reader.fail(*unused, std::string(by_alpha_eff ? "e" : "alpha_eff") +
                               " has no effect on figure " + kind + ": it is drawn " +
                               (by_alpha_eff ? "against alpha_eff" : "at target e"));
    }
    const toml::node& ps = *entry.get("p");
    figure.p = reader.numbers(ps, "p");
    for (const double p : figure.p) {
      reader.within_domain(ps, [&] { domain::require_p(p); });
    }
    if (const toml::node* es = entry.get("e")) {
      figure.e = reader.numbers(*es, "e");
      for (const double e : figure.e) {
        reader.check_in(*es, "e", e, Range::open(0, 1));
      }
    }
    if (const toml::node* zs = entry.get("alpha_eff")) {
      figure.alpha_eff = reader.numbers(*zs, "alpha_eff");
      for (const double z : figure.alpha_eff) {
        reader.check_in(*zs, "alpha_eff", z, Range::closed_open(0, 1).with_unit(" (a return)"));
      }
    }
    for (const char* key : {"p", "e", "alpha_eff"}) { // a point twice
      if (const toml::node* list = entry.get(key)) {
        refuse_repeated(reader, *list, key, reader.numbers(*list, key));
      }
    }
    // Figures drawn at one e (force_history, f_of_p) or one p (phase_portrait).
    const bool one_e =
        figure.kind == FigureKind::force_history || figure.kind == FigureKind::f_of_p;
    const bool one_p = figure.kind == FigureKind::phase_portrait;
    for (const auto& [key, values, one] :
         {std::tuple{"e", &figure.e, one_e}, std::tuple{"p", &figure.p, one_p}}) {
      if (one && values->size() > 1) {
        reader.fail(*entry.get(key), fmt::format("figure {} is drawn at one {} (got {} values)",
                                                 kind, key, values->size()));
      }
    }
    // Its tolerances against the precision and the cells it is drawn at (v0 = m = k = 1).
    Scene cells = with_cells(scene, ClaimGrid{figure.p, {1.0}, {1.0}, {1.0}, {}});
    cells.want = solvers::want_e | solvers::want_delta_max | solvers::want_tau;
    check_config(reader, item, cells, figure.config);
    scene.figures.push_back(figure);
  }
}

} // namespace pldamp::harness::scene_reading
