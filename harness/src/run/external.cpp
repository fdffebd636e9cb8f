#include "run/external.hpp"

#include "common/observables.hpp"
#include "run/answers.hpp"

#include "pldamp/core/domain.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

namespace pldamp::harness {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

// A line from the program, quoted in a message: one line, at most 100 characters.
std::string quote_line(std::string_view line) {
  return "'" + one_line(line, 100) + "'";
}

// A text the program said, kept (in a record, a report): one line, at most max_reply_text.
std::string kept(std::string_view text) {
  return one_line(text, max_reply_text);
}

constexpr std::chrono::milliseconds handshake_limit{30000};

// A run stopped by SIGINT or SIGTERM while it waited for the program. The program, in a process
// group of its own, does not get a terminal's Ctrl-C: pldamp stops it.
constexpr const char* stopped_by_signal = "pldamp was stopped by a signal; the program was stopped";

// nlohmann's DOM parser with what the protocol asks on top, as SAX: at most max_reply_depth levels
// (its dump, and a tree's use, recurse: a reply nested 10^5 deep overflowed the stack) and no key
// twice in an object (the last one won: an "id" twice answered another problem). Linear, where
// nlohmann's callback parser scans the parent at every object's end (a reply of 340 000 {} took
// 24 s).
class ReplySax : public nlohmann::detail::json_sax_dom_parser<json> {
  using Dom = nlohmann::detail::json_sax_dom_parser<json>;

public:
  explicit ReplySax(json& into) : Dom(into, false) {}
  std::string problem; // why it stopped early: nested too deep, or a key named twice
  bool start_object(std::size_t elements) {
    keys_.emplace_back();
    return enter() && Dom::start_object(elements);
  }
  bool end_object() {
    keys_.pop_back();
    --depth_;
    return Dom::end_object();
  }
  bool start_array(std::size_t elements) { return enter() && Dom::start_array(elements); }
  bool end_array() {
    --depth_;
    return Dom::end_array();
  }
  bool key(json::string_t& name) {
    if (!keys_.back().insert(name).second) {
      problem = "names " + one_line(name, 40) + " twice";
      return false;
    }
    return Dom::key(name);
  }

private:
  bool enter() {
    if (++depth_ > max_reply_depth) {
      problem = fmt::format("nests JSON deeper than {} levels", max_reply_depth);
      return false;
    }
    return true;
  }
  int depth_ = 0;
  std::vector<std::set<std::string>> keys_;
};

// A line of the program's as JSON, read as ReplySax reads it; discarded when it is not JSON (or
// holds a NUL, where nlohmann's parser would stop); throws std::runtime_error naming `what` when
// it nests too deep or names a key twice.
json parse_line(const std::string& line, const std::string& what) {
  json parsed;
  if (line.find('\0') != std::string::npos) {
    return json(json::value_t::discarded);
  }
  ReplySax sax(parsed);
  if (!json::sax_parse(line, &sax) || sax.is_errored()) {
    if (!sax.problem.empty()) {
      throw std::runtime_error(fmt::format("{} {} (got {})", what, sax.problem, quote_line(line)));
    }
    return json(json::value_t::discarded);
  }
  return parsed;
}

// A list of the handshake's, at most max_reply_items long.
template <class Item>
std::vector<Item> bounded_list(const json& list, const std::string& who, const char* key) {
  if (list.is_array() && list.size() > max_reply_items) {
    throw ProtocolError(fmt::format("{}: its handshake's {} lists {} items, more than {}", who, key,
                                    list.size(), max_reply_items));
  }
  return list.get<std::vector<Item>>();
}

// A measured value of the reply: absent, a number (whatever its sign: impossible values are
// judged by impossible_answer, the exchange is still in step), or "inf" where `infinite_ok`.
std::optional<double> reply_value(const json& reply, const char* key, bool infinite_ok) {
  const auto found = reply.find(key);
  if (found == reply.end() || found->is_null()) {
    return std::nullopt;
  }
  if (found->is_string() && infinite_ok && found->get<std::string>() == "inf") {
    return std::numeric_limits<double>::infinity();
  }
  if (!found->is_number()) {
    throw std::runtime_error(
        fmt::format("the reply's {} is not a number (got {})", key, quote_line(found->dump())));
  }
  return found->get<double>();
}

// A number of the reply's work (steps, rhs_evals, wall_seconds): absent, or a finite number >= 0.
std::optional<double> reply_number(const json& reply, const char* key) {
  const std::optional<double> value = reply_value(reply, key, false);
  if (value && !(std::isfinite(*value) && *value >= 0)) {
    throw std::runtime_error(
        fmt::format("the reply's {} must be a finite number >= 0 (got {})", key, *value));
  }
  return value;
}

long reply_count(const json& reply, const char* key) {
  const std::optional<double> value = reply_number(reply, key);
  if (value && (*value != std::floor(*value) || *value > max_reply_count)) {
    throw std::runtime_error(fmt::format(
        "the reply's {} must be a whole number up to {:g} (got {})", key, max_reply_count, *value));
  }
  return value ? static_cast<long>(*value) : 0;
}

} // namespace

