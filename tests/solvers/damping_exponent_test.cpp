// Any damping exponent β (MATH.md §12): m δ'' + α√(mk) δ^β δ' + k δ^p = 0.
//
// - The general path (a stated β, taylor's two-variable contact series) given the seed's
//   β = (p−1)/2 reproduces the closed forms: float128 within 1e-30 of cpp_bin_float_50's closed
//   forms over p, e and v0, both ends. This is the strongest check that the path which has no
//   closed form to compare with is right.
// - The two-variable series on exact identities: its energy balance and its inverse (locate).
// - Where no closed form exists: float128 against cpp_bin_float_50, both by taylor; the scaling
//   law of MATH.md §12.1 (e depends on p, β and α_eff alone); and every double solver against
//   the float128 reference at its own tolerance.
#include "taylor_degrees.hpp"
#include "two_power_series.hpp"

#include "every_solver.hpp"
#include "support.hpp"

#include "pldamp/analytic.hpp"
#include "pldamp/analytic/viscoelastic.hpp"
#include "pldamp/solvers/registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace pldamp::solvers {
namespace {

using analytic::Contact;
using pldamp::testing::relative_error;

template <SupportedReal Real>
Options<Real> at_epsilon(End end = End::overlap) {
  Options<Real> options;
  options.rtol = std::numeric_limits<Real>::epsilon();
  options.end = end;
  return options;
}

using pldamp::testing::Worst;

#if PLDAMP_WITH_QUAD
TEST(GeneralPath, StatedSeedExponentReproducesTheClosedFormsInQuad) {
  // Measured worst: see RecordProperty (the budget is 1e-30).
  Worst worst;
  for (const double p : {1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 5.0}) {
    for (const double e : {0.9, 0.5, 0.1, 1e-3}) {
      for (const double v0 : {1e-3, 1.0, 1e3}) {
        const auto exact = Contact<bin50>::from_e(bin50(p), bin50(e), bin50(v0));
        Problem<quad> problem{quad(p), quad(1), quad(1), quad(v0), quad(exact.alpha())};
        problem.damping_exponent = (quad(p) - 1) / 2;
        // The closed forms of the very α the solver was given, one precision up.
        const auto same = Contact<bin50>::from_alpha(bin50(p), bin50(problem.alpha), bin50(v0));
        const auto x = analytic::observables(same);
        std::ostringstream label;
        label << "p=" << p << " e=" << e << " v0=" << v0;
        const Result<quad> r = solve("taylor", problem, at_epsilon<quad>());
        ASSERT_EQ(r.outcome, Outcome::exited) << label.str();
        worst.check_observables(r, x, label.str());
        if (e >= 0.1) { // the capped end exists for every e; three suffice
          const Result<quad> capped = solve("taylor", problem, at_epsilon<quad>(End::force));
          ASSERT_EQ(capped.outcome, Outcome::exited) << label.str();
          const auto xc = analytic::observables(same, analytic::want_all);
          worst.check(capped.e, xc.e_cap, "e_cap", label.str());
          worst.check(capped.tau, xc.t_cut, "t_cut", label.str());
        }
      }
    }
  }
  EXPECT_LT(worst.error, 1e-30) << worst.where;
  RecordProperty("worst_relative_error", pldamp::testing::scientific(worst.error));
}

// The viscoelastic contact and two others without a closed form, at several dampings.
struct Beyond {
  double p, beta, alpha;
};
constexpr Beyond beyond_the_seed[] = {
    {1.5, 0.5, 0.05},
    {1.5, 0.5, 0.5},
    {1.5, 0.5, 2.0}, // viscoelastic spheres (LAMMPS
                     // gran/hertz/history)
    {1.5, 0.0, 0.3},
    {1.0, 0.5, 0.4},
    {2.5, 0.3, 1.0}, // Hertz with a δ⁰ dashpot, Hooke with δ^½
};

// And β = 1 at α = 0.1: there the force end's cut lies close to the exit, where δ^(p−β) = δ^½
// has its branch point; sized by δ's series alone, the step that held the cut left t_cut 2.2e-31
// off in float128 (taylor.cpp, log_radius_of).
TEST(BeyondTheSeed, QuadAgreesWithFiftyDigitsOnEveryObservable) {
  Worst worst;
  std::vector<Beyond> contacts(std::begin(beyond_the_seed), std::end(beyond_the_seed));
  contacts.push_back({1.5, 1.0, 0.1});
  for (const Beyond& b : contacts) {
    for (const End end : {End::overlap, End::force}) {
      const Problem<quad> problem{quad(b.p), 1, 1, 1, quad(b.alpha), quad(b.beta)};
      const Problem<bin50> wide{bin50(b.p), 1, 1, 1, bin50(b.alpha), bin50(b.beta)};
      const Result<quad> r = solve("taylor", problem, at_epsilon<quad>(end));
      const Result<bin50> x = solve("taylor", wide, at_epsilon<bin50>(end));
      std::ostringstream label;
      label << "p=" << b.p << " beta=" << b.beta << " alpha=" << b.alpha
            << (end == End::force ? " force" : " overlap");
      ASSERT_EQ(r.outcome, Outcome::exited) << label.str();
      ASSERT_EQ(x.outcome, Outcome::exited) << label.str();
      worst.check_observables(r, x, label.str());
    }
  }
  EXPECT_LT(worst.error, 1e-32) << worst.where;
  RecordProperty("worst_relative_error", pldamp::testing::scientific(worst.error));
}

// MATH.md §12.1: in the units δ_u, δ_u/v0, ½mv0² the contact depends on p, β and
// α_eff = α δ_u^(β−(p−1)/2)/√(2(p+1)) alone. Two contacts with different m, k, v0 and α but the
// same α_eff have the same e, δ_max/δ_u, t_peak v0/δ_u, τ v0/δ_u and energy split.
TEST(BeyondTheSeed, ObservablesDependOnTheGroupAlone) {
  const quad p = quad(3) / 2, beta = quad(1) / 2;
  auto delta_u = [&](const quad& m, const quad& k, const quad& v0) {
    return pow((p + 1) * m * v0 * v0 / (2 * k), 1 / (p + 1));
  };
  const quad group = quad(3) / 10; // α_eff
  auto alpha_for = [&](const quad& m, const quad& k, const quad& v0) {
    return group * sqrt(2 * (p + 1)) / pow(delta_u(m, k, v0), beta - (p - 1) / 2);
  };
  struct Units {
    quad m, k, v0;
  };
  const Units units[] = {{1, 1, 1},
                         {quad(12) / 1000000, quad(7) * 1000000000, quad(1) / 2},
                         {quad(3), quad(1) / 100, quad(40)}};
  std::optional<Result<quad>> first;
  quad first_scale = 0, first_time = 0;
  for (const Units& u : units) {
    const Problem<quad> problem{p, u.m, u.k, u.v0, alpha_for(u.m, u.k, u.v0), beta};
    const Result<quad> r = solve("taylor", problem, at_epsilon<quad>());
    ASSERT_EQ(r.outcome, Outcome::exited);
    const quad scale = delta_u(u.m, u.k, u.v0), time = scale / u.v0, energy = u.m * u.v0 * u.v0 / 2;
    if (!first) {
      first = r;
      first_scale = scale;
      first_time = time;
      continue;
    }
    const quad first_energy = quad(1) / 2;
    EXPECT_LT(relative_error(*r.e, *first->e), 1e-31);
    EXPECT_LT(relative_error(*r.delta_max / scale, *first->delta_max / first_scale), 1e-31);
    EXPECT_LT(relative_error(*r.t_peak / time, *first->t_peak / first_time), 1e-31);
    EXPECT_LT(relative_error(*r.tau / time, *first->tau / first_time), 1e-31);
    EXPECT_LT(relative_error(*r.energy_load / energy, *first->energy_load / first_energy), 1e-31);
    EXPECT_LT(relative_error(*r.energy_unload / energy, *first->energy_unload / first_energy),
              1e-31);
  }
}
#endif

// The two-variable series on identities: along the series the mechanical energy and the work
// balance, ż² + δ^(p+1) ± W = u² in the scaled units (contact_series.hpp (1)), and locate inverts
// at(). Incommensurate exponents (β + 1 and p + 1 with an irrational ratio) included.
TEST(TwoPowerSeries, EnergyBalancesAndLocateInverts) {
  using Real = long double;
  const Real eps = std::numeric_limits<Real>::epsilon();
  const Real kappa_of_p[][2] = {
      {1, 0}, {1.5L, 0.5L}, {1.5L, 0}, {2.5L, 0.3L}, {1.2L, 0.6180339887L}};
  for (const auto& pb : kappa_of_p) {
    const Real p = pb[0], beta = pb[1], kappa = (p + 1) / 2;
    const auto table = detail::table_for(p, beta, 30);
    for (const Real gamma : {Real(0), Real(0.3L), Real(2)}) {
      for (const int sign : {1, -1}) {
        const detail::TwoPowerSeries<Real> series(table, sign, gamma, kappa, eps);
        for (const Real u : {Real(1), Real(0.001L)}) {
          // The exit is located well inside the reach (taylor tries it after each step).
          const Real s = series.entry_end(u, Real(0.5L), false) / (sign > 0 ? 1 : 2);
          ASSERT_GT(s, 0) << p << " " << beta;
          const auto point = series.at(u, s);
          const Real energy = point.rate * point.rate + std::pow(point.delta, p + 1);
          const Real balance = energy - u * u + sign * point.work;
          EXPECT_LT(std::abs(balance) / std::max(energy, u * u), 64 * eps)
              << "p=" << p << " beta=" << beta << " gamma=" << gamma << " sign=" << sign;
          if (sign < 0) {
            const auto found = series.locate(point.delta, point.rate);
            ASSERT_TRUE(found.has_value()) << p << " " << beta << " " << gamma;
            EXPECT_LT(std::abs(found->u - u) / u, 64 * eps) << p << " " << beta;
            EXPECT_LT(std::abs(found->s - s) / s, 64 * eps) << p << " " << beta;
          }
        }
      }
    }
  }
}

// Asked to, the entry stretch ends before the normal force's peak, so that the steps find it:
// where the force (κ δ^p + γ δ^β dδ/ds, scaled) peaks inside the stretch, the end lies within
// 1/4096 of the stretch before the peak (its rate, taken here by the chain rule from the series'
// values, > 0 at the end and ≤ 0 just past it); where it peaks later, or falls from the onset on
// (β = 0), the stretch is the one not asked to stop.
TEST(TwoPowerSeries, EntryStopsBeforeTheNormalForcePeakWhenAsked) {
  using Real = double;
  const Real eps = std::numeric_limits<Real>::epsilon();
  int stopped = 0, kept = 0;
  for (const auto& [p, beta] : {std::pair{1.0, 0.25}, std::pair{1.5, 0.5}, std::pair{2.0, 0.25},
                                std::pair{2.0, 1.0}, std::pair{1.5, 0.0}}) {
    const Real kappa = (p + 1) / 2;
    const auto table = detail::table_for(p, beta, 23);
    for (const Real gamma : {0.3, 1.0, 3.0}) {
      const detail::TwoPowerSeries<Real> series(table, +1, gamma, kappa, eps);
      const auto force_rate = [&](const Real& s) {
        const auto point = series.at(1, s);
        const Real delta = point.delta, v = point.rate;
        const Real acceleration = -(gamma * std::pow(delta, beta) * v + kappa * std::pow(delta, p));
        return kappa * p * std::pow(delta, p - 1) * v +
               gamma * (beta * std::pow(delta, beta - 1) * v * v +
                        std::pow(delta, beta) * acceleration);
      };
      const Real free = series.entry_end(1, Real(1) / 8, false);
      const Real end = series.entry_end(1, Real(1) / 8, true);
      ASSERT_GT(end, 0);
      if (force_rate(free) > 0 || beta == 0) {
        EXPECT_EQ(end, free) << p << " " << beta << " " << gamma;
        ++kept;
      } else {
        EXPECT_LT(end, free);
        EXPECT_GT(force_rate(end), 0) << p << " " << beta << " " << gamma;
        EXPECT_LE(force_rate(end + free / 4096), 0) << p << " " << beta << " " << gamma;
        ++stopped;
      }
    }
  }
  EXPECT_GE(stopped, 3);
  EXPECT_GE(kept, 3);
}

// The exit's cancellation guard for Y and Z rides on Newton's last whole iteration: at every
// contact point it converges to, its verdict and the work's guard together are cancels()' whole
// verdict. Swept from the contact point back towards the overlap's peak, with the reach opened
// wide (a tail limit of 1e3) so that Newton also converges where the guard trips: the work's sum
// at strong damping, and Y's or Z's further out (four points here).
TEST(TwoPowerSeries, NewtonJudgesTheGuardAsCancelsDoes) {
  using Real = double;
  const Real eps = std::numeric_limits<Real>::epsilon();
  int tripped = 0, held = 0, by_motion = 0;
  for (const auto& [p, beta, gamma] :
       {std::tuple{1.0, 0.05, 4.0}, std::tuple{1.5, 0.5, 0.3}, std::tuple{2.0, 1.0, 2.0},
        std::tuple{2.0, 1.0, 3.0}, std::tuple{3.0, 1.0, 2.0}, std::tuple{1.5, 1.0, 2.0}}) {
    const Real kappa = (p + 1) / 2;
    const auto table = detail::table_for(p, beta, 20);
    const detail::TwoPowerSeries<Real> series(table, -1, gamma, kappa, eps);
    const detail::TwoPowerView<Real> view(table.get(), -gamma, kappa, Real(1e3));
    for (Real s = 0.01; s < 8; s *= 1.05) {
      const auto point = series.motion_at(1, s);
      if (!(point.delta > 0 && point.rate > 0)) {
        break;
      }
      Real u = point.rate, t = point.delta / point.rate;
      std::optional<bool> motion_cancels;
      const auto outcome = view.newton(point.delta, point.rate, u, t, true, &motion_cancels);
      if (outcome != detail::TwoPowerView<Real>::Newton::converged) {
        continue;
      }
      ASSERT_TRUE(motion_cancels.has_value());
      const bool whole = view.cancels(u, t);
      EXPECT_EQ(*motion_cancels || view.cancels(u, t, true), whole) << p << " " << beta << " " << s;
      (whole ? tripped : held) += 1;
      by_motion += *motion_cancels ? 1 : 0;
    }
  }
  EXPECT_GE(by_motion, 2);
  EXPECT_GE(tripped, by_motion);
  EXPECT_GE(held, 10);
}

// A lower degree is cut from a wider table already built (table_for): the very coefficients a
// build to that degree makes, bit for bit, and cut from the least wider one of the same (p, β).
template <class Real>
void expect_lower_degrees_cut_bit_for_bit() {
  const Real p = Real(3) / 2, beta = Real(1) / 2;
  const auto wide = detail::table_for(p, beta, 24);
  for (const int degree : {23, 17, 1}) {
    const auto cut = detail::table_for(p, beta, degree);
    const auto built = detail::two_power_detail::build(p, beta, degree);
    ASSERT_NE(cut, wide);
    EXPECT_EQ(cut->shape.degree(), degree);
    EXPECT_EQ(cut->work_shape.degree(), degree + 1);
    EXPECT_EQ(cut->y, built->y) << degree;
    EXPECT_EQ(cut->z, built->z) << degree;
    EXPECT_EQ(cut->w, built->w) << degree;
  }
  // Another β is no prefix of this one's.
  EXPECT_NE(detail::table_for(p, Real(1) / 4, 10)->y, detail::table_for(p, beta, 10)->y);
}

TEST(TwoPowerSeries, LowerDegreesAreCutFromAWiderTableBitForBit) {
  expect_lower_degrees_cut_bit_for_bit<long double>();
#if PLDAMP_WITH_QUAD
  expect_lower_degrees_cut_bit_for_bit<quad>();
#endif
}

#if PLDAMP_WITH_QUAD
// The float128 tables kept in the source (stored_tables.hpp) are the ones build makes, bit for bit
// (Y, Z and W̃, every stored (p, β)); table_for takes them, and cuts lower degrees from them as
// from a built one; a (p, β) not stored is built.
TEST(TwoPowerSeries, StoredTablesAreTheBuiltOnesBitForBit) {
  const auto bits = [](const std::vector<quad>& values) {
    std::vector<std::array<std::uint64_t, 2>> out;
    for (const quad& x : values) {
      out.push_back(std::bit_cast<std::array<std::uint64_t, 2>>(x.backend().value()));
    }
    return out;
  };
  const auto value = [](const std::uint64_t* words) {
    return quad(std::bit_cast<__float128>(std::array{words[0], words[1]}));
  };
  ASSERT_FALSE(detail::stored_tables.empty());
  for (const detail::StoredTable& stored : detail::stored_tables) {
    const quad p = value(stored.p), beta = value(stored.beta);
    const auto kept = detail::two_power_detail::from_stored(p, beta);
    ASSERT_NE(kept, nullptr);
    const auto built = detail::two_power_detail::build(p, beta, stored.degree);
    EXPECT_EQ(bits(kept->y), bits(built->y));
    EXPECT_EQ(bits(kept->z), bits(built->z));
    EXPECT_EQ(bits(kept->w), bits(built->w));
    const auto taken = detail::table_for(p, beta, stored.degree);
    EXPECT_EQ(bits(taken->y), bits(built->y));
    ASSERT_NE(taken->coarse, nullptr);
    EXPECT_EQ(taken->coarse->y, std::vector<double>(built->y.begin(), built->y.end()));
  }
  // The viscoelastic contact is stored, at the degree of float128's entry series (order 40 + 3:
  // taylor_degrees.hpp); the exit's, at the order, is cut from it.
  const auto viscoelastic = detail::two_power_detail::from_stored(quad(3) / 2, quad(1) / 2);
  ASSERT_NE(viscoelastic, nullptr);
  const int order = detail::taylor_order(static_cast<double>(std::numeric_limits<quad>::epsilon()));
  EXPECT_EQ(order, 40);
  EXPECT_EQ(detail::entry_degree(order), 43);
  EXPECT_EQ(viscoelastic->shape.degree(), detail::entry_degree(order));
  EXPECT_EQ(detail::two_power_detail::from_stored(quad(3) / 2, quad(1) / 3), nullptr);
}

// In float128 a polynomial of the table is summed with its high shells in double where their
// rounding bound allows (TwoPowerView::value, MATH.md §12.3): within tolerance/1024 of the sum in
// float128 throughout, from the onset to the entry's end; and where the shells cancel (an injected
// alternating 1e12 on every shell from degree 10 on), the bound keeps them in float128.
TEST(TwoPowerSeries, HighShellsInDoubleOnlyWhereTheirBoundAllows) {
  const quad eps = std::numeric_limits<quad>::epsilon(), p = quad(3) / 2, beta = quad(1) / 2;
  const quad kappa = (p + 1) / 2, gamma = quad(1) / 2;
  const auto table = detail::table_for(p, beta, 40);
  auto expect_close = [&](const detail::TwoPowerTable<quad>& t, const quad& allowed) {
    const detail::TwoPowerView<quad> view(&t, gamma, kappa, eps / 8);
    const detail::TwoPowerSeries<quad> series(table, 1, gamma, kappa, eps);
    const quad end = series.entry_end(quad(1), quad(1) / 2, false);
    for (const quad& fraction :
         {quad(1) / 1000, quad(1) / 10, quad(1) / 2, quad(9) / 10, quad(1)}) {
      const auto [x1, x2] = view.variables(quad(1), end * fraction);
      for (const auto& [c, coarse] :
           {std::pair{&t.y, &t.coarse->y}, std::pair{&t.z, &t.coarse->z}}) {
        const quad want = detail::TwoPowerView<quad>::evaluate(t.shape, *c, x1, x2);
        EXPECT_LE(abs(view.value(t.shape, *c, *coarse, x1, x2) - want),
                  allowed + 4 * eps * abs(want))
            << static_cast<double>(fraction);
      }
    }
  };
  expect_close(*table, eps / 1024);
  // The injected cancellation: terms 1e12 times the series', alternating, so that summing them in
  // double would cost 1e-4 of the result; the bound must leave them to float128.
  detail::TwoPowerTable<quad> injected = *table;
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; i + j <= 40; ++j) {
      if (i + j >= 10) {
        injected.y[injected.shape.index(i, j)] += quad((i + j) % 2 ? 1e12 : -1e12);
        injected.z[injected.shape.index(i, j)] += quad((i + j) % 2 ? 1e12 : -1e12);
      }
    }
  }
  injected.coarse =
      std::make_shared<const detail::TwoPowerTable<double>>(detail::TwoPowerTable<double>{
          1.5, 0.5, injected.shape, injected.work_shape,
          std::vector<double>(injected.y.begin(), injected.y.end()),
          std::vector<double>(injected.z.begin(), injected.z.end()),
          std::vector<double>(injected.w.begin(), injected.w.end()), nullptr});
  // Float128's own rounding of 1e12-sized terms: the sum in float128 errs by up to ~1e12 D ε too.
  expect_close(injected, quad(1e12) * 64 * eps);
}
#endif

