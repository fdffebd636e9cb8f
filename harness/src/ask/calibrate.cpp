// `pldamp calibrate`: the seed's α for a target e (MATH.md §2), what a DEM code's convention sets
// and really gives (MATH.md §5), and the α of LAMMPS's velocity-dependent models at a speed, with
// the e(v0) curve from the reference solve (MATH.md §12.4).
#include "ask/contact.hpp"
#include "truth/plan.hpp"
#include "truth/reference_solve.hpp"

#include "pldamp/analytic.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string_view>
#include <vector>

namespace pldamp::harness {

namespace {

// `calibrate --code`: what a DEM code sets for the target e, what it really gives, and what to
// enter instead (MATH.md §5).
Answer calibrate_for_code(const ContactArgs& args) {
  const analytic::Convention* convention = analytic::find_convention(*args.code);
  if (convention == nullptr) {
    throw InputError("unknown --code, expected " + calibrate_code_names() + " (got " + *args.code +
                     ")");
  }
  if (args.limit_damping && convention->cap != analytic::Cap::optional) {
    throw InputError(std::string(convention->name) +
                     (convention->cap == analytic::Cap::always ? " always caps" : " never caps") +
                     " the force: --limit-damping is a LAMMPS and LIGGGHTS option (got " +
                     "--limit-damping)");
  }
  Answer answer;
  with_precision(args.precision, [&]<SupportedReal Real>() {
    const Real p = parse_real<Real>("--p", args.p);
    const Real target = parse_real<Real>("--e", *args.e);
    domain::require_p(p);
    const bool cut = analytic::capped(*convention, args.limit_damping);
    const Real alpha = analytic::alpha_set(*convention, p, target);
    require_finite_alpha_set(*convention, alpha, *args.e);
    const std::optional<Real> enter =
        analytic::e_to_enter(*convention, p, target, args.limit_damping);
    Answer o = answer_object();
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
    answer = std::move(o);
  });
  return answer;
}

// The velocity-dependent models of LAMMPS (MATH.md §12.4): a dashpot δ^β δ' with β ≠ (p−1)/2,
// so that e depends on the impact speed. Read from LAMMPS's sources (adapters/lammps quotes the
// statements; tests/adapters/lammps_test.py checks the reading against the installed binary).
struct VelocityDependentCode {
  std::string_view name;
  double p; // 0: the model has p = 1 and 3/2, --p chooses
  double beta;
  bool divided_by_radius; // the entry is α √(k/m) / √Reff, else α √(k/m)
  std::string_view parameter, source;
};
constexpr VelocityDependentCode velocity_dependent_codes[] = {
    {"lammps-viscoelastic", 1.5, 0.5, true,
     "damp of pair_coeff ... hertz kn damping viscoelastic damp (kn = k/sqrt(Reff))",
     "LAMMPS src/GRANULAR/pair_granular.cpp: damp_normal = a*meff with a = sqrt(delta*Reff), "
     "Fdamp = -damp*damp_normal*vnnr: c = damp m sqrt(Reff) delta^(1/2)"},
    {"lammps-hertz-history", 1.5, 0.5, true,
     "gamman of pair_style gran/hertz/history kn kt gamman ... (kn = k/sqrt(Reff))",
     "LAMMPS src/GRANULAR/pair_gran_hertz_history.cpp: damp = meff*gamman*vnnr*rsqinv, "
     "ccel = kn*(radsum-r)*rinv - damp, ccel *= polyhertz = sqrt(delta*Reff)"},
    {"lammps-mass-velocity", 0, 0, false,
     "damp of pair_coeff ... hooke|hertz kn damping mass_velocity damp",
     "LAMMPS src/GRANULAR/pair_granular.cpp: damp_normal = meff, Fdamp = "
     "-damp*damp_normal*vnnr: c = damp m, beta = 0 (the seed's only at p = 1)"},
};

const VelocityDependentCode* find_velocity_dependent(std::string_view name) {
  for (const VelocityDependentCode& code : velocity_dependent_codes) {
    if (code.name == name) {
      return &code;
    }
  }
  return nullptr;
}

} // namespace

std::string calibrate_code_names() {
  std::string names = analytic::convention_names();
  for (const VelocityDependentCode& code : velocity_dependent_codes) {
    names += '|';
    names += code.name;
  }
  return names;
}

namespace {

// `calibrate --code` for a velocity-dependent model: the α (and the code's entry) that gives e at
// the speed --v0, and the e the same α gives at other speeds (the reference solve, float128).
Answer calibrate_velocity_dependent(const ContactArgs& args, const VelocityDependentCode& code) {
  if (args.precision != "double") {
    throw InputError("a velocity-dependent --code is calibrated on the float128 reference and "
                     "answers in double (got --precision " +
                     args.precision + ")");
  }
  const double p = parse_real<double>("--p", args.p);
  if (code.p == 0 && p != 1 && p != 1.5) {
    throw InputError(std::string(code.name) + " has a hooke (p = 1) and a hertz (p = 1.5) model: " +
                     "p must be 1 or 1.5 (got --p " + args.p + ")");
  }
  if (code.p != 0 && p != code.p) {
    throw InputError(std::string(code.name) + " is a hertz model: p must be 1.5 (got --p " +
                     args.p + ")");
  }
  const double e = parse_real<double>("--e", *args.e);
  require_finite("e", e);
  require(e > 0 && e <= 1, "e must be in (0, 1]", e);
  // From materials: m*, k and R* (MATH.md §13), the Reff LAMMPS divides its entry by.
  const std::optional<analytic::HertzContact<double>> hertz = hertz_of<double>(args);
  const auto given = [&](const char* option) {
    return std::any_of(
        args.speed_options_given.begin(), args.speed_options_given.end(),
        [&](const std::string& typed) { return typed.rfind(std::string(option) + " ", 0) == 0; });
  };
  if (hertz && given("--reff")) {
    throw InputError("--reff is R* under --geometry, derived from the radii (got --reff " +
                     args.reff + ")");
  }
  if (hertz && !given("--v0")) { // in SI the speed at which e is set has no natural default
    throw InputError("--v0, the relative normal speed in m/s at which e is set, is required with "
                     "--geometry (got nothing)");
  }
  const std::pair<double, double> mass_stiffness = mass_and_stiffness<double>(args);
  const double m = mass_stiffness.first, k = mass_stiffness.second; // (lambdas capture them)
  const double v0 = parse_real<double>("--v0", args.v0),
               reff = hertz ? hertz->radius : parse_real<double>("--reff", args.reff);
  domain::require_scale("v0", v0);
  domain::require_scale("m", m);
  domain::require_scale("k", k);
  domain::require_scale("Reff", reff);
  std::vector<double> speeds{v0 / 10, v0, 10 * v0};
  if (!args.speeds.empty()) {
    speeds.clear();
    for (const std::string& speed : args.speeds) {
      speeds.push_back(parse_real<double>("--speeds", speed));
      domain::require_scale("speed", speeds.back());
      if (std::count(speeds.begin(), speeds.end(), speeds.back()) > 1) {
        throw InputError("--speeds names one speed twice (got " + speed + ")");
      }
    }
  }
  const solvers::End end = args.limit_damping ? solvers::End::force : solvers::End::overlap;
  auto overlap_scale = [&](double speed) {
    return exp(log((Exact(p) + 1) / 2 * Exact(m) * Exact(speed) * Exact(speed) / Exact(k)) /
               (Exact(p) + 1));
  };
  const std::optional<Exact> group = group_for_e(p, code.beta, e, end);
  if (!group) {
    throw InputError(
        fmt::format("no damping gives e = {} with {} that the reference solve resolves: the "
                    "contact returns later than its horizon of 10^4 delta_u/v0 before e falls to "
                    "it (got --e {})",
                    *args.e, code.name, *args.e));
  }
  const Exact alpha = alpha_of(p, code.beta, *group, overlap_scale(v0));
  const double entry = static_cast<double>(alpha * sqrt(Exact(k) / Exact(m)) /
                                           (code.divided_by_radius ? sqrt(Exact(reff)) : Exact(1)));
  Answer o = answer_object();
  o["code"] = code.name;
  o["end"] = end == solvers::End::force ? "force" : "overlap";
  o["p"] = exact_number(p);
  o["damping_exponent"] = exact_number(code.beta);
  o["e"] = exact_number(e);
  o["v0"] = exact_number(v0);
  o["alpha"] = exact_number(static_cast<double>(alpha));
  o["alpha_eff"] = exact_number(static_cast<double>(*group));
  o["entry"] = exact_number(entry);
  o["entry_is"] = code.parameter;
  if (hertz) {
    o["m"] = exact_number(m);
    o["k"] = exact_number(k);
    describe_materials<double>(args, o);
    // With another dashpot than the seed's α has a unit: α √(m k) δ^β δ' is a force when α is in
    // m^((p−1)/2 − β); the entry α √(k/m) (/√R*) is then in m^(−β) (m^(−β−1/2)) per second.
    const auto metres = [](double power) {
      return power == 0 ? std::string() : fmt::format("m^{:g}", power);
    };
    Answer units = Answer::object();
    if (const std::string alpha_unit = metres((p - 1) / 2 - code.beta); !alpha_unit.empty()) {
      units["alpha"] = alpha_unit;
    }
    const std::string per_metre = metres(-code.beta - (code.divided_by_radius ? 0.5 : 0.0));
    units["entry"] = per_metre.empty() ? "1/s" : per_metre + "/s";
    o["units"] = units;
  }
  // e at each speed, from the reference solve of its group, solved from the least damped up: the
  // more damped a contact, the later it returns and the more steps its solve takes. A group far
  // beyond the last one solved is approached in steps of 8 (a contact that does not return within
  // the solve's horizon, or its steps, at one group does not at a larger one), so that damping
  // beyond what the solve resolves is refused in about a second: --speeds 1e30 took 140 s to say
  // step_limit, and 1e20 answered e = 0, the solve's horizon taken for no return.
  constexpr long curve_steps = 100000; // about 9 s of float128 Taylor steps on a 2.4 GHz core
  std::vector<Exact> groups;
  std::vector<std::size_t> order;
  for (const double speed : speeds) {
    order.push_back(groups.size());
    groups.push_back(group_of(p, code.beta, alpha, overlap_scale(speed)));
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return groups[a] < groups[b]; });
  std::vector<Exact> restitution(speeds.size());
  Exact resolved(1); // the most damped group seen to return (at least a start for the steps)
  for (const std::size_t i : order) {
    const auto solved = [&](const Exact& damping) {
      solvers::Result<Exact> truth =
          reference_solve_within(Exact(p), Exact(code.beta), damping, end, curve_steps);
      if (truth.outcome == solvers::Outcome::no_exit || solvers::failing(truth.outcome) ||
          !truth.e) {
        throw InputError(fmt::format(
            "at v0 = {} (alpha_eff {:.6g}) no e: the reference solve {}{}, and more damping "
            "returns later; ask at lower damping (got --speeds {})",
            speeds[i], static_cast<double>(groups[i]),
            damping == groups[i] ? "" : fmt::format("at alpha_eff {:.6g} ", double(damping)),
            truth.outcome == solvers::Outcome::no_exit
                ? "saw no return within its horizon of 10^4 delta_u/v0"
                : fmt::format("ended {} within {} steps", solvers::outcome_name(truth.outcome),
                              curve_steps),
            speeds[i]));
      }
      resolved = damping;
      return *truth.e;
    };
    for (Exact step = resolved * 8; step < groups[i]; step *= 8) {
      (void)solved(step);
    }
    restitution[i] = solved(groups[i]);
  }
  Answer curve = Answer::array();
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    curve.push_back({{"v0", exact_number(speeds[i])},
                     {"alpha_eff", exact_number(static_cast<double>(groups[i]))},
                     {"e", exact_number(static_cast<double>(restitution[i]))}});
  }
  o["e_of_v0"] = curve;
  o["source"] = code.source;
  return with_units(o);
}

} // namespace