ExternalFacts read_handshake(const std::string& line, const std::string& who) {
  json hello;
  try {
    hello = parse_line(line, who + ": its handshake");
  } catch (const std::runtime_error& e) {
    throw ProtocolError(e.what());
  }
  if (hello.is_discarded()) {
    throw ProtocolError(who + ": its handshake is not JSON (got " + quote_line(line) + ")");
  }
  if (!hello.is_object()) {
    throw ProtocolError(who + ": its handshake is not a JSON object (got " + quote_line(line) +
                        ")");
  }
  const auto protocol = hello.find("protocol");
  const auto version = hello.find("version");
  if (protocol == hello.end() || *protocol != protocol_name || version == hello.end() ||
      !version->is_number_integer() || *version != protocol_version) {
    throw ProtocolError(fmt::format("{}: speaks another protocol; pldamp speaks {} version {} "
                                    "(got {})",
                                    who, protocol_name, protocol_version, quote_line(line)));
  }
  ExternalFacts facts;
  try {
    facts.solver = kept(hello.at("solver").get<std::string>());
    if (facts.solver.empty()) {
      throw ProtocolError(who + ": its handshake's solver names nothing (got " + quote_line(line) +
                          ")");
    }
    // β in [0, p] at every p the domain has (p <= 1000): a β of 1e10 reached every problem as
    // "alpha must be finite (got nan)".
    if (const auto beta = hello.find("damping_exponent"); beta != hello.end()) {
      const double most = domain::p_max;
      if (beta->is_number()) {
        facts.damping_exponent = beta->get<double>();
        if (!(*facts.damping_exponent >= 0 && *facts.damping_exponent <= most)) {
          throw ProtocolError(fmt::format("{}: damping_exponent must be a number in [0, {:g}] or "
                                          "\"seed\" (got {})",
                                          who, most, quote_line(beta->dump())));
        }
      } else if (*beta != "seed") {
        throw ProtocolError(fmt::format("{}: damping_exponent must be a number in [0, {:g}] or "
                                        "\"seed\" (got {})",
                                        who, most, quote_line(beta->dump())));
      }
    }
    // A list given names something: "p": [] read as any p, "ends": [] as none.
    const auto nonempty = [&](const json& list, const char* key) {
      if (list.is_array() && list.empty()) {
        throw ProtocolError(fmt::format("{}: its handshake's {} is an empty list (leave it out "
                                        "for the default)",
                                        who, key));
      }
    };
    if (const auto p = hello.find("p"); p != hello.end()) {
      nonempty(*p, "p");
      facts.exponents = bounded_list<double>(*p, who, "p");
    }
    facts.ends = {solvers::End::overlap, solvers::End::force};
    if (const auto ends = hello.find("ends"); ends != hello.end()) {
      nonempty(*ends, "ends");
      facts.ends.clear();
      for (const std::string& name : bounded_list<std::string>(*ends, who, "ends")) {
        const std::optional<solvers::End> end = value_named(contact_ends, name);
        if (!end) {
          throw ProtocolError(who + ": unknown contact end in its handshake (got " +
                              quote_line(name) + ")");
        }
        facts.ends.push_back(*end);
      }
    }
    if (const auto honours = hello.find("honours"); honours != hello.end()) {
      facts.honours = bounded_list<std::string>(*honours, who, "honours");
      for (std::string& setting : *facts.honours) {
        // The settings a problem carries (answers.hpp, settings_not_honoured): a word beside
        // them would say nothing the check could hold the program to.
        const bool known = setting == "steps_per_contact" || setting == "dt" ||
                           setting == "onset_phase" || setting == "rtol" || setting == "atol" ||
                           (setting.starts_with("options.") && setting.size() > 8);
        if (!known) {
          throw ProtocolError(who +
                              ": unknown setting in its handshake's honours, expected "
                              "steps_per_contact|dt|onset_phase|rtol|atol|options.KEY (got " +
                              quote_line(setting) + ")");
        }
        setting = kept(setting);
      }
    }
    if (const auto unavailable = hello.find("unavailable"); unavailable != hello.end()) {
      facts.unavailable = kept(unavailable->get<std::string>());
      if (facts.unavailable.empty()) {
        facts.unavailable = "(no reason given)";
      }
    }
  } catch (const json::exception&) {
    throw ProtocolError(who +
                        ": its handshake has a key of the wrong type or lacks `solver` (got " +
                        quote_line(line) + ")");
  }
  return facts;
}

