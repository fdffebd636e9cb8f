#include "judge/figures.hpp"

#include "common/parallel.hpp"
#include "judge/solve.hpp"
#include "truth/reference_solve.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/analytic/viscoelastic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string_view>

namespace pldamp::harness {
namespace {

using analytic::Contact;

// Figures are drawn at v0 = m = k = 1, each solve within the scene's [limits].
solvers::Result<double> solve(const SolverConfig& config, const Limits& limits, double p,
                              double alpha, unsigned want, std::vector<double> sample_times = {}) {
  return solve_once(config, {p, alpha}, want, limits, std::move(sample_times));
}

double measured(const SolverConfig& config, const Limits& limits, double p, double alpha,
                unsigned want, std::optional<double> solvers::Result<double>::*value,
                const char* name) {
  return solved_value(config, {p, alpha}, want, value, name, limits);
}

double alpha_by_bisection(const SolverConfig& config, const Limits& limits, double p, double e) {
  return harness::alpha_by_bisection(config, {p, 0}, e, limits);
}

std::string p_title(double p) {
  return "p = " + to_string_full(p);
}

// Total normal force k δ^p + α √(mk) δ^((p−1)/2) v with m = k = 1.
double force(double p, double alpha, double delta, double v) {
  const double d = std::max(delta, 0.0);
  return std::pow(d, p) + alpha * std::pow(d, (p - 1) / 2) * v;
}

std::vector<double> fine(double from, double to, int n) {
  std::vector<double> x;
  for (int i = 0; i <= n; ++i) {
    x.push_back(from + (to - from) * i / n);
  }
  return x;
}

Figure figure(FigureKind kind, std::string title, std::string x, std::string y,
              std::string deviation_of) {
  return {std::string(name_of(figure_kinds, kind)),
          std::move(title),
          std::move(x),
          std::move(y),
          {},
          0,
          std::move(deviation_of),
          {},
          false,
          false,
          {},
          {}};
}

// Per p: the closed form along `curve` as a line, the solver at `at` as points, and the largest
// relative deviation between them.
void curve_and_points(Figure& f, const FigureSpec& spec, const std::vector<double>& curve,
                      const std::vector<double>& at,
                      const std::function<double(double p, double x)>& closed,
                      const std::function<double(double p, double x)>& numeric) {
  for (const double p : spec.p) {
    Series line{p_title(p) + " closed form", {}, true}, points{p_title(p), {}, false};
    for (const double x : curve) {
      line.points.emplace_back(x, closed(p, x));
    }
    for (const double x : at) {
      const double value = numeric(p, x);
      points.points.emplace_back(x, value);
      f.deviation = std::max(f.deviation, std::abs(value / closed(p, x) - 1));
    }
    f.series.push_back(line);
    f.series.push_back(points);
  }
}

// The solver's (t, δ, v) at n + 1 times across the contact and the closed form's at the same
// times, as pairs.
struct Sampled {
  solvers::Sample<double> solver, exact;
};
std::vector<Sampled> sample_contact(const FigureSpec& spec, const Limits& limits,
                                    const Contact<double>& c, int n) {
  const double tau = analytic::contact_duration(c);
  std::vector<double> times;
  for (const double x : fine(0, 1, n)) {
    times.push_back(x * tau);
  }
  const solvers::Result<double> r =
      solve(spec.config, limits, c.p(), c.alpha(), solvers::want_tau, times);
  const analytic::Trajectory<double> trajectory(c);
  std::vector<Sampled> out;
  for (const solvers::Sample<double>& s : r.samples) {
    const auto want = trajectory.at_time(s.t);
    out.push_back({s, {s.t, want.delta, want.v}});
  }
  return out;
}

Figure alpha_vs_e(const FigureSpec& spec, const Limits& limits) {
  Figure f = figure(FigureKind::alpha_vs_e, "Fig. 1: α against e", "e", "α", "α (relative)");
  curve_and_points(
      f, spec, fine(0.05, 0.995, 60), spec.e,
      [](double p, double e) { return Contact<double>::from_e(p, e, 1.0).alpha(); },
      [&](double p, double e) { return alpha_by_bisection(spec.config, limits, p, e); });
  return f;
}

Figure force_history(const FigureSpec& spec, const Limits& limits) {
  const double e = spec.e.front();
  Figure f =
      figure(FigureKind::force_history, "Fig. 2: force against time, e = " + to_string_full(e),
             "t / τ", "F / k δ_max^p", "F / k δ_max^p");
  for (const double p : spec.p) {
    const auto c = Contact<double>::from_e(p, e, 1.0);
    const double tau = analytic::contact_duration(c), peak = analytic::spring_force_max(c);
    Series line{p_title(p) + " closed form", {}, true}, points{p_title(p), {}, false};
    for (const auto& [s, want] : sample_contact(spec, limits, c, 80)) {
      const double numeric = force(p, c.alpha(), s.delta, s.v) / peak;
      const double closed = force(p, c.alpha(), want.delta, want.v) / peak;
      line.points.emplace_back(s.t / tau, closed);
      points.points.emplace_back(s.t / tau, numeric);
      f.deviation = std::max(f.deviation, std::abs(numeric - closed));
    }
    f.series.push_back(line);
    f.series.push_back(points);
  }
  return f;
}

Figure delta_max_vs_e(const FigureSpec& spec, const Limits& limits) {
  Figure f = figure(FigureKind::delta_max_vs_e, "Fig. 3: δ_max against e (v0 = 1)", "e", "δ_max",
                    "δ_max (relative)");
  curve_and_points(
      f, spec, fine(0.02, 1.0, 60), spec.e,
      [](double p, double e) { return analytic::delta_max(Contact<double>::from_e(p, e, 1.0)); },
      [&](double p, double e) {
        const double alpha = Contact<double>::from_e(p, e, 1.0).alpha();
        return measured(spec.config, limits, p, alpha, solvers::want_delta_max,
                        &solvers::Result<double>::delta_max, "delta_max");
      });
  return f;
}

Figure tau_ratio(const FigureSpec& spec, const Limits& limits) {
  Figure f = figure(FigureKind::tau_ratio, "Fig. 4: τ(α)/τ(0) against α_eff", "α_eff",
                    "τ(α) / τ(0)", "τ ratio (relative)");
  f.log_y = true;
  // The curves run as far as the solver's points (the ratio grows without bound as α_eff → 1).
  const double z_max = spec.alpha_eff.empty()
                           ? 0.9
                           : *std::max_element(spec.alpha_eff.begin(), spec.alpha_eff.end());
  Series linear{"1/√(1 − α_eff²) (the seed's curve, exact for p = 1)", {}, true};
  for (const double z : fine(0, z_max, 60)) {
    linear.points.emplace_back(z, 1 / std::sqrt(1 - z * z));
  }
  f.series.push_back(linear);
  auto closed = [](double p, double z) {
    const auto c = Contact<double>::from_alpha_eff(p, z, 1.0);
    return *analytic::observables(c, analytic::want_tau).tau_ratio;
  };
  curve_and_points(f, spec, fine(0, z_max, 40), spec.alpha_eff, closed, [&](double p, double z) {
    const double alpha = Contact<double>::from_alpha_eff(p, z, 1.0).alpha();
    const auto tau = &solvers::Result<double>::tau;
    return measured(spec.config, limits, p, alpha, solvers::want_tau, tau, "tau") /
           measured(spec.config, limits, p, 0.0, solvers::want_tau, tau, "tau");
  });
  // Each p's first order, measured on the closed form as (τ/τ0 − 1)/α_eff at α_eff = 1e-6 (the
  // z² term moves it by 1e-6 of itself), drawn after its pair so that it takes its colour.
  // Each p's line and points, then its first order: 1 + s·α_eff with s = (τ/τ0 − 1)/α_eff measured
  // on the closed form at α_eff = 1e-6 (the z² term moves it by 1e-6 of itself), drawn up to the
  // largest α_eff where it stays within the plot.
  std::vector<Series> series{f.series.front()};
  for (std::size_t i = 0; i < spec.p.size(); ++i) {
    series.push_back(f.series[1 + 2 * i]);
    series.push_back(f.series[2 + 2 * i]);
    const double p = spec.p[i], small = 1e-6;
    const double slope = (closed(p, small) - 1) / small;
    if (slope < 1e-3) {
      continue; // p = 1: no first order, the seed's curve is exact
    }
    Series first{fmt::format("p = {}: 1 + {:.3f} α_eff (first order)", to_string_full(p), slope),
                 {},
                 false,
                 true};
    for (const double z : fine(0, std::min(z_max, 0.6), 20)) {
      first.points.emplace_back(z, 1 + slope * z);
    }
    series.push_back(first);
  }
  f.series = series;
  return f;
}

Figure phase_portrait(const FigureSpec& spec, const Limits& limits) {
  const double p = spec.p.front();
  Figure f = figure(FigureKind::phase_portrait, "Fig. 5: phase portrait, " + p_title(p),
                    "δ / δ_max(e = 1)", "v / v0", "v / v0");
  const double undamped = analytic::delta_max(Contact<double>::from_e(p, 1.0, 1.0));
  for (const double e : spec.e) {
    const auto c = Contact<double>::from_e(p, e, 1.0);
    const std::string title = "e = " + to_string_full(e);
    Series line{title + " closed form", {}, true}, points{title, {}, false};
    for (const auto& [s, want] : sample_contact(spec, limits, c, 120)) {
      line.points.emplace_back(want.delta / undamped, want.v);
      points.points.emplace_back(s.delta / undamped, s.v);
      f.deviation = std::max(f.deviation, std::abs(s.v - want.v));
    }
    f.series.push_back(line);
    f.series.push_back(points);
  }
  return f;
}

Figure f_of_p(const FigureSpec& spec, const Limits& limits) {
  const double e = spec.e.front();
  const double xi = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
  Figure f = figure(FigureKind::f_of_p, "Fig. 6: f(p) = α/ξ_L at e = " + to_string_full(e), "p",
                    "f(p)", "f (relative)");
  Series line{"√(2(p+1))", {}, true}, points{"bisection on the solver", {}, false};
  const double p_max = *std::max_element(spec.p.begin(), spec.p.end());
  for (const double p : fine(1, p_max, 60)) {
    line.points.emplace_back(p, std::sqrt(2 * (p + 1)));
  }
  for (const double p : spec.p) {
    const double found = alpha_by_bisection(spec.config, limits, p, e) / xi;
    points.points.emplace_back(p, found);
    f.deviation = std::max(f.deviation, std::abs(found / std::sqrt(2 * (p + 1)) - 1));
  }
  f.series.push_back(line);
  f.series.push_back(points);
  return f;
}

// The longest run of consecutive x whose `holds` is true, as "from – to", or "nowhere".
std::string longest_run(const std::vector<double>& x, const std::vector<bool>& holds) {
  std::size_t best_from = 0, best_length = 0;
  for (std::size_t i = 0; i < x.size();) {
    if (!holds[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < x.size() && holds[j]) {
      ++j;
    }
    if (j - i > best_length) {
      best_from = i;
      best_length = j - i;
    }
    i = j;
  }
  if (best_length == 0) {
    return "nowhere";
  }
  return fmt::format("{:.3g} – {:.3g}", x[best_from], x[best_from + best_length - 1]);
}

// Viscoelastic Hertz: 1 − e of the reference solve and of each published approximation
// (MATH.md §12.5) at 65 α_eff spaced evenly in log over the spec's range; the table gives each
// approximation's largest relative error in e and where it stays within 1 % and 0.1 %. Each is
// measured against the truth of the contact end its authors defined e at (the 1999 series: δ = 0;
// the 2011 Padé: F = 0), and only the ends some approximation uses are solved.
Figure restitution_approximations(const FigureSpec& spec) {
  const double from = spec.alpha_eff[0], to = spec.alpha_eff[1];
  const double p = 1.5, beta = 0.5;
  Figure f = figure(FigureKind::restitution_approximations,
                    "Viscoelastic Hertz (p = 3/2, β = 1/2): 1 − e against α_eff ∝ v0^(1/5)",
                    "α_eff", "1 − e", "e (relative), the best approximation over the range");
  f.log_x = f.log_y = true;
  constexpr int intervals = 64;
  std::vector<double> groups;
  for (int i = 0; i <= intervals; ++i) {
    groups.push_back(from * std::pow(to / from, double(i) / intervals));
  }
  struct Truth {
    solvers::End end;
    std::string_view label;
    std::vector<Exact> e{};
  };
  std::array<Truth, 2> truths{{{solvers::End::overlap, "δ = 0"}, {solvers::End::force, "F = 0"}}};
  auto truth_at = [&truths](analytic::ContactEnd end) -> Truth& {
    return truths[end == analytic::ContactEnd::force ? 1 : 0];
  };
  for (const analytic::Approximation& approximation : analytic::published_approximations) {
    Truth& truth = truth_at(approximation.end);
    if (!truth.e.empty()) {
      continue;
    }
    Series reference{
        fmt::format("reference solve, the contact ending at {}", truth.label), {}, false};
    for (const double group : groups) {
      const solvers::Result<Exact>& r = reference_solve(p, beta, Exact(group), truth.end);
      if (solvers::failing(r.outcome) || !r.e || *r.e == 0) { // r.e: e where the contact ends
        throw std::runtime_error(fmt::format("the reference solve at alpha_eff = {} ended {}",
                                             group, solvers::outcome_name(r.outcome)));
      }
      truth.e.push_back(*r.e);
      reference.points.emplace_back(group, static_cast<double>(1 - *r.e));
    }
    f.series.push_back(reference);
  }
  f.table_header = {
      "approximation",           "truth: the contact ends at", "largest relative error in e",
      "within 1 % for α_eff in", "within 0.1 % for α_eff in",  "source"};
  f.deviation = std::numeric_limits<double>::infinity();
  for (const analytic::Approximation& approximation : analytic::published_approximations) {
    const Truth& truth = truth_at(approximation.end);
    Series line{std::string(approximation.name), {}, true};
    double largest = 0;
    std::vector<bool> percent, permille;
    for (std::size_t i = 0; i < groups.size(); ++i) {
      const double e = approximation.e(groups[i]);
      const double error = std::isfinite(e)
                               ? static_cast<double>(abs(Exact(e) - truth.e[i]) / truth.e[i])
                               : std::numeric_limits<double>::infinity();
      largest = std::max(largest, error);
      percent.push_back(error <= 1e-2);
      permille.push_back(error <= 1e-3);
      if (std::isfinite(e) && e < 1) { // 1 − e ≤ 0 has no place on the log axis
        line.points.emplace_back(groups[i], 1 - e);
      }
    }
    f.deviation = std::min(f.deviation, largest);
    f.series.push_back(line);
    f.table_rows.push_back({std::string(approximation.name), std::string(truth.label),
                            fmt::format("{:.2g}", largest), longest_run(groups, percent),
                            longest_run(groups, permille), std::string(approximation.source)});
  }
  if (f.table_rows.empty()) {
    f.deviation = 0;
  }
  return f;
}

Figure make_figure(const FigureSpec& spec, const Limits& limits) {
  switch (spec.kind) {
  case FigureKind::alpha_vs_e:
    return alpha_vs_e(spec, limits);
  case FigureKind::force_history:
    return force_history(spec, limits);
  case FigureKind::delta_max_vs_e:
    return delta_max_vs_e(spec, limits);
  case FigureKind::tau_ratio:
    return tau_ratio(spec, limits);
  case FigureKind::phase_portrait:
    return phase_portrait(spec, limits);
  case FigureKind::restitution_approximations:
    return restitution_approximations(spec);
  case FigureKind::f_of_p:
    break;
  }
  return f_of_p(spec, limits);
}

} // namespace

std::vector<Figure> make_figures(const Scene& scene, int jobs) {
  // The figures on the threads, each in its slot (common/parallel.hpp).
  return map_indices<Figure>(scene.figures.size(), jobs, [&](std::size_t i) {
    const FigureSpec& spec = scene.figures[i];
    Figure figure;
    try {
      figure = make_figure(spec, scene.limits);
    } catch (const std::exception& e) {
      const std::string kind(name_of(figure_kinds, spec.kind));
      figure = Figure{kind, kind, "", "", {}, 0, "", e.what(), false, false, {}, {}};
    }
    figure.title += " (" + spec.config.label() + ")";
    return figure;
  });
}

} // namespace pldamp::harness
