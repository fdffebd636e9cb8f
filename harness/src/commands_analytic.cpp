#include "contact_args.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pldamp::harness {

void run_calibrate(const ContactArgs& args, std::ostream& out) {
  if (!args.e) {
    throw InputError("calibrate needs --e (got nothing)");
  }
  with_precision(args.precision, [&]<class Real>() {
    const analytic::Contact<Real> c = make_contact<Real>(args);
    JsonObject o;
    o.string("precision", std::string(precision_name<Real>()));
    o.string("end", args.end);
    o.number("p", c.p());
    o.number("e", parse_real<Real>("--e", *args.e));
    o.number("alpha", c.alpha());
    o.number("alpha_eff", c.alpha_eff());
    if (parse_end(args.end) == ContactEnd::force) {
      // What the same α gives a code that lets the force turn attractive (overlap end).
      o.number("e_uncapped", analytic::restitution(c.damping()));
    } else {
      o.number("e_cap", analytic::capped_restitution(c.damping()));
    }
    emit(o, args.json, out);
  });
}

void run_observables(const ContactArgs& args, std::ostream& out) {
  with_precision(args.precision, [&]<class Real>() {
    const analytic::Contact<Real> c = make_contact<Real>(args);
    const bool capped = parse_end(args.end) == ContactEnd::force;
    const auto x = analytic::observables(c, analytic::want_all &
                                                ~(capped ? 0u : unsigned(analytic::want_capped)));
    JsonObject o = describe(c, args);
    o.number("e", x.e);
    o.number("log_e", x.log_e);
    o.number("delta_max", x.delta_max);
    o.number("force_max", x.force_max);
    o.number("t_peak", x.t_peak);
    o.number("tau", x.tau);
    o.number("tau0", x.tau0);
    o.number("tau_ratio", x.tau_ratio);
    o.number("energy_load", x.energy_load);
    o.number("energy_unload", x.energy_unload);
    o.number("dt_crit", x.dt_crit);
    o.number("dt_tangent", x.dt_tangent);
    o.number("e_cap", x.e_cap);
    o.number("t_cut", x.t_cut);
    emit(o, args.json, out);
  });
}

void run_showcase(const std::string& precision, std::ostream& out) {
  with_precision(precision, [&]<class Real>() {
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
