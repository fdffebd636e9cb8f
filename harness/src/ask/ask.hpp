// The questions about one contact (calibrate, observables, solve, timestep), asked by any front
// end: the command line (cli/) and the Python module (python/module.cpp) fill the same argument
// structs with the options as typed, settle them by the same rules and get the same Answer, so
// that the two doors agree to the last digit and refuse in the same words.
#pragma once

#include "common/answer.hpp"
#include "common/tau_as.hpp"

#include <exception>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pldamp::harness {

// Options as typed by the user; numbers are parsed later, in the precision asked for.
struct ContactArgs {
  std::string p;
  std::optional<std::string> e, alpha, alpha_eff;
  std::string v0 = "1", m = "1", k = "1";
  // A contact from materials (MATH.md §13, ask/materials.hpp): sphere-sphere|sphere-wall and one
  // value per body (or one for both spheres), in place of --m, --k and --p.
  std::optional<std::string> geometry;
  std::vector<std::string> radius, young, poisson, density;
  std::string precision = "double";
  std::string end = "overlap";
  bool json = false;
  std::optional<std::string> damping_exponent; // β of δ^β δ' (MATH.md §12); none: (p − 1)/2
  std::optional<std::string> code;             // calibrate: a DEM code's convention
  bool limit_damping = false;                  // calibrate --code: its optional force cap on
  // calibrate --code for a velocity-dependent model (MATH.md §12.4): where e(v0) is asked, and
  // the effective radius that LAMMPS's damping entry is divided by.
  std::vector<std::string> speeds;
  std::string reff = "1";
  // Every option the user gave, as typed ("--m 2", a list's items joined by commas), in the
  // order given: what settle() needs to tell a default from a value given (--m beside
  // --geometry; calibrate's --v0 without a velocity-dependent --code).
  std::vector<std::string> given;
  // calibrate: the options of `given` that only a velocity-dependent --code takes (the seed's α
  // is scale-free: without such a code they would be ignored, so they are refused). Set by settle.
  std::vector<std::string> speed_options_given;
};

// `pldamp solve`: the contact options plus the solver's.
struct SolveArgs {
  ContactArgs contact;
  std::string solver;
  std::optional<std::string> rtol; // default 1e-8; taylor: the precision's epsilon
  std::optional<std::string> atol, dt, horizon;
  std::string want = "e,delta_max,t_peak,tau,energy,normal_force";
  std::vector<std::string> sample_times;
  std::optional<std::string> steps_per_contact; // fixed-step solvers without --dt (default 50)
  std::optional<std::string> onset_phase;       // fixed-step solvers, in [0, 1)
  std::optional<std::string> tau_as;            // fixed-step solvers: how τ is counted
  std::string max_steps = "1000000";
  std::string max_seconds = "60";
  std::string repeats = "3"; // wall_seconds: the fastest of this many solves
};

// `pldamp timestep`: the contact options plus the question's.
struct TimestepArgs {
  ContactArgs contact; // --code: a DEM code's convention sets α from --e
  std::string scheme;
  std::string tolerance = "0.01";
  std::string observables = "e,delta_max,tau";
  std::string tau_as = "first-step-out"; // the contact time as the user's code measures it
};

// The questions, by the command's name.
enum class Question { calibrate, observables, solve, timestep, check };

// After the options are read: the lists split at commas (common/input.hpp list_items), the
// materials checked against --m, --k and --p (ask/materials.hpp), and what only some questions
// take refused elsewhere. Every front end calls it once, before asking.
void settle(Question question, ContactArgs& args);
void settle(SolveArgs& args);
void settle(TimestepArgs& args);

// The answers, as the command line writes them under --json (ask/*.cpp). Bad input throws
// InputError with the command line's one line.
Answer calibrate_answer(const ContactArgs& args);
Answer observables_answer(const ContactArgs& args);
Answer solve_answer(const SolveArgs& args);
Answer timestep_answer(const TimestepArgs& args);

// The door of a front end that has no argv (the Python module): a question with its options by
// their command-line names and values as typed ({"--alpha-eff", "0.2"}; a list's items
// comma-separated; "" for a switch), read, checked for what the command line requires, settled
// and answered as `pldamp <question> ... --json` answers. An option the question does not take
// is an InputError. check reads a file and answers in its own words: not asked here.
using TypedOptions = std::vector<std::pair<std::string, std::string>>;
Answer ask(Question question, const TypedOptions& options);
// Many cells of one question, each answered as ask() answers it, on `jobs` threads: answers[i]
// for cells[i], or failures[i] when it was refused (the exception ask() would have thrown). The
// double cells of a batched solver (the DEM schemes, verlet-predicted) are stepped together in
// its SIMD lanes (solvers::solve_batch): bit for bit ask()'s answers but for wall_seconds, the
// batch's time divided among its lanes.
void ask_cells(Question question, std::span<const TypedOptions> cells, int jobs,
               std::vector<Answer>& answers, std::vector<std::exception_ptr>& failures);
// ask_cells' solve for the cells of one thread: answers[i] or failures[i] for cells[i].
void solve_answers(std::span<const SolveArgs> cells, std::vector<Answer>& answers,
                   std::vector<std::exception_ptr>& failures);

// "observables" -> Question::observables; InputError for a name that is not a question asked here.
Question question_named(std::string_view name);

// --tau-as's word (common/tau_as.hpp), or InputError naming the choices.
TauAs parse_tau_as(const std::string& word);

// "lammps-tsuji|...|lammps-mass-velocity": every --code calibrate takes (the DEM conventions of
// analytic/conventions.hpp, then LAMMPS's velocity-dependent models), for its help and errors.
std::string calibrate_code_names();

// A contact from materials (it has E_eff) is answered with the units of its numbers; the text
// or JSON line of an answer.
void emit(Answer answer, bool json, std::ostream& out);

} // namespace pldamp::harness
