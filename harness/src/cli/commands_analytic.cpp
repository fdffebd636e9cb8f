#include "cli/contact_args.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pldamp::harness {

void run_calibrate(const ContactArgs& args, std::ostream& out) {
  if (!args.e) {
    throw InputError("calibrate needs --e (got nothing)");
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