// Every error-controlled double solver against the float128 reference, at rtol 1e-10.
TEST(BeyondTheSeed, EverySolverMeetsItsToleranceAgainstTheReference) {
  Options<double> options;
  options.rtol = 1e-10;
  for (const Beyond& b : beyond_the_seed) {
    const Problem<double> problem{b.p, 1, 1, 1, b.alpha, b.beta};
    using Ref = NarrowestWithDigits10<30>;
    const Problem<Ref> exact{Ref(b.p), 1, 1, 1, Ref(b.alpha), Ref(b.beta)};
    const Result<Ref> x = solve("taylor", exact, at_epsilon<Ref>());
    for (const SolverInfo& info : registry()) {
      if (info.fixed_step) {
        continue;
      }
      const Result<double> r = solve(std::string(info.name), problem, options);
      std::ostringstream label;
      label << info.name << " p=" << b.p << " beta=" << b.beta << " alpha=" << b.alpha;
      ASSERT_EQ(r.outcome, Outcome::exited) << label.str() << " " << r.invariant;
      Worst worst;
      worst.check(r.e, std::optional<double>(double(*x.e)), "e", label.str());
      worst.check(r.delta_max, std::optional<double>(double(*x.delta_max)), "delta_max",
                  label.str());
      worst.check(r.tau, std::optional<double>(double(*x.tau)), "tau", label.str());
      worst.check(r.energy_unload, std::optional<double>(double(*x.energy_unload)), "energy_unload",
                  label.str());
      EXPECT_LT(worst.error, 1e-6) << worst.where;
    }
  }
}

