#include "cli/contact_args.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pldamp::harness {

namespace {

// `calibrate --code`: what a DEM code sets for the target e, what it really gives, and what to
// enter instead (MATH.md §5).
void calibrate_for_code(const ContactArgs& args, std::ostream& out) {
  const analytic::Convention* convention = analytic::find_convention(*args.code);
  if (convention == nullptr) {
    throw InputError("unknown --code, expected " + analytic::convention_names() + " (got " +
                     *args.code + ")");
  }
  if (args.limit_damping && convention->cap != analytic::Cap::optional) {
    throw InputError(std::string(convention->name) +
                     (convention->cap == analytic::Cap::always ? " always caps" : " never caps") +
                     " the force: --limit-damping is a LAMMPS and LIGGGHTS option (got " +
                     "--limit-damping)");
  }
  with_precision(args.precision, [&]<SupportedReal Real>() {
    const Real p = parse_real<Real>("--p", args.p);
    const Real target = parse_real<Real>("--e", *args.e);
    domain::require_p(p);
    const bool cut = analytic::capped(*convention, args.limit_damping);
    const Real alpha = analytic::alpha_set(*convention, p, target);
    const std::optional<Real> enter =
        analytic::e_to_enter(*convention, p, target, args.limit_damping);
    Answer o;
    o["precision"] = precision_name<Real>();
    o["code"] = convention->name;
    o["end"] = cut ? "force" : "overlap";
    o["p"] = exact_number(p);
    o["e"] = exact_number(target);
    o["alpha"] = exact_number(alpha);
    o["alpha_eff"] = exact_number(Real(alpha / analytic::alpha_per_alpha_eff(p)));
    o["e_given"] = exact_number(analytic::e_given(p, alpha, cut));
    if (enter) {
      o["e_to_enter"] = exact_number(*enter);
    } else {
      o["e_to_enter"] = nullptr; // out of the convention's reach
      o["e_reachable_from"] = exact_number(
          analytic::e_given(p, analytic::alpha_set(*convention, p, Real(1) / 1000000), cut));
    }
    o["source"] = convention->source;
    emit(o, args.json, out);
  });
}

} // namespace

void run_calibrate(const ContactArgs& args, std::ostream& out) {
  if (!args.e) {
    throw InputError("calibrate needs --e (got nothing)");
  }
  if (args.code) {
    calibrate_for_code(args, out);
    return;
  }
  if (args.limit_damping) {
    throw InputError("--limit-damping goes with --code (got --limit-damping alone)");
  }
  with_precision(args.precision, [&]<SupportedReal Real>() {
    const analytic::Contact<Real> c = make_contact<Real>(args);
    Answer o;
    o["precision"] = precision_name<Real>();
    o["end"] = args.end;
    o["p"] = exact_number(c.p());
    o["e"] = exact_number(parse_real<Real>("--e", *args.e));
    o["alpha"] = exact_number(c.alpha());
    o["alpha_eff"] = exact_number(c.alpha_eff());
    if (parse_end(args.end) == ContactEnd::force) {
      // What the same α gives a code that lets the force turn attractive (overlap end).
      o["e_uncapped"] = exact_number(analytic::restitution(c.damping()));
    } else {
      o["e_cap"] = exact_number(analytic::capped_restitution(c.damping()));
    }
    emit(o, args.json, out);
  });
}

void run_observables(const ContactArgs& args, std::ostream& out) {
  with_precision(args.precision, [&]<SupportedReal Real>() {
    const analytic::Contact<Real> c = make_contact<Real>(args);
    const bool capped = parse_end(args.end) == ContactEnd::force;
    const auto x = analytic::observables(c, analytic::want_all &
                                                ~(capped ? 0u : unsigned(analytic::want_capped)));
    Answer o = describe(c, args);
    const std::pair<const char*, const std::optional<Real>&> fields[] = {
        {"e", x.e},
        {"log_e", x.log_e},
        {"delta_max", x.delta_max},
        {"force_max", x.force_max},
        {"t_peak", x.t_peak},
        {"tau", x.tau},
        {"log_tau", x.log_tau},
        {"tau0", x.tau0},
        {"tau_ratio", x.tau_ratio},
        {"energy_load", x.energy_load},
        {"energy_unload", x.energy_unload},
        {"dt_crit", x.dt_crit},
        {"dt_tangent", x.dt_tangent},
        {"e_cap", x.e_cap},
        {"t_cut", x.t_cut}};
    for (const auto& [key, value] : fields) {
      put_number(o, key, value);
    }
    emit(o, args.json, out);
  });
}

void run_showcase(const std::string& precision, std::ostream& out) {
  with_precision(precision, [&]<SupportedReal Real>() {
    auto shown = [](const Real& value) {
      std::ostringstream s;
      s.precision(10);
      s << value;
      return s.str();
    };
    out << fmt::format("pldamp showcase: closed forms of MATH.md at v0 = m = k = 1, precision {}\n",
                       precision_name<Real>());
    out << fmt::format("{:>4} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
                       "p", "alpha_eff", "e", "e_cap", "delta_max", "t_peak", "tau", "tau/tau0",
                       "E_load/KE0", "E_unload/KE0");
    auto row = [&](const analytic::Contact<Real>& c) {
      const auto x = analytic::observables(c);
      out << fmt::format("{:>4} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12} {:>12}\n",
                         shown(c.p()), shown(c.alpha_eff()), shown(*x.e), shown(*x.e_cap),
                         shown(*x.delta_max), shown(*x.t_peak), shown(*x.tau), shown(*x.tau_ratio),
                         shown(Real(*x.energy_load / c.ke0())),
                         shown(Real(*x.energy_unload / c.ke0())));
    };
    for (const char* p : {"1", "1.5", "2", "2.5", "3"}) {
      row(analytic::Contact<Real>::from_e(parse_real<Real>("p", p), Real(1) / 2, Real(1)));
    }
    row(analytic::Contact<Real>::from_alpha_eff(Real(3) / 2, Real(3) / 2, Real(1)));
    out << "(alpha_eff >= 1 is overdamped: no return in finite time, e = 0, tau = inf)\n";
  });
}

} // namespace pldamp::harness