bool ExternalFacts::seed_damping(double p) const {
  return !damping_exponent || std::abs(*damping_exponent - (p - 1) / 2) <= 1e-15;
}

std::string ExternalFacts::describe() const {
  std::string out = one_line(solver);
  if (damping_exponent) {
    out += fmt::format("; damping exponent {:g}", *damping_exponent);
  }
  if (honours) {
    out +=
        "; honours " + (honours->empty() ? std::string("no setting")
                                         : one_line(fmt::format("{}", fmt::join(*honours, ", "))));
  }
  if (!unavailable.empty()) {
    out += "; unavailable: " + one_line(unavailable);
  }
  return out;
}

void ExternalFacts::require_honoured(const SolverConfig& config) const {
  if (!honours || !unavailable.empty()) {
    return;
  }
  const std::vector<std::string> ignored = settings_not_honoured(config, *honours);
  if (!ignored.empty()) {
    throw ProtocolError(fmt::format(
        "[[solver]] {} ({}): sets {}, which its program does not honour (its handshake honours "
        "{}): remove the setting from the scene, or teach the program it",
        config.name, config.label(), fmt::join(ignored, ", "),
        honours->empty() ? std::string("none") : fmt::format("{}", fmt::join(*honours, ", "))));
  }
}

ExternalSolver::ExternalSolver(const SolverConfig& config, double limit_seconds,
                               const std::atomic<bool>* stop)
    : config_(config), options_(config.options.empty() ? ordered_json::object()
                                                       : ordered_json::parse(config.options)),
      limit_(std::chrono::milliseconds(std::llround(limit_seconds * 1000))), stop_(stop) {
  start();
}

ExternalSolver::~ExternalSolver() {
  if (program_) {
    program_->finish();
  }
}

void ExternalSolver::start() {
  const std::string who = "[[solver]] " + config_.name;
  program_ = std::make_unique<LineProgram>(config_.command, stop_);
  if (!program_->started()) {
    program_.reset();
    // Named as the scene typed it, and where it was looked for.
    const std::string& typed = config_.program.empty() ? config_.command.front() : config_.program;
    const std::string& resolved = config_.command.front();
    const std::string why =
        typed != resolved ? "from the scene's folder: " + resolved + ", not found or not executable"
        : typed.find('/') == std::string::npos
            ? "not beside the scene nor on PATH, or not executable"
            : "not found or not executable";
    throw ProtocolError(who + ": cannot start " + typed + " (" + why + ")");
  }
  std::string line;
  // Starting a code (an interpreter, a simulation library) may take longer than one problem.
  const std::chrono::milliseconds limit = std::max(limit_, handshake_limit);
  switch (program_->write_line(
      ordered_json{{"protocol", protocol_name}, {"version", protocol_version}}.dump(), limit)) {
  case LineProgram::Write::done:
    break;
  case LineProgram::Write::timeout:
    stop_program();
    throw ProtocolError(fmt::format("{}: did not read pldamp's handshake within {} s", who,
                                    double(limit.count()) / 1000));
  case LineProgram::Write::closed:
    throw ProtocolError(who + ": " + why_stopped(""));
  case LineProgram::Write::stopped:
    stop_program();
    throw ProtocolError(who + ": " + stopped_by_signal);
  }
  switch (program_->read_line(line, limit)) {
  case LineProgram::Read::line:
    break;
  case LineProgram::Read::timeout:
    stop_program();
    throw ProtocolError(
        fmt::format("{}: no handshake within {} s", who, double(limit.count()) / 1000));
  case LineProgram::Read::too_long:
    stop_program();
    throw ProtocolError(who + ": its handshake is longer than 1 MiB");
  case LineProgram::Read::end:
    throw ProtocolError(who + ": " + why_stopped(line) + " before its handshake");
  case LineProgram::Read::stopped:
    stop_program();
    throw ProtocolError(who + ": " + stopped_by_signal);
  }
  facts_ = read_handshake(line, who);
}

