// The questions about one contact (ask/ask.hpp) written as the command line writes them, and
// `pldamp showcase`, a table of the closed forms.
#include "cli/commands.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <sstream>

namespace pldamp::harness {

void run_calibrate(const ContactArgs& args, std::ostream& out) {
  emit(calibrate_answer(args), args.json, out);
}

void run_observables(const ContactArgs& args, std::ostream& out) {
  emit(observables_answer(args), args.json, out);
}

void run_solve(const SolveArgs& args, std::ostream& out) {
  emit(solve_answer(args), args.contact.json, out);
}

void run_timestep(const TimestepArgs& args, std::ostream& out) {
  emit(timestep_answer(args), args.contact.json, out);
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
