// `pldamp solve`: one collision integrated by a registered solver. The harness calibrates α from
// --e / --alpha-eff with the analytic layer (in the precision asked for) or, with a
// --damping-exponent, from the group of MATH.md §12.1 and the float128 reference solve; then hands
// solvers/ only the physical parameters (p, m, k, v0, α, β).
#include "ask/contact.hpp"
#include "common/observables.hpp"

#include "pldamp/solvers/registry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <optional>

namespace pldamp::harness {
namespace {

// "e,delta_max,..." -> Want bits; "energy" is both energy_load and energy_unload.
unsigned parse_want_list(const std::string& list) {
  static const std::string asked_by_default = SolveArgs().want;
  if (list == asked_by_default) { // read once: a tenth of what an answer adds to its solve
    static const unsigned wanted_by_default =
        parse_want(list_items("--want", list, true), "--want", true);
    return wanted_by_default;
  }
  const std::vector<std::string> words = list_items("--want", list, true);
  if (words.size() > 1 && std::find(words.begin(), words.end(), "all") != words.end()) {
    throw InputError("--want all names every observable: give it alone (got " + list + ")");
  }
  const unsigned want = parse_want(words, "--want", true);
  if (want == 0) {
    throw InputError("--want names no observable (got " + list + ")");
  }
  return want;
}

template <SupportedReal Real>
Answer samples_of(const std::vector<solvers::Sample<Real>>& samples) {
  Answer out = Answer::array();
  for (const auto& s : samples) {
    out.push_back({exact_number(s.t), exact_number(s.delta), exact_number(s.v)});
  }
  return out;
}

// A collision ready to solve: the answer's head (the contact), the problem and options handed to
// the solver, and how its result is read.
template <SupportedReal Real>
struct PreparedSolve {
  Answer head;
  solvers::Problem<Real> problem;
  solvers::Options<Real> options;
  long repeats = 1;
  TauAs tau_as = TauAs::first_step_out;
};

// Everything before the solve, in precision Real: α calibrated in Real, the options read.
template <SupportedReal Real>
PreparedSolve<Real> prepare(const SolveArgs& args, const solvers::SolverInfo* solver) {
  Answer o = answer_object();
  solvers::Problem<Real> problem{Real(0), Real(0), Real(0), Real(0), Real(0)};
  if (args.contact.damping_exponent) {
    const Real beta = parse_real<Real>("--damping-exponent", *args.contact.damping_exponent);
    problem = contact_with_exponent<Real>(args.contact, beta, o).problem;
    o["damping_exponent"] = exact_number(beta);
  } else {
    // α from e or α_eff as `calibrate` gives it and `run` sends it (describe); --alpha as typed.
    const analytic::Contact<Real> contact = make_contact<Real>(args.contact);
    problem = {contact.p(), contact.m(), contact.k(), contact.v0(), contact.alpha()};
    o = describe(contact, args.contact);
    append(o, "damping_exponent", exact_number(Real((contact.p() - 1) / 2)));
  }
  PreparedSolve<Real> prepared; // filled in place: a copy of the options' optional float128s
                                // read as uninitialized to GCC 12
  solvers::Options<Real>& options = prepared.options;
  if (args.rtol) {
    options.rtol = parse_real<Real>("--rtol", *args.rtol);
  } else if (solver != nullptr) {
    options.rtol = solver->template default_rtol<Real>();
  }
  if (args.atol) {
    options.atol = parse_real<Real>("--atol", *args.atol);
  }
  if (args.dt) {
    options.fixed_step = parse_real<Real>("--dt", *args.dt);
  }
  if (args.horizon) {
    options.horizon = parse_real<Real>("--horizon", *args.horizon);
  }
  if (args.onset_phase) {
    options.onset_phase = parse_real<Real>("--onset-phase", *args.onset_phase);
  }
  for (const std::string& t : args.sample_times) {
    options.sample_times.push_back(parse_real<Real>("--sample-times", t));
    if (std::count(options.sample_times.begin(), options.sample_times.end(),
                   options.sample_times.back()) > 1) {
      throw InputError("--sample-times names one time twice (got " + t + ")");
    }
  }
  options.want = parse_want_list(args.want);
  options.end = parse_end(args.contact.end) == ContactEnd::force ? solvers::End::force
                                                                 : solvers::End::overlap;
  if (args.steps_per_contact) {
    const long steps_per_contact = parse_integer("--steps-per-contact", *args.steps_per_contact);
    if (steps_per_contact < 1 || steps_per_contact > 1000000000) {
      throw InputError("--steps-per-contact must be in [1, 1e9] (got " + *args.steps_per_contact +
                       ")");
    }
    options.steps_per_contact = int(steps_per_contact);
  }
  options.max_steps = parse_whole("--max-steps", args.max_steps); // "1e6", as --help writes it
  options.max_seconds = static_cast<double>(parse_real<double>("--max-seconds", args.max_seconds));

  const long repeats = parse_integer("--repeats", args.repeats);
  if (repeats < 1 || repeats > 1000) {
    throw InputError("--repeats must be in [1, 1000] (got " + args.repeats + ")");
  }
  prepared.head = std::move(o);
  prepared.problem = problem;
  prepared.repeats = repeats;
  prepared.tau_as = args.tau_as ? parse_tau_as(*args.tau_as) : TauAs::first_step_out;
  return prepared;
}

// The answer of a solve: its head, then what the solver measured, read as asked.
template <SupportedReal Real>
Answer finish(PreparedSolve<Real>&& prepared, solvers::Result<Real> r, const SolveArgs& args) {
  Answer o = std::move(prepared.head);
  const solvers::Options<Real>& options = prepared.options;
  const TauAs tau_as = prepared.tau_as;
  const std::optional<Real> tau_first_step_out = r.tau;
  time_contact_as(r, tau_as);

  // Every time asked for is answered: a sample is taken inside the contact the solve ran, and a
  // time past it (after the peak, where --want asks for nothing later; after the contact's end)
  // is refused rather than dropped from the answer.
  for (const Real& t : options.sample_times) {
    if (std::none_of(r.samples.begin(), r.samples.end(),
                     [&](const solvers::Sample<Real>& s) { return s.t == t; })) {
      throw InputError(fmt::format(
          "--sample-times {} lies outside the contact solved (outcome {}{}): samples are taken "
          "inside it (got {})",
          to_string_full(t), solvers::outcome_name(r.outcome),
          r.outcome == solvers::Outcome::peak ? ", at the peak: --want asks for nothing later" : "",
          to_string_full(t)));
    }
  }
  append(o, "solver", args.solver);
  if (r.fixed_step) { // what a fixed-step run used instead of tolerances
    append_number(o, "dt", r.fixed_step);
  } else {
    append(o, "rtol", exact_number(options.rtol));
    append_number(o, "atol", options.atol);
  }
  append(o, "outcome", solvers::outcome_name(r.outcome));
  if (!r.invariant.empty()) {
    append(o, "invariant", r.invariant); // what made the answer impossible
  }
  for (const Observable& observable : observable_table()) { // keys the head does not have
    append_number(o, observable.key_at(options.end), observable.measured(r));
  }
  if (r.fixed_step) { // τ as asked; the three ways a code may count it (docs/MATH.md §5.1)
    append(o, "tau_as", name_of(tau_as_names, tau_as));
    append_number(o, "tau_first_step_out", tau_first_step_out);
    if (r.steps_in_contact) {
      append(o, "steps_in_contact", *r.steps_in_contact);
    }
    append_number(o, "tau_crossing", r.tau_crossing);
  }
  append(o, "steps", r.steps);
  append(o, "rhs_evals", r.rhs_evals);
  if (r.jacobian_evals > 0) {
    append(o, "jacobian_evals", r.jacobian_evals);
  }
  append(o, "wall_seconds", exact_number(r.wall_seconds));
  if (!options.sample_times.empty()) {
    append(o, "samples", samples_of(r.samples));
  }
  return with_units(o);
}

// One collision in precision Real: α calibrated in Real, the solver run in Real. Every solve
// gives the same answer; the time reported is the fastest, as the harness's (the first solve of
// a process pays for cold caches and page faults: 70 µs against 10 µs in loop for a double taylor
// collision).
template <SupportedReal Real>
Answer solve_in(const SolveArgs& args, const solvers::SolverInfo* solver) {
  PreparedSolve<Real> prepared = prepare<Real>(args, solver);
  solvers::Result<Real> r = solvers::solve(args.solver, prepared.problem, prepared.options);
  for (long i = 1; i < prepared.repeats; ++i) {
    r.wall_seconds =
        std::min(r.wall_seconds,
                 solvers::solve(args.solver, prepared.problem, prepared.options).wall_seconds);
  }
  return finish(std::move(prepared), std::move(r), args);
}

} // namespace

TauAs parse_tau_as(const std::string& word) {
  const std::optional<TauAs> as = value_named(tau_as_names, word);
  if (!as) {
    throw InputError("--tau-as must be " + names_of(tau_as_names) + " (got " + word + ")");
  }
  return *as;
}

namespace {

// What solve refuses before any precision is chosen; the solver's traits (none for an unknown
// name, which solvers::solve reports after the contact's own checks).
const solvers::SolverInfo* checked_solver(const SolveArgs& args) {
  const solvers::SolverInfo* solver = solvers::find_solver(args.solver);
  if (solver != nullptr && !solver->runs_in(args.contact.precision) &&
      precision_bit(args.contact.precision) != 0) {
    throw InputError(solvers::precision_refusal(*solver, "--precision " + args.contact.precision));
  }
  // Worded like the refusal of --atol (registry.cpp): the step is what --dt or
  // --steps-per-contact set, and telling to give them misled when one was given already.
  if (solver != nullptr && args.rtol && !solver->takes_rtol()) {
    throw InputError(args.solver + " takes a fixed step and no rtol (got --rtol " + *args.rtol +
                     ")");
  }
  if (solver != nullptr && args.steps_per_contact && !solver->fixed_step) {
    throw InputError(args.solver + " does not step a fixed number of steps per contact (got " +
                     "--steps-per-contact " + *args.steps_per_contact + ")");
  }
  if (args.tau_as) {
    parse_tau_as(*args.tau_as);
    if (solver != nullptr && !solver->fixed_step) {
      throw InputError(args.solver +
                       " is not a fixed-step solver: its tau is not counted on "
                       "steps (got --tau-as " +
                       *args.tau_as + ")");
    }
  }
  if (args.steps_per_contact && args.dt) {
    throw InputError("give --dt or --steps-per-contact, not both (got --steps-per-contact " +
                     *args.steps_per_contact + ")");
  }
  return solver;
}

// The cells of a batched solver in double, stepped together (solvers::solve_batch): each lane's
// result is solve()'s, bit for bit, but for its wall time (the batch's, divided among its lanes).
// A batch that throws is solved again cell by cell, so that each cell gets its own answer or
// refusal.
void solve_batched(std::span<const SolveArgs> cells, const std::vector<std::size_t>& batched,
                   std::vector<std::optional<PreparedSolve<double>>>& prepared,
                   std::vector<Answer>& answers, std::vector<std::exception_ptr>& failures) {
  std::vector<solvers::Problem<double>> problems;
  std::vector<solvers::Options<double>> options;
  long repeats = 1;
  for (const std::size_t i : batched) {
    problems.push_back(prepared[i]->problem);
    options.push_back(prepared[i]->options);
    repeats = std::max(repeats, prepared[i]->repeats);
  }
  std::vector<solvers::Result<double>> results;
  try {
    results = solvers::solve_batch(cells[batched.front()].solver, problems, options);
    for (long r = 1; r < repeats; ++r) {
      const auto again = solvers::solve_batch(cells[batched.front()].solver, problems, options);
      for (std::size_t j = 0; j < batched.size(); ++j) {
        if (r < prepared[batched[j]]->repeats) {
          results[j].wall_seconds = std::min(results[j].wall_seconds, again[j].wall_seconds);
        }
      }
    }
  } catch (...) {
    results.clear();
  }
  for (std::size_t j = 0; j < batched.size(); ++j) {
    const std::size_t i = batched[j];
    try {
      answers[i] = results.empty()
                       ? solve_in<double>(cells[i], solvers::find_solver(cells[i].solver))
                       : finish(std::move(*prepared[i]), std::move(results[j]), cells[i]);
    } catch (...) {
      failures[i] = std::current_exception();
    }
  }
}

// solve_answer's answer once the solver's traits are checked.
Answer solve_checked(const SolveArgs& args, const solvers::SolverInfo* solver) {
  Answer answer;
  with_precision(args.contact.precision,
                 [&]<SupportedReal Real>() { answer = solve_in<Real>(args, solver); });
  return answer;
}

} // namespace

Answer solve_answer(const SolveArgs& args) {
  return solve_checked(args, checked_solver(args));
}

void solve_answers(std::span<const SolveArgs> cells, std::vector<Answer>& answers,
                   std::vector<std::exception_ptr>& failures) {
  answers.assign(cells.size(), Answer());
  failures.assign(cells.size(), nullptr);
  // A batched solver's double cells set aside for its lanes, any other cell answered as
  // solve_answer answers it.
  std::vector<std::optional<PreparedSolve<double>>> prepared(cells.size());
  std::map<std::string, std::vector<std::size_t>> by_solver; // lanes share a solver
  for (std::size_t i = 0; i < cells.size(); ++i) {
    try {
      const solvers::SolverInfo* solver = checked_solver(cells[i]);
      if (solver != nullptr && solver->batched && cells[i].contact.precision == "double") {
        prepared[i] = prepare<double>(cells[i], solver);
        by_solver[cells[i].solver].push_back(i);
      } else {
        answers[i] = solve_checked(cells[i], solver);
      }
    } catch (...) {
      failures[i] = std::current_exception();
    }
  }
  for (const auto& [name, batched] : by_solver) {
    solve_batched(cells, batched, prepared, answers, failures);
  }
}

} // namespace pldamp::harness