void ExternalSolver::stop_program() {
  if (program_) {
    program_->finish(std::chrono::milliseconds(0));
    program_.reset();
  }
}

std::string ExternalSolver::why_stopped(const std::string& partial) {
  program_->finish();
  std::string out = "the program " + program_->status();
  if (!partial.empty()) {
    out += " in the middle of a line (" + quote_line(partial) + ")";
  }
  if (const std::string error = program_->last_error_line(); !error.empty()) {
    out += "; its last words on stderr: " + quote_line(error);
  }
  program_.reset();
  return out;
}

std::string ExternalSolver::problem_line(const SolverConfig& config,
                                         const solvers::Problem<double>& problem,
                                         const solvers::Options<double>& options, long id) const {
  ordered_json line{{"id", id},
                    {"p", problem.p},
                    {"m", problem.m},
                    {"k", problem.k},
                    {"v0", problem.v0},
                    {"alpha", problem.alpha},
                    {"damping_exponent", facts_.beta(problem.p)},
                    {"end", name_of(contact_ends, options.end)}};
  ordered_json want = ordered_json::array();
  for (const Observable* observable : observables_of(options.want)) {
    want.push_back(observable->key);
  }
  line["want"] = want;
  if (const std::optional<double> dt = step_of(config, problem)) {
    if (config.steps_per_contact) {
      line["steps_per_contact"] = *config.steps_per_contact;
    }
    line["dt"] = *dt;
    line["onset_phase"] = options.onset_phase;
  }
  if (config.rtol) {
    line["rtol"] = *config.rtol;
  }
  if (config.atol) {
    line["atol"] = *config.atol;
  }
  line["options"] = options_;
  return line.dump();
}

solvers::Result<double> read_reply(const std::string& line, long id) {
  const json reply = parse_line(line, "the reply");
  if (reply.is_discarded()) {
    throw std::runtime_error("the reply is not JSON (got " + quote_line(line) + ")");
  }
  if (!reply.is_object()) {
    throw std::runtime_error("the reply is not a JSON object (got " + quote_line(line) + ")");
  }
  const auto reply_id = reply.find("id");
  if (reply_id == reply.end() || !reply_id->is_number_integer() || *reply_id != id) {
    throw std::runtime_error(
        fmt::format("the reply is for another problem: id {} expected (got {})", id,
                    reply_id == reply.end() ? "none" : quote_line(reply_id->dump())));
  }
  const auto outcome = reply.find("outcome");
  if (outcome == reply.end() || !outcome->is_string()) {
    throw std::runtime_error("the reply has no outcome (got " + quote_line(line) + ")");
  }
  const std::string name = outcome->get<std::string>();
  const auto reason = [&] {
    const auto found = reply.find("reason");
    return found != reply.end() && found->is_string() ? kept(found->get<std::string>())
                                                      : std::string("no reason given");
  };
  if (name == "unsupported") {
    throw Skipped("unsupported: " + reason());
  }
  if (name == "error") {
    throw ReportedError("the program's error: " + reason());
  }
  const std::optional<solvers::Outcome> known = solvers::outcome_named(name);
  if (!known) {
    throw std::runtime_error("unknown outcome " + quote_line(name) +
                             ", expected exited|peak|no_exit|step_limit|time_limit|unstable|"
                             "unsupported|error");
  }
  solvers::Result<double> result;
  result.outcome = *known;
  result.e = reply_value(reply, "e", false);
  result.delta_max = reply_value(reply, "delta_max", false);
  result.t_peak = reply_value(reply, "t_peak", false);
  result.tau = reply_value(reply, "tau", true);
  result.energy_load = reply_value(reply, "energy_load", false);
  result.energy_unload = reply_value(reply, "energy_unload", false);
  result.normal_force_max = reply_value(reply, "normal_force_max", false);
  result.t_normal_force_max = reply_value(reply, "t_normal_force_max", false);
  result.steps = reply_count(reply, "steps");
  result.rhs_evals = reply_count(reply, "rhs_evals");
  result.wall_seconds = reply_number(reply, "wall_seconds").value_or(0);
  if (*known == solvers::Outcome::unstable) {
    result.invariant = "the program says unstable: " + reason();
  }
  return result;
}