Answer calibrate_answer(const ContactArgs& args) {
  if (!args.e) {
    throw InputError("calibrate needs --e (got nothing)");
  }
  if (args.code) {
    if (const VelocityDependentCode* code = find_velocity_dependent(*args.code)) {
      return calibrate_velocity_dependent(args, *code);
    }
  }
  if (!args.speed_options_given.empty()) {
    const std::string& given = args.speed_options_given.front();
    throw InputError(given.substr(0, given.find(' ')) +
                     " goes with a velocity-dependent --code (lammps-viscoelastic|"
                     "lammps-hertz-history|lammps-mass-velocity): the seed's alpha for an e does "
                     "not depend on v0, m or k (got " +
                     given + ")");
  }
  if (args.code) {
    return calibrate_for_code(args);
  }
  if (args.limit_damping) {
    throw InputError("--limit-damping goes with --code (got --limit-damping alone)");
  }
  Answer answer;
  with_precision(args.precision, [&]<SupportedReal Real>() {
    const analytic::Contact<Real> c = make_contact<Real>(args);
    Answer o = answer_object();
    o["precision"] = precision_name<Real>();
    o["end"] = args.end;
    o["p"] = exact_number(c.p());
    o["e"] = exact_number(parse_real<Real>("--e", *args.e));
    // α and α_eff as `run` sends them for this p and e (seed_alpha, seed_alpha_eff): the
    // contact's own, calibrated in CalibrationReal and rounded once at any scale (describe()).
    o["alpha"] = exact_number(c.alpha());
    o["alpha_eff"] = exact_number(c.alpha_eff());
    if (parse_end(args.end) == ContactEnd::force) {
      // What the same α gives a code that lets the force turn attractive (overlap end).
      o["e_uncapped"] = exact_number(analytic::restitution(c.damping()));
    } else {
      o["e_cap"] = exact_number(analytic::capped_restitution(c.damping()));
    }
    answer = std::move(o);
  });
  return with_units(answer);
}

} // namespace pldamp::harness
