// The seed's Figures 1–6 (a scene's [[figure]] entries, paper.toml): each one a solver's points
// over the closed form's curve, with the largest deviation between them.
//
//   alpha_vs_e      Fig. 1: α found by bisection on the solver for target e, per p
//   force_history   Fig. 2: F/F_max against t/τ at one e, per p
//   delta_max_vs_e  Fig. 3: δ_max against e at v0 = 1, per p
//   tau_ratio       Fig. 4: τ(α)/τ(0) against α_eff, per p, with 1/√(1 − α_eff²) and each p's
//                   first order 1 + s·α_eff, s measured on the closed form (MATH.md §3)
//   phase_portrait  Fig. 5: v/v0 against δ/δ_max(e) at one p, per e
//   f_of_p          Fig. 6: α/ξ_L by bisection at one e against √(2(p+1))
//   restitution_approximations
//                   not the seed's: 1 − e of viscoelastic Hertz (p = 3/2, β = ½) against α_eff,
//                   the reference solve (MATH.md §12.2) and the published approximations
//                   (§12.5), with a table of each one's largest error and the range of α_eff
//                   in which it stays within 1 % and 0.1 %
#pragma once

#include "scene/scene.hpp"

#include <string>
#include <utility>
#include <vector>

namespace pldamp::harness {

struct Series {
  std::string title;
  std::vector<std::pair<double, double>> points;
  bool closed_form = false; // drawn as a line; the solver's as points
  // A thin dashed line in the colour of the p before it: Fig. 4's measured first order.
  bool first_order = false;
};

struct Figure {
  std::string kind, title, x_label, y_label;
  std::vector<Series> series;
  double deviation = 0; // the largest |solver − closed form| in the figure's units
  std::string deviation_of;
  std::string failure; // not empty: the figure could not be drawn, and why
  bool log_y = false;  // Fig. 4: ratios from 1 to ~15, its first orders visible near 1
  bool log_x = false;  // restitution_approximations: α_eff over decades
  // A table shown under the figure (restitution_approximations: each approximation's errors).
  std::vector<std::string> table_header;
  std::vector<std::vector<std::string>> table_rows;
};

// Computes every figure of the scene (double precision, the figure's solver configuration, each
// solve within the scene's [limits]). A figure whose solver fails (a step limit, no exit where
// one was due, a bisection without a bracket) carries the reason in `failure` and no series; the
// others are unaffected. The figures are computed on `jobs` threads, each the same on any number.
std::vector<Figure> make_figures(const Scene& scene, int jobs = 1);

} // namespace pldamp::harness
