// External solvers (docs/external.md "Your code in the loop"): a scene's [[solver]] that
// names a program. pldamp starts it once per [[solver]] entry (the configurations of its sweep
// share it) with an argument vector (never a shell)
// and speaks the pldamp-solver protocol, version 1, to it: a handshake line each way, then one
// JSON problem per line on its standard input and one JSON result per line from its standard
// output. What comes back is a solvers::Result like any registered solver's, so budgets, claims,
// work-precision points and diffs treat it alike.
//
// A program that cannot be started or speaks another protocol stops the run before any work
// (ProtocolError, exit 2). Within the run, a malformed, missing, late or foreign reply, an `error`
// outcome and a crash fail that record with the reason (std::runtime_error) and the program is
// restarted for the next; `unsupported`, `unavailable` and a p or contact end outside the
// handshake's skip it (Skipped). An answer that breaks an invariant of pldamp's own solvers
// (answers.hpp) is `unstable`, with the reason. A configuration that sets what the handshake's
// `honours` leaves out is refused before any work (ProtocolError).
#pragma once

#include "common/input.hpp"
#include "common/process.hpp"
#include "scene/scene.hpp"

#include "pldamp/solvers/problem.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pldamp::harness {

inline constexpr std::string_view protocol_name = "pldamp-solver";
inline constexpr int protocol_version = 1;

// The program could not be started, or its handshake is not protocol version 1: exit 2.
struct ProtocolError : InputError {
  using InputError::InputError;
};

// The program does not run this record; the reason is reported, the record is not failed.
struct Skipped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a program said of itself in its handshake.
struct ExternalFacts {
  std::string solver;                     // its name for itself
  std::optional<double> damping_exponent; // β of its dashpot c δ^β δ'; none: the seed's (p−1)/2
  std::vector<double> exponents;          // the p it runs (empty: any)
  std::vector<solvers::End> ends;         // the contact ends it runs
  std::string unavailable;                // not empty: it cannot run here (its code is missing)
  // The settings it says it honours (steps_per_contact, dt, onset_phase, rtol, atol,
  // options.KEY); none: it did not say, and is not checked.
  std::optional<std::vector<std::string>> honours;

  // β at p.
  double beta(double p) const { return damping_exponent.value_or((p - 1) / 2); }
  // The closed forms are its truth at p: its dashpot is the seed's (MATH.md §1).
  bool seed_damping(double p) const;
  // "LAMMPS granular hertz tsuji; damping exponent 0.5; honours dt, onset_phase"
  std::string describe() const;
  // Throws ProtocolError when `config` sets what the program declared it does not honour
  // (answers.hpp, settings_not_honoured); an unavailable program is not asked.
  void require_honoured(const SolverConfig& config) const;
};

// What a program says is read within these bounds, before anything of it is kept or printed (a
// line is at most 1 MiB: LineProgram): JSON nested deeper than `max_reply_depth` is refused
// unread (nlohmann's dump, which a message quoting a value calls, recurses once per level: a
// reply of 10^5 nested arrays overflowed the stack), and each text kept from it (a name, a
// reason) is cut to `max_reply_text` characters, each list to `max_reply_items`.
inline constexpr int max_reply_depth = 16;
inline constexpr std::size_t max_reply_text = 200;
inline constexpr std::size_t max_reply_items = 1000;
// The largest work count (steps, rhs_evals) a reply may state: a report sums them over its
// records in 64 bits (larger ones wrapped the total).
inline constexpr double max_reply_count = 1e12;

// The program's own `error` outcome: the record fails, the exchange is still in step.
struct ReportedError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A handshake line's facts; throws ProtocolError naming what is wrong (`who` begins it).
ExternalFacts read_handshake(const std::string& line, const std::string& who);
// A reply line to problem `id` as a Result, before the invariants (answers.hpp) are checked;
// throws Skipped (unsupported), ReportedError (the program's error) or std::runtime_error (a
// reply that cannot be read: the exchange is no longer trusted).
solvers::Result<double> read_reply(const std::string& line, long id);

class ExternalSolver {
public:
  // Starts the program and reads its handshake (within 30 s, or `limit_seconds` if longer);
  // `limit_seconds` bounds each reply after it, and `stop` (the run's stop_requested) ends any
  // wait for the program. Throws ProtocolError.
  ExternalSolver(const SolverConfig& config, double limit_seconds,
                 const std::atomic<bool>* stop = nullptr);
  ExternalSolver(const ExternalSolver&) = delete;
  ExternalSolver& operator=(const ExternalSolver&) = delete;
  ~ExternalSolver();

  const ExternalFacts& facts() const { return facts_; }

  // One problem of `config` (this program's, or another of its [[solver]] entry's sweep), one
  // reply; one at a time per program (callers on several threads queue). Throws Skipped, or
  // std::runtime_error with the reason the record failed.
  solvers::Result<double> solve(const SolverConfig& config, const solvers::Problem<double>& problem,
                                const solvers::Options<double>& options);

private:
  void start();        // the program and its handshake; throws ProtocolError
  void stop_program(); // after a broken exchange: killed, restarted on the next problem
  std::string problem_line(const SolverConfig& config, const solvers::Problem<double>& problem,
                           const solvers::Options<double>& options, long id) const;
  // Why the program stopped answering: its exit status and the last line it wrote on stderr.
  std::string why_stopped(const std::string& partial);

  SolverConfig config_;
  nlohmann::ordered_json options_; // config_.options, parsed once
  std::chrono::milliseconds limit_;
  const std::atomic<bool>* stop_;
  ExternalFacts facts_;
  std::unique_ptr<LineProgram> program_;
  std::string dead_; // not empty: it could not be restarted; every record fails with this
  long next_id_ = 0;
  std::mutex busy_;
};

} // namespace pldamp::harness