// The DEM schemes converge to the reference at their order: dem-verlet's e at the overlap end is
// first order in the step (the exit found up to one step late, MATH.md §5).
TEST(BeyondTheSeed, DemVerletConvergesToTheReference) {
  for (const Beyond& b : beyond_the_seed) {
    const Problem<double> problem{b.p, 1, 1, 1, b.alpha, b.beta};
    using Ref = NarrowestWithDigits10<30>;
    const Problem<Ref> exact{Ref(b.p), 1, 1, 1, Ref(b.alpha), Ref(b.beta)};
    const double truth = double(*solve("taylor", exact, at_epsilon<Ref>()).e);
    // The largest error over four onset phases: at one phase the error of the step that crosses
    // the exit depends on where it falls (β = 0: the dashpot's force c v does not vanish there).
    double errors[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
      for (const double phase : {0.0, 0.25, 0.5, 0.75}) {
        Options<double> options;
        options.steps_per_contact = i == 0 ? 200 : 2000;
        options.onset_phase = phase;
        errors[i] =
            std::max(errors[i], std::abs(*solve("dem-verlet", problem, options).e - truth) / truth);
      }
    }
    EXPECT_LT(errors[0], 0.05) << b.p << " " << b.beta << " " << b.alpha << " e=" << truth
                               << " errors " << errors[0] << " " << errors[1];
    EXPECT_GT(errors[0] / errors[1], 5) << b.p << " " << b.beta << " " << b.alpha << " e=" << truth
                                        << " errors " << errors[0] << " " << errors[1];
    // Ten for first order; up to 22 where the dashpot is weak and the second-order part of the
    // error still counts at 200 steps (α = 0.05).
    EXPECT_LT(errors[0] / errors[1], 40) << b.p << " " << b.beta << " " << b.alpha;
  }
}

} // namespace
} // namespace pldamp::solvers