solvers::Result<double> ExternalSolver::solve(const SolverConfig& config,
                                              const solvers::Problem<double>& problem,
                                              const solvers::Options<double>& options) {
  if (!facts_.unavailable.empty()) {
    throw Skipped("unavailable: " + one_line(facts_.unavailable));
  }
  if (!facts_.exponents.empty() && std::find(facts_.exponents.begin(), facts_.exponents.end(),
                                             problem.p) == facts_.exponents.end()) {
    throw Skipped(fmt::format("it runs p = {} only", fmt::join(facts_.exponents, ", ")));
  }
  if (std::find(facts_.ends.begin(), facts_.ends.end(), options.end) == facts_.ends.end()) {
    throw Skipped(fmt::format("it has no {} end", name_of(contact_ends, options.end)));
  }
  const std::lock_guard lock(busy_);
  if (!dead_.empty()) {
    throw std::runtime_error(dead_);
  }
  if (!program_) {
    try {
      start();
    } catch (const ProtocolError& e) {
      dead_ = std::string("could not be restarted: ") + e.what();
      throw std::runtime_error(dead_);
    }
  }
  const long id = next_id_++;
  const auto sent = std::chrono::steady_clock::now();
  switch (program_->write_line(problem_line(config, problem, options, id), limit_)) {
  case LineProgram::Write::done:
    break;
  case LineProgram::Write::timeout: // it does not read: not in step any more
    stop_program();
    throw std::runtime_error(fmt::format("the program did not read the problem within {} s "
                                         "([limits] max_seconds); the program was stopped",
                                         double(limit_.count()) / 1000));
  case LineProgram::Write::closed:
    throw std::runtime_error(why_stopped(""));
  case LineProgram::Write::stopped:
    stop_program();
    throw std::runtime_error(stopped_by_signal);
  }
  std::string line;
  switch (program_->read_line(line, limit_)) {
  case LineProgram::Read::line:
    break;
  case LineProgram::Read::timeout:
    stop_program();
    throw std::runtime_error(fmt::format("no reply within {} s ([limits] max_seconds); the "
                                         "program was stopped",
                                         double(limit_.count()) / 1000));
  case LineProgram::Read::too_long:
    stop_program();
    throw std::runtime_error("a reply longer than 1 MiB; the program was stopped");
  case LineProgram::Read::end:
    throw std::runtime_error(why_stopped(line));
  case LineProgram::Read::stopped:
    stop_program();
    throw std::runtime_error(stopped_by_signal);
  }
  const double round_trip =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
  try {
    solvers::Result<double> result = read_reply(line, id);
    if (result.wall_seconds == 0) {
      result.wall_seconds = round_trip;
    } else if (result.wall_seconds > round_trip + 1) { // its clock's grain and ours aside
      throw ReportedError(fmt::format("the reply's wall_seconds {} is longer than its round "
                                      "trip, {:.3g} s",
                                      result.wall_seconds, round_trip));
    }
    result.fixed_step = step_of(config, problem);
    if (result.outcome != solvers::Outcome::unstable) {
      // Held to the invariants of pldamp's own solvers: an impossible answer is unstable, with
      // nothing measured kept (as BasicCollision::finish does).
      if (const std::string why = impossible_answer(result, config, problem, options);
          !why.empty()) {
        result.outcome = solvers::Outcome::unstable;
        result.invariant = "impossible answer: " + why;
        result.e = result.delta_max = result.t_peak = result.tau = result.energy_load =
            result.energy_unload = std::nullopt;
      }
    }
    return result;
  } catch (const Skipped&) {
    throw;
  } catch (const ReportedError&) {
    throw;
  } catch (const std::runtime_error&) {
    // After a reply it cannot read, pldamp no longer trusts the exchange to be in step.
    stop_program();
    throw;
  }
}

} // namespace pldamp::harness