namespace pldamp::solvers {
namespace {

#if PLDAMP_WITH_QUAD
// The 1999 series' coefficients from the truth at small speeds (MATH.md §12.5): with
// X = √5 (4/5)^(1/10) α_eff, f(X) = (1 − e)/X = C1 − C2 X + O(X²). Richardson on X and 2X
// removes the C2 term: C1 = 2 f(X) − f(2X) + O(X²); and (f(X) − C1)/X = −C2 + O(X) likewise.
TEST(BeyondTheSeed, ReproducesTheLeadingCoefficientsOfRamirez1999) {
  auto f = [](const quad& alpha_eff) {
    const quad delta_u = pow(quad(5) / 4, quad(2) / 5); // m = k = v0 = 1
    const quad alpha = alpha_eff * sqrt(quad(5)) / pow(delta_u, quad(1) / 4);
    const Result<quad> r = solve("taylor", Problem<quad>{quad(3) / 2, 1, 1, 1, alpha, quad(1) / 2},
                                 at_epsilon<quad>());
    const quad x = analytic::viscoelastic_variable(alpha_eff);
    return (1 - *r.e) / x;
  };
  const quad small = quad(1) / 100000000; // α_eff = 1e-8
  const quad c1 = 2 * f(small) - f(2 * small);
  EXPECT_LT(relative_error(c1, analytic::ramirez_c1<quad>()), 1e-12);
  // g(X) = (f(X) − C1)/X = −C2 + O(X), by Richardson again at α_eff = 1e-4.
  auto g = [&](const quad& alpha_eff) {
    return (f(alpha_eff) - analytic::ramirez_c1<quad>()) /
           analytic::viscoelastic_variable(alpha_eff);
  };
  const quad moderate = quad(1) / 10000;
  const quad c2 = -(2 * g(moderate) - g(2 * moderate));
  EXPECT_LT(relative_error(c2, analytic::ramirez_c2<quad>()), 1e-6);
  RecordProperty("C1", pldamp::testing::scientific(static_cast<double>(c1)));
}

// e by the reference solve at α_eff (m = k = v0 = 1) with the contact ending at `end`, the truth
// of MATH.md §12.5.
quad viscoelastic_restitution(const quad& alpha_eff, End end) {
  const quad delta_u = pow(quad(5) / 4, quad(2) / 5);
  const quad alpha = alpha_eff * sqrt(quad(5)) / pow(delta_u, quad(1) / 4);
  const Result<quad> r = solve("taylor", Problem<quad>{quad(3) / 2, 1, 1, 1, alpha, quad(1) / 2},
                               at_epsilon<quad>(end));
  return *r.e;
}

// The 2011 Padé is of the contact that ends at F = 0 (MATH.md §12.5). Against that truth its error
// up to α_eff = 0.1 is the rounding of its six printed digits, ~3e-6 X (measured 6.4e-8 at
// α_eff = 0.01), and it stays within 2.0e-3 up to α_eff = 1. Against the truth that ends at δ = 0
// it is 300 times worse already at α_eff = 0.01 (1.9e-5): the ends part at order X^(5/2).
TEST(BeyondTheSeed, MullerPoschelPadeFollowsTheForceEndTruth) {
  double largest = 0;
  for (const char* alpha_eff : {"1e-4", "1e-3", "1e-2", "0.1", "0.3", "1"}) {
    const quad z(alpha_eff);
    const quad pade = analytic::muller_poschel_2011_pade(z);
    const quad truth = viscoelastic_restitution(z, End::force);
    largest = std::max(largest, relative_error(pade, truth));
    if (z <= quad(1) / 10) {
      EXPECT_LT(abs(pade - truth), 1e-5 * analytic::viscoelastic_variable(z)) << alpha_eff;
    }
    if (z == quad(1) / 100) {
      EXPECT_GT(relative_error(pade, viscoelastic_restitution(z, End::overlap)), 1e-5);
    }
  }
  EXPECT_LT(largest, 3e-3);
  RecordProperty("largest", pldamp::testing::scientific(largest));
}
#endif

// The 2011 Padé's own series N(v*)/D(v*) = Σ c_k v*^k (c_k = a_k − Σ_j b_j c_(k−j)) must be the
// 1999 series 1 − C1 v*² + C2 v*⁴ with no odd terms below v*⁵, up to the rounding of six printed
// digits (at most 5e-6 per coefficient, two or three of them per c_k). This pins the transcription
// of a1..a3 and b1..b4; b5, b6 are held by the comparison with the truth above.
TEST(PublishedApproximations, MullerPoschelPadeExpandsToTheSeriesOfRamirez1999) {
  const auto a = analytic::muller_poschel_2011_numerator<bin50>();
  const auto b = analytic::muller_poschel_2011_denominator<bin50>();
  std::array<bin50, 5> c{};
  for (std::size_t k = 0; k < c.size(); ++k) {
    c[k] = k < a.size() ? a[k] : bin50(0);
    for (std::size_t j = 1; j <= k; ++j) {
      c[k] -= b[j] * c[k - j];
    }
  }
  EXPECT_EQ(c[0], 1);
  EXPECT_EQ(c[1], 0);
  EXPECT_LT(abs(c[2] + analytic::ramirez_c1<bin50>()), 1e-5);
  EXPECT_LT(abs(c[3]), 1e-5);
  EXPECT_LT(abs(c[4] - analytic::ramirez_c2<bin50>()), 1e-5);
}

// Every quad result against cpp_bin_float_50: the Padé's coefficients are exact rationals in the
// target type, so the two precisions agree to quad's rounding.
TEST(PublishedApproximations, MullerPoschelPadeInEveryPrecision) {
  for (const char* alpha_eff : {"1e-6", "0.05", "0.7", "12"}) {
    const bin50 want = analytic::muller_poschel_2011_pade(bin50(alpha_eff));
    EXPECT_LT(relative_error(analytic::muller_poschel_2011_pade(double(bin50(alpha_eff))), want),
              4 * std::numeric_limits<double>::epsilon())
        << alpha_eff;
#if PLDAMP_WITH_QUAD
    EXPECT_LT(relative_error(analytic::muller_poschel_2011_pade(quad(alpha_eff)), want), 1e-32)
        << alpha_eff;
#endif
  }
}

} // namespace
} // namespace pldamp::solvers
