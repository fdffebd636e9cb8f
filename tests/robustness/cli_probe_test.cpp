// Robustness (ctest label robustness): the `pldamp` command line probed with extreme, malformed and
// hostile input, a table of cases each with the class of answer it must get:
//
//   ok             exit 0; with --json one JSON object on stdout, every number finite, e and e_cap
//                  in [0, 1] (to the solve's accuracy: 1 + 1e-6), delta_max >= 0, tau and t_peak >
//                  0 or null; for `solve` the outcome "exited" or "peak" ("no_exit" only where the
//                  case says critical/overdamped)
//   refused        exit 2, stdout empty, stderr one line "error: ..." (scenes: "path:line: ...")
//                  with no other control character and no "internal", "terminate", "what()", "nan"
//   outcome(set)   exit 0, JSON "outcome" in the set; e and delta_max checked as for ok when there;
//                  a few cases also accept a refusal (outcome_or_refused)
//   ok_or_refused  either, for input at the edge of the documented domain (each says why)
//   judged_failing exit 1, stderr empty, the verdict on stdout (`check --tolerance` beyond it):
//                  with --json one JSON object whose "passed" is false
//
// and for every case: exit code 0, 1 or 2 (a crash, an abort or exit 3 is a bug), never "internal"
// on stderr, and an answer within 20 s of wall time.
//
// Each case runs the CLI in-process (testing::run, as the harness tests do) inside a forked child
// of this test: a case that crashes, aborts or hangs is reported as that case's failure (its
// signal, or the time at which it was stopped) instead of taking the whole table down with it.
// What the child writes to file descriptors 1 and 2 outside the streams (a library printing
// directly) is appended to what the case saw on stdout and stderr: it is what a user sees.
// PLDAMP_PROBE_IN_PROCESS=1 runs the cases without the fork (for a debugger);
// PLDAMP_PROBE_VERBOSE=1 prints every case's exit code, time and first line.
//
// "nan" on stderr: a refusal may echo what the user typed ("--p nan ... (got nan)"), so the word
// may appear on stderr as often as it appears in the case's own input (arguments and files), never
// more: a NaN the program computed is a bug.
#include "harness/cli_run.hpp"
#include "harness/fixtures.hpp"

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace pldamp::robustness {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// The classes of answer.

enum class Class { ok, refused, outcome, ok_or_refused, judged_failing };

struct Expect {
  Class cls = Class::ok;
  std::vector<std::string> outcomes; // Class::outcome
  bool or_refused = false;           // Class::outcome: a refusal is right too
  bool no_exit = false;              // ok, solve: critical or overdamped, "no_exit" is right too
};

Expect ok() {
  return {Class::ok, {}, false, false};
}
// A contact that does not return (alpha_eff >= 1 at the overlap end): "no_exit" is honest.
Expect ok_no_exit() {
  return {Class::ok, {}, false, true};
}
Expect refused() {
  return {Class::refused, {}, false, false};
}
Expect outcome(std::vector<std::string> set) {
  return {Class::outcome, std::move(set), false, false};
}
Expect outcome_or_refused(std::vector<std::string> set) {
  return {Class::outcome, std::move(set), true, false};
}
Expect ok_or_refused() {
  return {Class::ok_or_refused, {}, false, false};
}
Expect judged_failing() {
  return {Class::judged_failing, {}, false, false};
}

std::string describe(const Expect& x) {
  switch (x.cls) {
  case Class::ok:
    return x.no_exit ? "ok (no_exit allowed: critical/overdamped)" : "ok";
  case Class::refused:
    return "refused";
  case Class::ok_or_refused:
    return "ok_or_refused";
  case Class::judged_failing:
    return "judged_failing";
  case Class::outcome:
    break;
  }
  std::string set;
  for (const std::string& o : x.outcomes) {
    set += (set.empty() ? "" : ",") + o;
  }
  return "outcome{" + set + "}" + (x.or_refused ? " or refused" : "");
}

// What a case saw.
struct Seen {
  int code = -1; // the exit code; 128 + N for a child killed by signal N
  std::string out, err;
  double seconds = 0;
  bool killed = false; // stopped by the probe at its time limit
  int signal = 0;
};

// The directory of a case: written by its setup, "{dir}" in its arguments.
using Setup = std::function<std::string(const fs::path& dir)>; // "" or why not
using Extra =
    std::function<std::string(const Seen& seen, const fs::path& dir)>; // "" or what's wrong

struct Case {
  std::string name;
  std::vector<std::string> args;
  Expect expect;
  Setup setup;
  Extra extra;
  double limit = 20; // seconds of wall time
};

// ---------------------------------------------------------------------------------------------
// Text helpers.

std::string escaped(const std::string& s, std::size_t keep = 240) {
  std::string out;
  const std::size_t n = std::min(s.size(), keep);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    switch (c) {
    case '\n':
      out += "\\n";
      break;
    case '\t':
      out += "\\t";
      break;
    case '\r':
      out += "\\r";
      break;
    case '\\':
      out += "\\\\";
      break;
    case '"':
      out += "\\\"";
      break;
    default:
      if (c < 0x20 || c >= 0x7f) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02x", c);
        out += hex;
      } else {
        out += static_cast<char>(c);
      }
    }
  }
  if (s.size() > keep) {
    out += "...(" + std::to_string(s.size()) + " bytes)";
  }
  return out;
}

std::string command_line(const std::vector<std::string>& args) {
  std::string line = "pldamp";
  for (const std::string& a : args) {
    const bool plain = !a.empty() && std::all_of(a.begin(), a.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("-+._/=,:{}", c);
    });
    line += ' ';
    if (plain) {
      line += escaped(a, 120);
    } else {
      line += '"';
      line += escaped(a, 120);
      line += '"';
    }
  }
  return line;
}

std::string first_line(const std::string& s) {
  return s.substr(0, s.find('\n'));
}

std::string lower(std::string s) {
  for (char& c : s) {
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return s;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// Occurrences of `word` (lower case) not inside a longer word, case-insensitively.
int count_word(const std::string& text, const std::string& word) {
  const std::string s = lower(text);
  int n = 0;
  for (std::size_t at = s.find(word); at != std::string::npos; at = s.find(word, at + 1)) {
    const bool before = at > 0 && std::isalpha(static_cast<unsigned char>(s[at - 1]));
    const std::size_t end = at + word.size();
    const bool after = end < s.size() && std::isalpha(static_cast<unsigned char>(s[end]));
    if (!before && !after) {
      ++n;
    }
  }
  return n;
}

std::string substitute(std::string s, const std::string& dir) {
  for (std::size_t at = s.find("{dir}"); at != std::string::npos; at = s.find("{dir}", at)) {
    s.replace(at, 5, dir);
    at += dir.size();
  }
  return s;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

bool write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  return static_cast<bool>(out);
}

std::string sanitize_name(const std::string& raw) {
  std::string name;
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const char c = raw[i];
    const bool word = std::isalnum(static_cast<unsigned char>(c)) != 0;
    // a minus sign starting a value ("jobs_-1", "alpha_-0") is "neg", not lost
    const bool sign = c == '-' && (name.empty() || name.back() == '_') && i + 1 < raw.size() &&
                      (std::isdigit(static_cast<unsigned char>(raw[i + 1])) || raw[i + 1] == '.' ||
                       raw[i + 1] == 'i');
    if (sign) {
      name += "neg";
    } else if (word) {
      name += c;
    } else if (!name.empty() && name.back() != '_') {
      name += '_';
    }
  }
  while (!name.empty() && name.back() == '_') {
    name.pop_back();
  }
  return name.empty() ? "empty" : name;
}

// ---------------------------------------------------------------------------------------------
// Running a case: a forked child calls testing::run; the parent keeps the time.

void read_all(int fd, std::string& into) {
  char buffer[65536];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) {
    into.append(buffer, static_cast<std::size_t>(n));
  }
}

bool write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n <= 0) {
      return false;
    }
    data += n;
    size -= static_cast<std::size_t>(n);
  }
  return true;
}

void put_u64(std::string& frame, std::uint64_t v) {
  frame.append(reinterpret_cast<const char*>(&v), sizeof v);
}

std::uint64_t get_u64(const std::string& frame, std::size_t& at) {
  std::uint64_t v = 0;
  if (at + sizeof v <= frame.size()) {
    std::memcpy(&v, frame.data() + at, sizeof v);
  }
  at += sizeof v;
  return v;
}

Seen run_in_process(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  const harness::testing::CliRun r = harness::testing::run(args);
  Seen seen{r.code, r.out, r.err, 0, false, 0};
  seen.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return seen;
}

Seen run_isolated(const std::vector<std::string>& args, double kill_after) {
  if (const char* in_process = std::getenv("PLDAMP_PROBE_IN_PROCESS");
      in_process != nullptr && std::string(in_process) == "1") {
    return run_in_process(args);
  }
  Seen seen;
  // Direct writes to fd 1 and 2 go to two unlinked temporary files.
  char out_name[] = "/tmp/pldamp-probe-fd1-XXXXXX";
  char err_name[] = "/tmp/pldamp-probe-fd2-XXXXXX";
  const int out_fd = ::mkstemp(out_name);
  const int err_fd = ::mkstemp(err_name);
  if (out_fd < 0 || err_fd < 0) {
    seen.err = "probe: mkstemp failed";
    return seen;
  }
  ::unlink(out_name);
  ::unlink(err_name);
  int result[2];
  if (::pipe(result) != 0) {
    seen.err = "probe: pipe failed";
    return seen;
  }
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(result[0]);
    ::dup2(out_fd, STDOUT_FILENO);
    ::dup2(err_fd, STDERR_FILENO);
    const harness::testing::CliRun r = harness::testing::run(args);
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    std::string frame;
    put_u64(frame, static_cast<std::uint64_t>(static_cast<std::int64_t>(r.code)));
    put_u64(frame, r.out.size());
    frame += r.out;
    put_u64(frame, r.err.size());
    frame += r.err;
    write_all(result[1], frame.data(), frame.size());
    ::_exit(0);
  }
  ::close(result[1]);
  if (pid < 0) {
    ::close(result[0]);
    seen.err = "probe: fork failed";
    return seen;
  }
  // Read the frame until the child closes its end, or stop the child at the deadline.
  std::string frame;
  const auto deadline = start + std::chrono::duration<double>(kill_after);
  bool open = true;
  while (open) {
    const double left =
        std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      ::kill(pid, SIGKILL);
      seen.killed = true;
      break;
    }
    pollfd p{result[0], POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min(left * 1000 + 1, 1000.0)));
    if (ready > 0) {
      char buffer[65536];
      const ssize_t n = ::read(result[0], buffer, sizeof buffer);
      if (n > 0) {
        frame.append(buffer, static_cast<std::size_t>(n));
      } else {
        open = false;
      }
    }
  }
  ::close(result[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  seen.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string direct_out, direct_err;
  ::lseek(out_fd, 0, SEEK_SET);
  ::lseek(err_fd, 0, SEEK_SET);
  read_all(out_fd, direct_out);
  read_all(err_fd, direct_err);
  ::close(out_fd);
  ::close(err_fd);
  std::size_t at = 0;
  const std::uint64_t code = get_u64(frame, at);
  const std::uint64_t out_size = get_u64(frame, at);
  const bool complete_out = at + out_size <= frame.size();
  if (complete_out) {
    seen.out = frame.substr(at, out_size);
    at += out_size;
  }
  const std::uint64_t err_size = get_u64(frame, at);
  const bool complete = complete_out && at + err_size <= frame.size();
  if (complete) {
    seen.err = frame.substr(at, err_size);
  }
  seen.out += direct_out;
  seen.err += direct_err;
  if (WIFSIGNALED(status)) {
    seen.signal = WTERMSIG(status);
    seen.code = 128 + seen.signal;
  } else if (complete) {
    seen.code = static_cast<int>(static_cast<std::int64_t>(code));
  } else {
    seen.code = -1; // the child exited without answering (exit() inside the library?)
  }
  return seen;
}

// ---------------------------------------------------------------------------------------------
// JSON answers: the document, and the raw text of each top-level number (e_cap to 1e-30).

class RawNumbers : public nlohmann::json_sax<json> {
public:
  std::map<std::string, std::string> raw; // top-level key -> number as written

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t v) override { return number(std::to_string(v)); }
  bool number_unsigned(number_unsigned_t v) override { return number(std::to_string(v)); }
  bool number_float(number_float_t, const string_t& s) override { return number(s); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override {
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    if (depth_ == 1) {
      key_ = k;
    }
    return true;
  }
  bool end_object() override {
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    ++depth_;
    return true;
  }
  bool end_array() override {
    --depth_;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

private:
  bool value() { return true; }
  bool number(const std::string& s) {
    if (depth_ == 1) {
      raw[key_] = s;
    }
    return true;
  }
  int depth_ = 0;
  std::string key_;
};

// A number of 50-digit or quad precision may lie beyond double's range (tau = 1e+19295196 just
// below critical damping): finite, and valid JSON. Such a number is read as +-1e308, so the range
// checks still judge it; "inf" and "nan" are not JSON and fail the parse.
std::string clamp_huge_numbers(const std::string& text) {
  std::string out;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      out += c;
      if (c == '\\' && i + 1 < text.size()) {
        out += text[++i];
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
      out += c;
      continue;
    }
    if (c == '-' || std::isdigit(static_cast<unsigned char>(c))) {
      std::size_t end = i;
      while (end < text.size() && std::strchr("+-0123456789.eE", text[end]) != nullptr &&
             text[end] != '\0') {
        ++end;
      }
      const std::string token = text.substr(i, end - i);
      const double value = std::strtod(token.c_str(), nullptr);
      out += std::isinf(value) ? (value > 0 ? "1e308" : "-1e308") : token;
      i = end - 1;
      continue;
    }
    out += c;
  }
  return out;
}

std::optional<json> parse_json(const std::string& text, std::string& problem) {
  try {
    json j = json::parse(clamp_huge_numbers(text));
    if (!j.is_object()) {
      problem = "stdout is JSON but not one object";
      return std::nullopt;
    }
    return j;
  } catch (const std::exception& e) {
    problem = std::string("stdout is not one JSON object: ") + e.what();
    return std::nullopt;
  }
}

std::map<std::string, std::string> raw_numbers(const std::string& text) {
  RawNumbers sax;
  json::sax_parse(clamp_huge_numbers(text), &sax);
  return sax.raw;
}

// Every number finite, anywhere in the document.
std::string non_finite_in(const json& j, const std::string& where) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    return where + " is not finite";
  }
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      if (std::string p = non_finite_in(value, where + "." + key); !p.empty()) {
        return p;
      }
    }
  }
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (std::string p = non_finite_in(j[i], where + "[" + std::to_string(i) + "]"); !p.empty()) {
        return p;
      }
    }
  }
  return "";
}

// The checks of a JSON answer common to ok and outcome(set).
std::string check_answer_numbers(const json& j) {
  if (std::string p = non_finite_in(j, "$"); !p.empty()) {
    return p;
  }
  // e ≤ 1 within the solve's own accuracy: undamped, an error-controlled solve at rtol 1e-8
  // measures e = 1 + 8e-9 (the solvers' invariant allows min(1e4 rtol, √rtol); beyond it the
  // answer is `unstable`). 1e-6 covers every tolerance these cases ask for.
  // `check` answers each observable as an object: its measured "value" is what is judged here.
  const auto value_of = [&](const char* key) -> const json& {
    const json& v = j.at(key);
    return v.is_object() && v.contains("value") ? v.at("value") : v;
  };
  for (const char* key : {"e", "e_cap"}) {
    if (j.contains(key)) {
      const json& v = value_of(key);
      if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= 1 + 1e-6)) {
        return std::string("\"") + key + "\" = " + v.dump() + " is not in [0, 1 + 1e-6]";
      }
    }
  }
  if (j.contains("delta_max")) {
    const json& v = value_of("delta_max");
    if (!v.is_number() || !(v.get<double>() >= 0)) {
      return "\"delta_max\" = " + v.dump() + " is not >= 0";
    }
  }
  for (const char* key : {"tau", "t_peak"}) {
    if (j.contains(key)) {
      const json& v = value_of(key);
      if (!v.is_null() && (!v.is_number() || !(v.get<double>() > 0))) {
        return std::string("\"") + key + "\" = " + v.dump() + " is neither > 0 nor null";
      }
    }
  }
  return "";
}

bool is_solve(const std::vector<std::string>& args) {
  return !args.empty() && args.front() == "solve";
}
bool wants_json(const std::vector<std::string>& args) {
  return std::find(args.begin(), args.end(), "--json") != args.end();
}

// ---------------------------------------------------------------------------------------------
// The checkers: each returns "" or what is wrong.

std::string check_ok(const Case& c, const std::vector<std::string>& args, const Seen& seen) {
  if (seen.code != 0) {
    return "expected exit 0";
  }
  if (!wants_json(args)) {
    if (seen.out.empty()) {
      return "stdout is empty";
    }
    if (count_word(seen.out, "nan") > 0) {
      return "stdout shows a nan";
    }
    return "";
  }
  std::string problem;
  const std::optional<json> j = parse_json(seen.out, problem);
  if (!j) {
    return problem;
  }
  if (std::string p = check_answer_numbers(*j); !p.empty()) {
    return p;
  }
  if (is_solve(args)) {
    const std::string got = j->value("outcome", std::string("(none)"));
    const bool fine = got == "exited" || got == "peak" || (c.expect.no_exit && got == "no_exit");
    if (!fine) {
      return "outcome \"" + got + "\" is not " +
             (c.expect.no_exit ? "exited, peak or no_exit" : "exited or peak");
    }
  }
  return "";
}

std::string check_refused(const std::vector<std::string>& args, const Seen& seen,
                          int nan_in_input) {
  if (seen.code != 2) {
    return "expected exit 2";
  }
  if (!seen.out.empty()) {
    return "stdout is not empty";
  }
  const std::string& err = seen.err;
  if (err.empty() || err.back() != '\n' || std::count(err.begin(), err.end(), '\n') != 1) {
    return "stderr is not exactly one line ending in \\n";
  }
  const bool scene_prefix = [&] {
    // "<path>:<line>: " (the path as the program prints it, escaped or not)
    for (std::size_t at = err.find(':'); at != std::string::npos; at = err.find(':', at + 1)) {
      std::size_t i = at + 1;
      while (i < err.size() && std::isdigit(static_cast<unsigned char>(err[i]))) {
        ++i;
      }
      if (i > at + 1 && i + 1 < err.size() && err[i] == ':' && err[i + 1] == ' ') {
        return true; // an empty path gives ":0: ..."
      }
    }
    return false;
  }();
  const bool scene_command = !args.empty() && args.front() == "run";
  if (err.rfind("error: ", 0) != 0 && !(scene_command && scene_prefix)) {
    return scene_command ? "stderr begins with neither \"error: \" nor \"<path>:<line>: \""
                         : "stderr does not begin with \"error: \"";
  }
  if (scene_command && args.size() > 1 && !args[1].empty()) {
    const std::size_t first = err.find(args[1] + ":");
    if (first != std::string::npos && err.find(args[1] + ":", first + 1) != std::string::npos) {
      return "stderr names the scene's path twice";
    }
  }
  for (std::size_t i = 0; i + 1 < err.size(); ++i) {
    const unsigned char ch = static_cast<unsigned char>(err[i]);
    if (ch < 0x20 || ch == 0x7f) {
      return "stderr holds a control character at byte " + std::to_string(i);
    }
  }
  for (const char* word : {"internal", "terminate", "what()"}) {
    if (contains(lower(err), word)) {
      return std::string("stderr mentions \"") + word + "\"";
    }
  }
  if (count_word(err, "nan") > nan_in_input) {
    return "stderr mentions \"nan\" (more often than the input did)";
  }
  return "";
}

std::string check_outcome(const Case& c, const Seen& seen) {
  if (seen.code != 0) {
    return "expected exit 0";
  }
  std::string problem;
  const std::optional<json> j = parse_json(seen.out, problem);
  if (!j) {
    return problem;
  }
  const std::string got = j->value("outcome", std::string("(none)"));
  if (std::find(c.expect.outcomes.begin(), c.expect.outcomes.end(), got) ==
      c.expect.outcomes.end()) {
    return "outcome \"" + got + "\" is not in the set";
  }
  return check_answer_numbers(*j);
}

std::string check_judged_failing(const std::vector<std::string>& args, const Seen& seen) {
  if (seen.code != 1) {
    return "expected exit 1";
  }
  if (!seen.err.empty()) {
    return "stderr is not empty";
  }
  if (!wants_json(args)) {
    return seen.out.find("FAILED: ") == std::string::npos ? "stdout names no FAILED observable"
                                                          : "";
  }
  std::string problem;
  const std::optional<json> j = parse_json(seen.out, problem);
  if (!j) {
    return problem;
  }
  if (j->value("passed", true)) {
    return "\"passed\" is not false";
  }
  return check_answer_numbers(*j);
}

// Every case: the exit code, "internal", the time.
std::string check_every_case(const Case& c, const Seen& seen) {
  if (seen.killed) {
    return "did not return within " + std::to_string(int(c.limit)) + " s (stopped after " +
           std::to_string(seen.seconds) + " s)";
  }
  if (seen.signal != 0) {
    return "killed by signal " + std::to_string(seen.signal) + " (" + strsignal(seen.signal) + ")";
  }
  if (seen.code != 0 && seen.code != 1 && seen.code != 2) {
    return "exit code " + std::to_string(seen.code) + " is not 0, 1 or 2";
  }
  if (contains(lower(seen.err), "internal")) {
    return "stderr mentions \"internal\"";
  }
  if (seen.seconds > c.limit) {
    return "took " + std::to_string(seen.seconds) + " s, more than " + std::to_string(c.limit) +
           " s";
  }
  return "";
}

std::string judge(const Case& c, const std::vector<std::string>& args, const Seen& seen,
                  int nan_in_input) {
  std::vector<std::string> problems;
  if (std::string p = check_every_case(c, seen); !p.empty()) {
    problems.push_back(p);
  }
  std::string p;
  switch (c.expect.cls) {
  case Class::ok:
    p = check_ok(c, args, seen);
    break;
  case Class::refused:
    p = check_refused(args, seen, nan_in_input);
    break;
  case Class::outcome:
    p = (c.expect.or_refused && seen.code != 0) ? check_refused(args, seen, nan_in_input)
                                                : check_outcome(c, seen);
    break;
  case Class::ok_or_refused:
    p = seen.code == 0 ? check_ok(c, args, seen) : check_refused(args, seen, nan_in_input);
    break;
  case Class::judged_failing:
    p = check_judged_failing(args, seen);
    break;
  }
  if (!p.empty() && (problems.empty() || problems.front() != p)) {
    problems.push_back(p);
  }
  std::string all;
  for (const std::string& q : problems) {
    all += (all.empty() ? "" : "; ") + q;
  }
  return all;
}

// ---------------------------------------------------------------------------------------------
// Extra checks.

Extra all_of(std::vector<Extra> checks) {
  return [checks](const Seen& seen, const fs::path& dir) {
    for (const Extra& check : checks) {
      if (std::string p = check(seen, dir); !p.empty()) {
        return p;
      }
    }
    return std::string();
  };
}

// stderr (on a refusal) mentions one of the words, case-insensitively.
Extra err_mentions(std::vector<std::string> words) {
  return [words](const Seen& seen, const fs::path&) {
    if (seen.code != 2) {
      return std::string();
    }
    for (const std::string& w : words) {
      if (contains(lower(seen.err), lower(w))) {
        return std::string();
      }
    }
    std::string list;
    for (const std::string& w : words) {
      list += (list.empty() ? "\"" : " or \"") + w + "\"";
    }
    return "the refusal does not mention " + list;
  };
}

// The refusal is not for a reason other than the one probed.
Extra err_lacks(std::string words) {
  return [words](const Seen& seen, const fs::path&) {
    if (seen.code == 2 && contains(lower(seen.err), lower(words))) {
      return "the refusal is \"" + words + "\", not the check probed";
    }
    return std::string();
  };
}

// A JSON number of the answer within `tolerance` of `target`, read in 50 digits from its text.
Extra number_near(std::string key, std::string target, std::string tolerance) {
  return [=](const Seen& seen, const fs::path&) {
    using boost::multiprecision::cpp_bin_float_50;
    if (seen.code != 0) {
      return std::string();
    }
    const auto raw = raw_numbers(seen.out);
    const auto found = raw.find(key);
    if (found == raw.end()) {
      return "no number \"" + key + "\" in the answer";
    }
    try {
      const cpp_bin_float_50 value(found->second);
      if (abs(value - cpp_bin_float_50(target)) > cpp_bin_float_50(tolerance)) {
        return "\"" + key + "\" = " + found->second + " is not within " + tolerance + " of " +
               target;
      }
    } catch (const std::exception&) {
      return "\"" + key + "\" = " + found->second + " does not parse";
    }
    return std::string();
  };
}

// The same, where the answer's outcome is "exited" (a step_limit is honest without it).
Extra number_near_if_exited(std::string key, std::string target, std::string tolerance) {
  const Extra near = number_near(key, target, tolerance);
  return [near](const Seen& seen, const fs::path& dir) {
    std::string problem;
    const std::optional<json> j = seen.code == 0 ? parse_json(seen.out, problem) : std::nullopt;
    if (!j || j->value("outcome", std::string()) != "exited") {
      return std::string();
    }
    return near(seen, dir);
  };
}

// The refusal names the smallest rtol accepted: a number above the one given, at most 1e-8.
Extra names_smallest_rtol(double given) {
  return [given](const Seen& seen, const fs::path&) {
    if (seen.code != 2) {
      return std::string();
    }
    const std::string& err = seen.err;
    for (std::size_t i = 0; i < err.size(); ++i) {
      if (!std::isdigit(static_cast<unsigned char>(err[i])) ||
          (i > 0 && (std::isalnum(static_cast<unsigned char>(err[i - 1])) || err[i - 1] == '.'))) {
        continue;
      }
      char* end = nullptr;
      const double x = std::strtod(err.c_str() + i, &end);
      if (x > given && x <= 1e-8) {
        return std::string();
      }
      i = static_cast<std::size_t>(end - err.c_str());
    }
    return std::string("the refusal names no smallest rtol accepted (a number in (given, 1e-8])");
  };
}

// The report folder of a refused run was not made: no work started.
Extra no_report_folder() {
  return [](const Seen& seen, const fs::path& dir) {
    if (seen.code == 2 && fs::exists(dir / "out")) {
      return std::string("a refused run created its report folder");
    }
    return std::string();
  };
}

// ---------------------------------------------------------------------------------------------
// The table.

const std::vector<std::string> adaptive_solvers{"cvode-bdf",   "cvode-adams", "arkode-dp5",
                                                "arkode-erk8", "arkode-dirk", "odeint-rkf78",
                                                "odeint-bs",   "taylor"};
const std::vector<std::string> atol_solvers{"cvode-bdf",   "cvode-adams", "arkode-dp5",
                                            "arkode-erk8", "arkode-dirk", "odeint-rkf78",
                                            "odeint-bs"};
const std::vector<std::string> fixed_step_solvers{"verlet-predicted", "dem-verlet",
                                                  "dem-symplectic-euler", "dem-leapfrog"};
const std::vector<std::string> optional_step_solvers{"arkode-dp5", "arkode-erk8", "arkode-dirk"};

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// p = 1.5 (Hertz), e = 0.5, v0 = 1: the contact every variation starts from.
std::vector<std::string> contact(std::vector<std::string> change = {}) {
  std::map<std::string, std::string> values{{"--p", "1.5"}, {"--e", "0.5"}, {"--v0", "1"}};
  std::vector<std::string> out;
  std::set<std::string> replaced;
  for (std::size_t i = 0; i + 1 < change.size(); i += 2) {
    replaced.insert(change[i]);
  }
  for (const char* key : {"--p", "--e", "--v0"}) {
    if (replaced.count(key) == 0) {
      out.insert(out.end(), {key, values[key]});
    }
  }
  for (std::size_t i = 0; i + 1 < change.size(); i += 2) {
    if (change[i + 1] != "<absent>") {
      out.insert(out.end(), {change[i], change[i + 1]});
    }
  }
  return out;
}

std::vector<std::string> solve_args(const std::string& solver,
                                    std::vector<std::string> change = {}) {
  return cat(cat({"solve", "--solver", solver}, contact(std::move(change))), {"--json"});
}

// Strings with control characters, empty, unicode, very long.
struct Hostile {
  std::string name, text;
};
const std::vector<Hostile>& hostile_strings() {
  static const std::vector<Hostile> strings{
      {"newline", "0.5\nx"},
      {"tab", "\t1"},
      {"escape", "1\x1b[31m"},
      {"cr", "0.5\r"},
      {"nul_like_del", "0.5\x7f"},
      {"empty", ""},
      {"space", " "},
      {"unicode_half", "\xc2\xbd"},            // ½
      {"unicode_digits", "\xd9\xa0.\xd9\xa5"}, // Arabic-Indic ٠.٥
      {"long_digits", std::string(10000, '9')},
      {"long_letters", std::string(10000, 'x')},
      {"long_zeros", "0." + std::string(9998, '0')},
  };
  return strings;
}

void add(std::vector<Case>& table, std::string name, std::vector<std::string> args, Expect expect,
         Extra extra = nullptr, Setup setup = nullptr, double limit = 20) {
  table.push_back({sanitize_name(name), std::move(args), std::move(expect), std::move(setup),
                   std::move(extra), limit});
}

// -- Command-level: no command, unknown commands, help, unknown flags.
std::vector<Case> command_cases() {
  std::vector<Case> t;
  add(t, "no_arguments", {}, refused());
  add(t, "unknown_command", {"frobnicate"}, refused());
  add(t, "empty_command", {""}, refused());
  add(t, "unicode_command", {"s\xc3\xb6lve"}, refused());
  add(t, "command_with_newline", {"solve\n"}, refused());
  add(t, "long_command", {std::string(10000, 'c')}, refused());
  add(t, "unknown_top_flag", {"--frobnicate"}, refused());
  add(t, "version_flag", {"--version"}, ok()); // the build every report names (issue 49)
  add(t, "help", {"--help"}, ok());
  add(t, "two_commands", {"calibrate", "observables", "--p", "1.5", "--e", "0.5"}, refused());
  for (const char* command :
       {"calibrate", "observables", "solve", "run", "diff", "check", "showcase"}) {
    add(t, std::string(command) + "_help", {command, "--help"}, ok());
  }
  // An unknown flag on a command that is otherwise valid (run and diff: in their groups).
  const std::vector<std::pair<std::string, std::vector<std::string>>> valid{
      {"calibrate", {"calibrate", "--p", "1.5", "--e", "0.5", "--json"}},
      {"observables", cat(cat({"observables"}, contact()), {"--json"})},
      {"solve", solve_args("cvode-bdf")},
      {"showcase", {"showcase"}}};
  for (const auto& [command, args] : valid) {
    add(t, command + "_unknown_flag", cat(args, {"--frobnicate", "1"}), refused(),
        err_mentions({"frobnicate"}));
  }
  add(t, "solve_unknown_flag_after_valid", cat(solve_args("cvode-bdf"), {"--rtl", "1e-6"}),
      refused());
  add(t, "observables_extra_positional", cat({"observables"}, cat(contact(), {"extra"})),
      refused());
  add(t, "observables_double_dash", cat({"observables"}, cat(contact(), {"--", "--json"})),
      refused());
  add(t, "observables_single_dash_flag", {"observables", "-p", "1.5", "-e", "0.5", "-v0", "1"},
      refused());
  add(t, "observables_equals_syntax", {"observables", "--p=1.5", "--e=0.5", "--v0=1", "--json"},
      ok()); // CLI11 reads --name=value, a common spelling
  add(t, "observables_flag_without_value", {"observables", "--p", "1.5", "--v0", "1", "--e"},
      refused());
  add(t, "observables_value_is_a_flag", {"observables", "--p", "--e", "0.5", "--v0", "1"},
      refused());
  // Duplicated flags: conflicting values may be refused or the last one taken (common practice).
  add(t, "observables_duplicated_p", cat({"observables"}, cat(contact(), {"--p", "2", "--json"})),
      ok_or_refused());
  add(t, "observables_duplicated_json", cat({"observables"}, cat(contact(), {"--json", "--json"})),
      ok_or_refused());
  add(t, "solve_duplicated_solver", cat(solve_args("cvode-bdf"), {"--solver", "odeint-rkf78"}),
      ok_or_refused());
  add(t, "solve_duplicated_rtol",
      cat(solve_args("cvode-bdf"), {"--rtol", "1e-6", "--rtol", "1e-8"}), ok_or_refused());
  add(t, "json_flag_with_value", cat({"observables"}, cat(contact(), {"--json=yes"})),
      ok_or_refused()); // CLI11 reads a flag's =value as a boolean word
  return t;
}

// -- calibrate: every flag, numbers at and beyond the domain.
std::vector<Case> calibrate_cases() {
  std::vector<Case> t;
  const auto calibrate = [](std::vector<std::string> more) {
    return cat({"calibrate"}, std::move(more));
  };
  add(t, "basic", calibrate({"--p", "1.5", "--e", "0.5", "--json"}), ok());
  add(t, "text", calibrate({"--p", "1.5", "--e", "0.5"}), ok());
  add(t, "end_force", calibrate({"--p", "1.5", "--e", "0.5", "--end", "force", "--json"}), ok());
  add(t, "end_sideways", calibrate({"--p", "1.5", "--e", "0.5", "--end", "sideways", "--json"}),
      refused());
  add(t, "end_empty", calibrate({"--p", "1.5", "--e", "0.5", "--end", "", "--json"}), refused());
  for (const char* precision : {"double", "long", "quad", "50"}) {
    add(t, std::string("precision_") + precision,
        calibrate({"--p", "1.5", "--e", "0.5", "--precision", precision, "--json"}), ok());
  }
  for (const char* precision : {"float", "", "DOUBLE", "128"}) {
    add(t, std::string("precision_bad_") + (precision[0] ? precision : "empty"),
        calibrate({"--p", "1.5", "--e", "0.5", "--precision", precision, "--json"}), refused());
  }
  add(t, "missing_e", calibrate({"--p", "1.5", "--json"}), refused());
  add(t, "missing_p", calibrate({"--e", "0.5", "--json"}), refused());
  add(t, "alpha_not_an_option", calibrate({"--p", "1.5", "--alpha", "0.5", "--json"}), refused());
  add(t, "code_lammps_tsuji",
      calibrate({"--code", "lammps-tsuji", "--p", "1.5", "--e", "0.5", "--json"}), ok());
  add(t, "code_liggghts_limit_damping",
      calibrate({"--code", "liggghts", "--limit-damping", "--p", "1", "--e", "0.5", "--json"}),
      ok());
  add(t, "code_chrono_limit_damping",
      calibrate({"--code", "chrono", "--limit-damping", "--p", "1.5", "--e", "0.5", "--json"}),
      refused());
  add(t, "code_unknown", calibrate({"--code", "ode45", "--p", "1.5", "--e", "0.5", "--json"}),
      refused());
  add(t, "code_empty", calibrate({"--code", "", "--p", "1.5", "--e", "0.5", "--json"}), refused());
  add(t, "code_lammps_tsuji_p_nan",
      calibrate({"--code", "lammps-tsuji", "--p", "nan", "--e", "0.5", "--json"}), refused());
  add(t, "code_yade_e_0", calibrate({"--code", "yade", "--p", "1", "--e", "0", "--json"}),
      refused());
  add(t, "code_mercurydpm_e_nan",
      calibrate({"--code", "mercurydpm", "--p", "1", "--e", "nan", "--json"}), refused());
  // e = 1 (no damping) and the limit of the reach: each code answers or refuses, in one line.
  add(t, "code_lammps_tsuji_e_1e_300",
      calibrate({"--code", "lammps-tsuji", "--p", "1.5", "--e", "1e-300", "--json"}),
      ok_or_refused());
  add(t, "limit_damping_alone",
      calibrate({"--limit-damping", "--p", "1.5", "--e", "0.5", "--json"}), refused());
  // p across and beyond the domain [1, 1000].
  const std::vector<std::pair<std::string, Expect>> ps{
      {"1", ok()},         {"1.000000000000001", ok()},   {"1e3", ok()},      {"1e18", refused()},
      {"1e30", refused()}, {"0.999", refused()},          {"nan", refused()}, {"inf", refused()},
      {"-1", refused()},   {"1000.0000000001", refused()}};
  for (const auto& [p, expect] : ps) {
    add(t, "p_" + p, calibrate({"--p", p, "--e", "0.5", "--json"}), expect);
  }
  const std::vector<std::pair<std::string, Expect>> es{
      {"1", ok()},
      {"1e-300", ok()}, // in (0, 1]: alpha_eff just below 1
      // 5e-324, the smallest subnormal: at the edge of double, refusing it is as honest
      {"5e-324", ok_or_refused()},
      {"0", refused()},
      // 1 + 1e-16 rounds to 1 in double: answering for e = 1 or refusing e > 1 are both honest
      {"1.0000000000000001", ok_or_refused()},
      {"0.999999", ok()},
      {"nan", refused()},
      {"-0.5", refused()},
      {"1.5", refused()}};
  for (const auto& [e, expect] : es) {
    add(t, "e_" + e, calibrate({"--p", "1.5", "--e", e, "--json"}), expect);
  }
  add(t, "e_1e_300_force", calibrate({"--p", "1.5", "--e", "1e-300", "--end", "force", "--json"}),
      ok_or_refused()); // the numeric inverse of e_cap, at the far end of its range
  add(t, "e_1plus_quad",
      calibrate({"--p", "1.5", "--e", "1.0000000000000001", "--precision", "quad", "--json"}),
      refused()); // representable above 1 in quad
  return t;
}

// -- observables: every flag, numbers, precisions, strings.
std::vector<Case> observables_cases() {
  std::vector<Case> t;
  const auto obs = [](std::vector<std::string> change, std::vector<std::string> more = {"--json"}) {
    return cat(cat({"observables"}, contact(std::move(change))), std::move(more));
  };
  add(t, "basic", obs({}), ok());
  add(t, "text", obs({}, {}), ok());
  add(t, "end_force", obs({}, {"--end", "force", "--json"}), ok());
  add(t, "end_force_e_1", obs({"--e", "1"}, {"--end", "force", "--json"}), ok(),
      number_near("e_cap", "1", "1e-15"));
  add(t, "m_k_si", obs({"--v0", "2"}, {"--m", "0.01", "--k", "7e9", "--json"}), ok());
  for (const char* precision : {"double", "long", "quad", "50"}) {
    add(t, std::string("precision_") + precision, obs({}, {"--precision", precision, "--json"}),
        ok());
  }
  for (const char* precision : {"float", ""}) {
    add(t, std::string("precision_bad_") + (precision[0] ? precision : "empty"),
        obs({}, {"--precision", precision, "--json"}), refused());
  }
  const std::vector<std::pair<std::string, Expect>> ps{
      {"1", ok()},         {"1.000000000000001", ok()}, {"1e3", ok()},
      {"1e18", refused()}, {"1e30", refused()},         {"0.999", refused()},
      {"nan", refused()},  {"inf", refused()},          {"-1", refused()}};
  for (const auto& [p, expect] : ps) {
    add(t, "p_" + p, obs({"--p", p}), expect);
  }
  add(t, "p_1e3_quad", obs({"--p", "1e3"}, {"--precision", "quad", "--json"}), ok());
  add(t, "p_1e18_quad", obs({"--p", "1e18"}, {"--precision", "quad", "--json"}), refused());
  const std::vector<std::pair<std::string, Expect>> es{
      {"1", ok()},
      {"1e-300", ok()},
      {"5e-324", ok_or_refused()}, // the smallest subnormal
      {"0", refused()},
      {"1.0000000000000001", ok_or_refused()}, // rounds to 1 in double
      {"0.999999", ok()},
      {"nan", refused()}};
  for (const auto& [e, expect] : es) {
    add(t, "e_" + e, obs({"--e", e}), expect);
  }
  add(t, "e_1e_300_quad", obs({"--e", "1e-300"}, {"--precision", "quad", "--json"}), ok());
  add(t, "e_1plus_quad", obs({"--e", "1.0000000000000001"}, {"--precision", "quad", "--json"}),
      refused());
  add(t, "e_1e_300_end_force", obs({"--e", "1e-300"}, {"--end", "force", "--json"}),
      ok_or_refused()); // e_cap's inverse at the far end of its range
  // Damping as alpha and alpha_eff: zero, critical, just below it, far beyond the domain.
  const std::vector<std::pair<std::string, Expect>> zs{
      {"0", ok()},      {"1", ok()},          {"0.9999999999999999", ok()},
      {"-0", ok()},     {"1e300", refused()}, {"nan", refused()},
      {"-1", refused()}};
  for (const char* flag : {"--alpha", "--alpha-eff"}) {
    for (const auto& [z, expect] : zs) {
      add(t, std::string(flag).substr(2) + "_" + z, obs({"--e", "<absent>", flag, z}), expect);
    }
  }
  add(t, "alpha_1e300_quad",
      {"observables", "--p", "1.5", "--alpha", "1e300", "--v0", "1", "--precision", "quad",
       "--json"},
      refused());
  add(t, "alpha_eff_1e6", obs({"--e", "<absent>", "--alpha-eff", "1e6"}), ok());
  add(t, "alpha_eff_critical_quad",
      obs({"--e", "<absent>", "--alpha-eff", "1"}, {"--precision", "quad", "--json"}), ok());
  add(t, "alpha_eff_below_critical_50",
      obs({"--e", "<absent>", "--alpha-eff", "0.9999999999999999"},
          {"--precision", "50", "--json"}),
      ok());
  add(t, "e_and_alpha", obs({"--alpha", "0.3"}), refused());
  add(t, "alpha_and_alpha_eff", obs({"--e", "<absent>", "--alpha", "0.3", "--alpha-eff", "0.3"}),
      refused());
  add(t, "no_damping_given", obs({"--e", "<absent>"}), refused());
  add(t, "missing_v0", obs({"--v0", "<absent>"}), refused());
  // v0, m, k: far outside [1e-30, 1e30], zero, negative, infinite.
  for (const char* flag : {"--v0", "--m", "--k"}) {
    for (const char* x : {"1e-300", "1e300", "5e-324", "0", "-1", "inf"}) {
      add(t, std::string(flag).substr(2) + "_" + x,
          std::string(flag) == "--v0" ? obs({flag, x}) : obs({}, {flag, x, "--json"}), refused());
    }
  }
  add(t, "m_1e300_k_1e_300", obs({}, {"--m", "1e300", "--k", "1e-300", "--json"}), refused());
  add(t, "m_1e30_k_1e_30", obs({}, {"--m", "1e30", "--k", "1e-30", "--json"}), ok());
  add(t, "v0_1e30_quad", obs({"--v0", "1e30"}, {"--precision", "quad", "--json"}), ok());
  // The brief's named cases.
  add(t, "named_p_1e18", {"observables", "--p", "1e18", "--e", "0.5", "--v0", "1"}, refused());
  // A contact from materials (ask/materials.hpp): each number at its edges, far beyond them,
  // not finite; lists of the wrong length; mixed with --m/--k or another p.
  const auto materials = [&](const std::string& flag, const std::string& value,
                             std::vector<std::string> more = {"--json"}) {
    std::vector<std::string> given{"--geometry", "sphere-sphere", "--radius",  "0.01",
                                   "--young",    "7e10",          "--poisson", "0.3",
                                   "--density",  "2700"};
    for (std::size_t i = 0; i + 1 < given.size(); ++i) {
      if (given[i] == flag) {
        given[i + 1] = value;
      }
    }
    return obs({"--p", "<absent>"}, cat(std::move(given), std::move(more)));
  };
  add(t, "materials", materials("", ""), ok());
  add(t, "materials_text", materials("", "", {}), ok());
  add(t, "materials_quad", materials("", "", {"--precision", "quad", "--json"}), ok());
  add(t, "materials_50", materials("", "", {"--precision", "50", "--json"}), ok());
  add(t, "materials_wall_rigid", materials("--geometry", "sphere-wall"), ok());
  add(t, "materials_wall_elastic",
      obs({"--p", "<absent>"},
          {"--geometry", "sphere-wall", "--radius", "0.01", "--young", "7e10,2e11", "--poisson",
           "0.3,0.29", "--density", "2700", "--json"}),
      ok());
  for (const char* flag : {"--radius", "--young", "--density"}) {
    for (const char* x : {"0", "-1", "-0", "inf", "nan", "1e-300,1", "1,2,3", ""}) {
      add(t, std::string("materials_") + (flag + 2) + "_" + x, materials(flag, x), refused());
    }
  }
  for (const char* x : {"0.5", "-1", "0.5000000000000001", "nan", "1,0.2", "0.2,0.2,0.2"}) {
    add(t, std::string("materials_poisson_") + x, materials("--poisson", x), refused());
  }
  for (const char* x : {"0.4999999", "-0.9999999", "0"}) {
    add(t, std::string("materials_poisson_") + x, materials("--poisson", x), ok());
  }
  // A radius of 1e300 overflows m (R³), a density of 1e-300 makes m too small: the contact's own
  // checks of m and k refuse them; the smallest sane contact answers.
  add(t, "materials_radius_1e300", materials("--radius", "1e300"), refused());
  add(t, "materials_density_1e_300", materials("--density", "1e-300"), refused());
  add(t, "materials_young_1e300", materials("--young", "1e300"), refused());
  add(t, "materials_geometry_bad", materials("--geometry", "cube"), refused());
  add(t, "materials_with_m", materials("", "", {"--m", "1", "--json"}), refused());
  add(t, "materials_with_k", materials("", "", {"--k", "1", "--json"}), refused());
  add(t, "materials_with_p_2", materials("", "", {"--p", "2", "--json"}), refused());
  add(t, "materials_with_p_1_5", materials("", "", {"--p", "1.5", "--json"}), ok());
  add(t, "materials_without_geometry",
      obs({}, {"--radius", "0.01", "--young", "7e10", "--poisson", "0.3", "--density", "2700"}),
      refused());
  add(t, "materials_wall_two_radii",
      materials("--geometry", "sphere-wall", {"--radius", "0.01", "--json"}), refused());
  // Strings: control characters, empty, unicode, 10 000 characters, in each number.
  for (const char* flag : {"--p", "--e", "--v0", "--m"}) {
    for (const Hostile& h : hostile_strings()) {
      if (std::string(flag) != "--e" && h.name != "newline" && h.name != "empty" &&
          h.name != "long_digits" && h.name != "escape") {
        continue; // every string on --e; the sharpest four on the others
      }
      add(t, std::string(flag).substr(2) + "_string_" + h.name,
          std::string(flag) == "--m" ? obs({}, {flag, h.text, "--json"}) : obs({flag, h.text}),
          refused());
    }
  }
  // strtod reads hexadecimal floats and signs; harmless either way.
  add(t, "e_hex_float", obs({"--e", "0x1p-1"}), ok_or_refused());
  add(t, "e_plus_sign", obs({"--e", "+0.5"}), ok_or_refused());
  add(t, "e_comma_decimal", obs({"--e", "0,5"}), refused());
  add(t, "e_trailing_space", obs({"--e", "0.5 "}), refused());
  add(t, "e_exponent_only", obs({"--e", "1e"}), refused());
  add(t, "e_infinity_word", obs({"--e", "infinity"}), refused());
  add(t, "p_long_one", obs({"--p", "1." + std::string(9990, '0') + "1"}),
      ok_or_refused()); // 1 + 1e-9991 rounds to 1
  add(t, "end_unicode", obs({}, {"--end", "f\xc3\xb6rce", "--json"}), refused());
  add(t, "end_long", obs({}, {"--end", std::string(10000, 'f'), "--json"}), refused());
  add(t, "precision_long", obs({}, {"--precision", std::string(10000, '5'), "--json"}), refused());
  return t;
}

// -- solve: every solver, tolerances, steps, options.
std::vector<Case> solve_cases() {
  std::vector<Case> t;
  const std::vector<std::string> all_solvers = cat(adaptive_solvers, fixed_step_solvers);
  for (const std::string& s : all_solvers) {
    add(t, s + "_basic", solve_args(s), ok());
    add(t, s + "_end_force", cat(solve_args(s), {"--end", "force"}), ok());
  }
  // Tolerances on every error-controlled solver.
  struct Tol {
    std::string value;
    Expect expect;
  };
  const std::vector<Tol> rtols{{"1", refused()},
                               // a loose but legal tolerance: an answer, or an honest unstable
                               {"0.5", outcome({"exited", "unstable"})},
                               {"1e-17", refused()},  // below double's epsilon
                               {"1e-400", refused()}, // underflows to 0
                               {"-1", refused()},
                               {"nan", refused()},
                               {"inf", refused()},
                               {"0", refused()}};
  for (const std::string& s : adaptive_solvers) {
    for (const Tol& tol : rtols) {
      add(t, s + "_rtol_" + tol.value, cat(solve_args(s), {"--rtol", tol.value}), tol.expect,
          tol.value == "1e-17" ? names_smallest_rtol(1e-17) : nullptr);
    }
  }
  for (const std::string& s : atol_solvers) {
    add(t, s + "_atol_1e300", cat(solve_args(s), {"--atol", "1e300"}), refused());
    // below any state's scale by 290 orders: refusing or meeting it, never exit 3 or a hang
    add(t, s + "_atol_1e_300", cat(solve_args(s), {"--atol", "1e-300"}), ok_or_refused());
    // zero: pure relative control from delta = 0 has no error weight (scenes refuse atol <= 0)
    add(t, s + "_atol_0", cat(solve_args(s), {"--atol", "0"}), refused());
  }
  add(t, "cvode-bdf_atol_nan", cat(solve_args("cvode-bdf"), {"--atol", "nan"}), refused());
  add(t, "cvode-bdf_atol_neg", cat(solve_args("cvode-bdf"), {"--atol", "-1e-8"}), refused());
  add(t, "taylor_atol", cat(solve_args("taylor"), {"--atol", "1e-12"}), refused());
  for (const std::string& s : fixed_step_solvers) {
    add(t, s + "_rtol", cat(solve_args(s), {"--rtol", "1e-6"}), refused());
    add(t, s + "_atol", cat(solve_args(s), {"--atol", "1e-6"}), refused());
  }
  // The brief's named tolerance cases.
  add(t, "named_cvode-bdf_rtol_1e_16", cat(solve_args("cvode-bdf"), {"--rtol", "1e-16"}), refused(),
      names_smallest_rtol(1e-16));
  add(t, "named_taylor_quad_rtol_1e_400",
      cat(solve_args("taylor"), {"--precision", "quad", "--rtol", "1e-400"}), refused());
  add(t, "taylor_quad_rtol_1e_40",
      cat(solve_args("taylor"), {"--precision", "quad", "--rtol", "1e-40"}), refused(),
      names_smallest_rtol(1e-40));
  add(t, "taylor_50_rtol_1e_60",
      cat(solve_args("taylor"), {"--precision", "50", "--rtol", "1e-60"}), refused());
  add(t, "taylor_50_rtol_1e_40",
      cat(solve_args("taylor"), {"--precision", "50", "--rtol", "1e-40"}), ok());
  // Fixed steps too large and tiny.
  const std::vector<std::string> stepping = cat(fixed_step_solvers, optional_step_solvers);
  for (const std::string& s : stepping) {
    for (const char* dt : {"3", "5", "10"}) {
      Expect expect = outcome({"exited", "unstable"});
      const std::string d = dt;
      if ((d == "10" && (s == "verlet-predicted" || s == "dem-verlet")) ||
          (d == "5" && s == "arkode-dp5") || (d == "3" && s == "arkode-erk8")) {
        expect = outcome({"unstable"}); // the brief's named cases
      }
      add(t, s + "_dt_" + d, cat(solve_args(s), {"--dt", d}), expect);
    }
    add(t, s + "_dt_1e300", cat(solve_args(s), {"--dt", "1e300"}),
        outcome_or_refused({"unstable"}));
    // 1e-300 per step: the step limit (or the time limit) comes first, or it is refused
    add(t, s + "_dt_1e_300", cat(solve_args(s), {"--dt", "1e-300"}),
        outcome_or_refused({"step_limit", "time_limit"}));
  }
  for (const char* dt : {"0", "-1", "nan", "inf", ""}) {
    add(t, std::string("dem-verlet_dt_bad_") + (dt[0] ? dt : "empty"),
        cat(solve_args("dem-verlet"), {"--dt", dt}), refused());
  }
  for (const char* s : {"cvode-bdf", "odeint-bs", "taylor"}) {
    add(t, std::string(s) + "_dt", cat(solve_args(s), {"--dt", "0.01"}), refused());
    // an option the solver does not take is refused (docs/cli.md), steps per contact included
    add(t, std::string(s) + "_steps_per_contact",
        cat(solve_args(s), {"--steps-per-contact", "100"}), refused());
  }
  add(t, "dem-verlet_dt_and_steps",
      cat(solve_args("dem-verlet"), {"--dt", "0.01", "--steps-per-contact", "100"}), refused());
  for (const std::string& s : fixed_step_solvers) {
    add(t, s + "_steps_0", cat(solve_args(s), {"--steps-per-contact", "0"}), refused());
    add(t, s + "_steps_1", cat(solve_args(s), {"--steps-per-contact", "1"}),
        outcome({"exited", "unstable"}));
    add(t, s + "_steps_2", cat(solve_args(s), {"--steps-per-contact", "2"}),
        outcome({"exited", "unstable"}));
    add(t, s + "_steps_1000000000", cat(solve_args(s), {"--steps-per-contact", "1000000000"}),
        outcome_or_refused({"step_limit", "time_limit"}));
  }
  add(t, "dem-verlet_steps_1e9", cat(solve_args("dem-verlet"), {"--steps-per-contact", "1e9"}),
      outcome_or_refused({"step_limit", "time_limit"}));
  add(t, "dem-verlet_steps_huge",
      cat(solve_args("dem-verlet"), {"--steps-per-contact", "99999999999999999999"}), refused());
  add(t, "dem-verlet_steps_neg", cat(solve_args("dem-verlet"), {"--steps-per-contact", "-5"}),
      refused());
  add(t, "dem-verlet_steps_fraction", cat(solve_args("dem-verlet"), {"--steps-per-contact", "2.5"}),
      refused());
  // --onset-phase
  add(t, "dem-verlet_onset_half", cat(solve_args("dem-verlet"), {"--onset-phase", "0.5"}), ok());
  add(t, "dem-leapfrog_onset_almost_1",
      cat(solve_args("dem-leapfrog"), {"--onset-phase", "0.9999999999999999"}), ok());
  for (const char* phase : {"1", "-0.1", "nan", "inf", "1e300"}) {
    add(t, std::string("dem-verlet_onset_") + phase,
        cat(solve_args("dem-verlet"), {"--onset-phase", phase}), refused());
  }
  add(t, "cvode-bdf_onset", cat(solve_args("cvode-bdf"), {"--onset-phase", "0.5"}), refused());
  // --horizon
  add(t, "cvode-bdf_horizon_tiny", cat(solve_args("cvode-bdf"), {"--horizon", "1e-300"}),
      outcome_or_refused({"no_exit"})); // the horizon comes first: that is what no_exit says
  for (const char* h : {"0", "-1", "nan"}) {
    add(t, std::string("cvode-bdf_horizon_") + h, cat(solve_args("cvode-bdf"), {"--horizon", h}),
        refused());
  }
  add(t, "cvode-bdf_horizon_inf", cat(solve_args("cvode-bdf"), {"--horizon", "inf"}),
      ok_or_refused()); // no horizon: the contact returns by itself
  add(t, "cvode-bdf_overdamped_horizon_1e300",
      cat(solve_args("cvode-bdf", {"--e", "<absent>", "--alpha-eff", "2"}), {"--horizon", "1e300"}),
      outcome_or_refused({"no_exit", "step_limit", "time_limit"}));
  add(t, "taylor_overdamped_horizon_1e300",
      cat(solve_args("taylor", {"--e", "<absent>", "--alpha-eff", "2"}), {"--horizon", "1e300"}),
      outcome_or_refused({"no_exit", "step_limit", "time_limit"}));
  // --sample-times
  add(t, "cvode-bdf_samples", cat(solve_args("cvode-bdf"), {"--sample-times", "0.5,1,2"}), ok());
  add(t, "cvode-bdf_samples_beyond", cat(solve_args("cvode-bdf"), {"--sample-times", "1e300"}),
      ok_or_refused()); // outside the contact: no sample, or refused
  for (const auto& [name, times] : std::vector<std::pair<std::string, std::string>>{
           {"negative", "-1"}, {"nan", "nan"}, {"empty", ""}, {"word", "soon"}, {"inf", "inf"}}) {
    add(t, "cvode-bdf_samples_" + name, cat(solve_args("cvode-bdf"), {"--sample-times", times}),
        refused());
  }
  // An empty item between commas: skipped or refused, both honest.
  add(t, "cvode-bdf_samples_empty_item", cat(solve_args("cvode-bdf"), {"--sample-times", "1,,2"}),
      ok_or_refused());
  {
    std::string many;
    for (int i = 1; i <= 10000; ++i) {
      if (i > 1) {
        many += ',';
      }
      many += std::to_string(i * 3e-4);
    }
    add(t, "cvode-bdf_samples_10000", cat(solve_args("cvode-bdf"), {"--sample-times", many}),
        ok_or_refused());
  }
  // --max-steps
  add(t, "cvode-bdf_max_steps_1", cat(solve_args("cvode-bdf"), {"--max-steps", "1"}),
      outcome({"step_limit"}));
  add(t, "taylor_max_steps_1", cat(solve_args("taylor"), {"--max-steps", "1"}),
      outcome({"step_limit"}));
  add(t, "dem-verlet_max_steps_10", cat(solve_args("dem-verlet"), {"--max-steps", "10"}),
      outcome({"step_limit"}));
  for (const char* n : {"0", "-1", "1.5", "99999999999999999999", ""}) {
    add(t, std::string("cvode-bdf_max_steps_") + (n[0] ? n : "empty"),
        cat(solve_args("cvode-bdf"), {"--max-steps", n}), refused());
  }
  // As --help writes its default (issue 50: it was refused as "not an integer").
  add(t, "cvode-bdf_max_steps_1e6_word", cat(solve_args("cvode-bdf"), {"--max-steps", "1e6"}),
      ok());
  add(t, "cvode-bdf_max_steps_long_max",
      cat(solve_args("cvode-bdf"), {"--max-steps", "9223372036854775807"}), ok());
  // --want
  add(t, "cvode-bdf_want_e", cat(solve_args("cvode-bdf"), {"--want", "e"}), ok());
  add(t, "cvode-bdf_want_peak", cat(solve_args("cvode-bdf"), {"--want", "delta_max,t_peak"}), ok());
  add(t, "cvode-bdf_want_energy", cat(solve_args("cvode-bdf"), {"--want", "energy"}), ok());
  add(t, "cvode-bdf_want_twice", cat(solve_args("cvode-bdf"), {"--want", "e,e"}), ok_or_refused());
  for (const auto& [name, want] :
       std::vector<std::pair<std::string, std::string>>{{"bogus", "bogus"},
                                                        {"empty", ""},
                                                        {"comma", ","},
                                                        {"newline", "e\ntau"},
                                                        {"long", std::string(10000, 'e')}}) {
    add(t, "cvode-bdf_want_" + name, cat(solve_args("cvode-bdf"), {"--want", want}), refused());
  }
  // --solver
  for (const auto& [name, solver] :
       std::vector<std::pair<std::string, std::string>>{{"ode45", "ode45"},
                                                        {"empty", ""},
                                                        {"upper", "CVODE-BDF"},
                                                        {"newline", "cvode-bdf\n"},
                                                        {"escape", "cvode\x1b[31m"},
                                                        {"long", std::string(10000, 's')}}) {
    add(t, "solver_" + name, solve_args(solver), refused());
  }
  add(t, "solver_missing", cat({"solve"}, cat(contact(), {"--json"})), refused());
  // --precision with solve: taylor runs in every precision, the others in double only.
  for (const char* precision : {"double", "long", "quad", "50"}) {
    add(t, std::string("taylor_precision_") + precision,
        cat(solve_args("taylor"), {"--precision", precision}), ok());
    add(t, std::string("cvode-bdf_precision_") + precision,
        cat(solve_args("cvode-bdf"), {"--precision", precision}),
        std::string(precision) == "double" ? ok() : refused());
  }
  for (const char* precision : {"float", ""}) {
    for (const char* s : {"taylor", "cvode-bdf"}) {
      add(t, std::string(s) + "_precision_bad_" + (precision[0] ? precision : "empty"),
          cat(solve_args(s), {"--precision", precision}), refused());
    }
  }
  // Numbers through solve.
  const std::vector<std::pair<std::string, Expect>> ps{
      {"1", ok()},         {"1.000000000000001", ok()}, {"1e3", ok()},
      {"1e18", refused()}, {"1e30", refused()},         {"0.999", refused()},
      {"nan", refused()},  {"inf", refused()},          {"-1", refused()}};
  for (const auto& [p, expect] : ps) {
    add(t, "cvode-bdf_p_" + p, solve_args("cvode-bdf", {"--p", p}), expect);
  }
  add(t, "taylor_p_1e3", solve_args("taylor", {"--p", "1e3"}), ok());
  const std::vector<std::pair<std::string, Expect>> es{
      {"1", ok()},
      // alpha_eff = 1 - 1e-5 and tau = 3.7e60 (observables): the return comes long after the
      // horizon, docs/solve.md's "outcome", so no_exit is honest here
      {"1e-300", ok_no_exit()},
      {"5e-324", {Class::ok_or_refused, {}, false, true}},
      {"0", refused()},
      {"1.0000000000000001", ok_or_refused()},
      {"0.999999", ok()},
      {"nan", refused()}};
  for (const auto& [e, expect] : es) {
    add(t, "cvode-bdf_e_" + e, solve_args("cvode-bdf", {"--e", e}), expect);
    add(t, "taylor_e_" + e, solve_args("taylor", {"--e", e}), expect);
  }
  const std::vector<std::pair<std::string, Expect>> zs{
      {"0", ok()},          {"1", ok_no_exit()}, {"0.9999999999999999", ok_no_exit()},
      {"1e300", refused()}, {"-0", ok()},        {"nan", refused()}};
  for (const char* flag : {"--alpha", "--alpha-eff"}) {
    for (const auto& [z, expect] : zs) {
      // alpha = 1 is alpha_eff ~ 0.45 at p = 1.5: a return
      const Expect x = (std::string(flag) == "--alpha" && z == "1") ? ok() : expect;
      add(t, "cvode-bdf_" + std::string(flag).substr(2) + "_" + z,
          solve_args("cvode-bdf", {"--e", "<absent>", flag, z}), x);
    }
  }
  add(t, "taylor_alpha_eff_1", solve_args("taylor", {"--e", "<absent>", "--alpha-eff", "1"}),
      ok_no_exit());
  add(t, "cvode-bdf_alpha_eff_1e6",
      solve_args("cvode-bdf", {"--e", "<absent>", "--alpha-eff", "1e6"}), ok_no_exit());
  add(t, "dem-verlet_alpha_eff_2",
      solve_args("dem-verlet", {"--e", "<absent>", "--alpha-eff", "2"}), ok_no_exit());
  for (const char* flag : {"--v0", "--m", "--k"}) {
    for (const char* x : {"1e-300", "1e300", "5e-324", "0", "-1", "inf"}) {
      const std::string f = flag;
      add(t, "cvode-bdf_" + f.substr(2) + "_" + x,
          f == "--v0" ? solve_args("cvode-bdf", {flag, x})
                      : cat(solve_args("cvode-bdf"), {flag, x}),
          refused());
    }
  }
  add(t, "named_cvode-bdf_m_1e300_k_1e_300",
      cat(solve_args("cvode-bdf"), {"--m", "1e300", "--k", "1e-300"}), refused());
  add(t, "cvode-bdf_m_1e30_k_1e_30", cat(solve_args("cvode-bdf"), {"--m", "1e30", "--k", "1e-30"}),
      ok());
  add(t, "dem-verlet_v0_1e30", solve_args("dem-verlet", {"--v0", "1e30"}), ok());
  // The brief's named solve cases.
  add(t, "named_taylor_50_force_e_1",
      cat(solve_args("taylor", {"--e", "1"}), {"--precision", "50", "--end", "force"}), ok(),
      number_near("e_cap", "1", "1e-30"));
  add(t, "named_taylor_force_e_1", cat(solve_args("taylor", {"--e", "1"}), {"--end", "force"}),
      ok(), number_near("e_cap", "1", "1e-15"));
  add(t, "named_taylor_quad_force_e_1",
      cat(solve_args("taylor", {"--e", "1"}), {"--precision", "quad", "--end", "force"}), ok(),
      number_near("e_cap", "1", "1e-30"));
  add(t, "named_odeint-rkf78_p_50_e_0_999999",
      solve_args("odeint-rkf78", {"--p", "50", "--e", "0.999999"}),
      outcome({"exited", "step_limit"}), number_near_if_exited("e", "0.999999", "1e-3"));
  // The same contact through CVODE: an accurate e, or an honest failure label.
  add(t, "cvode-bdf_p_50_e_0_999999", solve_args("cvode-bdf", {"--p", "50", "--e", "0.999999"}),
      outcome({"exited", "step_limit", "unstable"}),
      number_near_if_exited("e", "0.999999", "1e-3"));
  add(t, "named_e_newline", solve_args("cvode-bdf", {"--e", "0.5\nx"}), refused());
  for (const Hostile& h : hostile_strings()) {
    if (h.name == "newline" || h.name == "tab" || h.name == "escape" || h.name == "long_letters") {
      add(t, "rtol_string_" + h.name, cat(solve_args("cvode-bdf"), {"--rtol", h.text}), refused());
      add(t, "dt_string_" + h.name, cat(solve_args("dem-verlet"), {"--dt", h.text}), refused());
    }
  }
  return t;
}

// -- showcase.
std::vector<Case> showcase_cases() {
  std::vector<Case> t;
  add(t, "default", {"showcase"}, ok());
  for (const char* precision : {"double", "long", "quad", "50"}) {
    add(t, std::string("precision_") + precision, {"showcase", "--precision", precision}, ok());
  }
  for (const char* precision : {"float", "", "nan", "double\n"}) {
    add(t, std::string("precision_bad_") + (precision[0] ? precision : "empty"),
        {"showcase", "--precision", precision}, refused());
  }
  add(t, "json_not_an_option", {"showcase", "--json"}, refused());
  add(t, "positional", {"showcase", "extra"}, refused());
  return t;
}

// -- run: scenes written into the case's directory.
// The harness tests' one-solver scene (name "t", p 1.5, e 0.5, v0 1, cvode-bdf at rtol 1e-6).
const std::string base_scene = pldamp::harness::testing::valid_scene;
const std::string json_only = "[report]\nformats = [\"json\"]\n";

Setup write_scene(std::string text) {
  return [text](const fs::path& dir) {
    return write_text(dir / "scene.toml", text) ? std::string() : "cannot write the scene";
  };
}

std::vector<std::string> run_scene(std::vector<std::string> more = {}) {
  return cat({"run", "{dir}/scene.toml", "--out", "{dir}/out"}, std::move(more));
}

// A grid of 100 p x 100 e x 100 v0 = 1e6 cells and a sweep of 10 rtols: 1e7 solver runs.
std::string huge_scene() {
  std::string p, e, v0;
  for (int i = 0; i < 100; ++i) {
    if (i > 0) {
      p += ", ";
      e += ", ";
      v0 += ", ";
    }
    p += std::to_string(1.0 + 0.01 * i);
    e += std::to_string(0.01 * (i + 1));
    v0 += std::to_string(1.0 + i);
  }
  return "name = \"huge\"\nwant = [\"e\"]\n[grid]\np = [" + p + "]\ne = [" + e + "]\nv0 = [" + v0 +
         "]\n[[solver]]\nname = \"cvode-bdf\"\nrtol = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, "
         "1e-10, 1e-11, 1e-12]\n" +
         json_only;
}

Extra says_plan_size() {
  return err_mentions({"10000000", "1e+07", "1e7", "1e+7", "1.0e7", "1.0e+07", "10 000 000",
                       "10,000,000", "1000000 cells"});
}

// Every record of the report failed, and the report says so.
Extra records_all_failed() {
  return [](const Seen& seen, const fs::path& dir) {
    if (seen.code != 0) {
      return std::string();
    }
    try {
      const json report = json::parse(read_text(dir / "out" / "report.json"));
      const json& records = report.at("records");
      if (records.empty()) {
        return std::string("the report has no records");
      }
      for (const json& r : records) {
        if (!r.at("failed").get<bool>()) {
          return "record " + r.at("key").dump() + " did not fail under max_steps = 10";
        }
      }
      if (report.at("totals").at("failed_records").get<std::size_t>() != records.size()) {
        return std::string("totals.failed_records is not the number of records");
      }
    } catch (const std::exception& e) {
      return std::string("report.json unreadable: ") + e.what();
    }
    return std::string();
  };
}

std::vector<Case> run_cases() {
  std::vector<Case> t;
  const auto scene = [&](std::string name, std::string text, Expect expect, Extra extra = nullptr,
                         std::vector<std::string> more = {}, double limit = 20) {
    const bool refusal = expect.cls == Class::refused;
    Extra checks =
        refusal ? (extra ? all_of({extra, no_report_folder()}) : no_report_folder()) : extra;
    add(t, std::move(name), run_scene(std::move(more)), std::move(expect), std::move(checks),
        write_scene(std::move(text)), limit);
  };
  scene("valid", base_scene + json_only, ok());
  scene("valid_all_formats", base_scene, ok());
  scene("valid_jobs_1", base_scene + json_only, ok(), nullptr, {"--jobs", "1"});
  scene("unknown_flag", base_scene + json_only, refused(), err_mentions({"frobnicate"}),
        {"--frobnicate", "1"});
  scene("valid_jobs_1024", base_scene + json_only, ok(), nullptr, {"--jobs", "1024"});
  for (const char* jobs : {"0", "-1", "1025", "x", "", "1e3", "99999999999999999999"}) {
    scene(std::string("jobs_") + (jobs[0] ? jobs : "empty"), base_scene + json_only, refused(),
          nullptr, {"--jobs", jobs});
  }
  // The scene itself: a directory, missing, empty, garbage, too deep, too big.
  add(t, "scene_is_directory", {"run", "{dir}", "--out", "{dir}/out"}, refused(),
      all_of({err_mentions({"director"}), no_report_folder()}));
  add(t, "scene_missing", run_scene(), refused(), no_report_folder());
  add(t, "scene_missing_newline_in_name", {"run", "{dir}/no\nsuch.toml", "--out", "{dir}/out"},
      refused(), no_report_folder());
  add(t, "scene_long_path",
      {"run", "{dir}/" + std::string(10000, 's') + ".toml", "--out", "{dir}/out"}, refused(),
      no_report_folder());
  add(t, "scene_empty_path", {"run", "", "--out", "{dir}/out"}, refused(), no_report_folder());
  scene("empty_file", "", refused());
  scene("only_comment", "# nothing\n", refused());
  {
    std::mt19937 random(20260101);
    std::string garbage(4096, '\0');
    for (char& c : garbage) {
      c = static_cast<char>(random() & 0xff);
    }
    scene("binary_garbage", garbage, refused());
    scene("nul_in_string",
          std::string("name = \"a\0b\"\n", 13) + base_scene.substr(base_scene.find('\n') + 1),
          refused());
  }
  {
    std::string key = "a";
    for (int i = 1; i < 100000; ++i) {
      key += ".a";
    }
    scene("dotted_key_100000_deep", key + " = 1\n" + base_scene, refused());
    scene("table_header_100000_deep", base_scene + "[" + key + "]\n", refused());
  }
  scene("arrays_nested_1000_deep",
        R"(name = "deep"
[grid]
p = )" + std::string(1000, '[') +
            "1.5" + std::string(1000, ']') + "\ne = [0.5]\nv0 = [1.0]\n",
        refused());
  {
    std::string inline_table = "x = ";
    for (int i = 0; i < 1000; ++i) {
      inline_table += "{a = ";
    }
    inline_table += "1" + std::string(1000, '}');
    scene("inline_tables_nested_1000_deep", inline_table + "\n" + base_scene, refused());
  }
  scene("larger_than_1MB", base_scene + std::string(2 << 20, '#') + "\n", refused());
  scene("unterminated_string", "name = \"probe\n" + base_scene, refused());
  scene("duplicate_key", "name = \"a\"\n" + base_scene, refused());
  // [report]
  scene("formats_empty", base_scene + "[report]\nformats = []\n", refused());
  scene("formats_unknown", base_scene + "[report]\nformats = [\"pdf\"]\n", refused());
  scene("formats_number", base_scene + "[report]\nformats = [1]\n", refused());
  scene("report_unknown_key", base_scene + "[report]\nformat = [\"json\"]\n", refused());
  // Unknown keys, wrong types.
  scene("unknown_top_key", "colour = 1\n" + base_scene, refused());
  scene("unknown_grid_key", base_scene + "[grid.extra]\nq = 1\n", refused());
  scene("unknown_solver_key", base_scene + "[[solver]]\nname = \"cvode-adams\"\nrtl = 1e-6\n",
        refused());
  scene("unknown_timing_key", base_scene + "[timing]\nrepeat = 2\n", refused());
  scene("name_number", "name = 5\n" + base_scene.substr(base_scene.find('\n') + 1), refused());
  scene("want_number", "want = 5\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [1.0]\n", refused());
  scene("want_unknown", "want = [\"speed\"]\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [1.0]\n",
        refused());
  scene("grid_number", "name = \"g\"\ngrid = 5\n", refused());
  scene("p_string", "[grid]\np = [\"one\"]\ne = [0.5]\nv0 = [1.0]\n", refused());
  scene("v0_boolean", "[grid]\np = [1.5]\ne = [0.5]\nv0 = true\n", refused());
  scene("p_date", "[grid]\np = 1979-05-27\ne = [0.5]\nv0 = [1.0]\n", refused());
  scene("solver_string", "solver = \"cvode\"\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [1.0]\n",
        refused());
  scene("solver_unknown", base_scene + "[[solver]]\nname = \"ode45\"\nrtol = 1e-6\n", refused());
  scene("end_unknown", "end = \"sideways\"\n" + base_scene, refused());
  // Negative and NaN grid values.
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"p", "-1.0"},
                                                        {"p", "nan"},
                                                        {"p", "inf"},
                                                        {"p", "1e18"},
                                                        {"v0", "-1.0"},
                                                        {"v0", "nan"},
                                                        {"v0", "1e-300"},
                                                        {"e", "nan"},
                                                        {"e", "-0.5"},
                                                        {"e", "0.0"},
                                                        {"m", "-inf"},
                                                        {"k", "0.0"},
                                                        {"k", "1e300"},
                                                        {"alpha_eff", "-1.0"},
                                                        {"alpha_eff", "nan"},
                                                        {"alpha_eff", "1e300"}}) {
    std::string grid = "[grid]\n";
    std::map<std::string, std::string> values{{"p", "[1.5]"}, {"v0", "[1.0]"}};
    if (key != "alpha_eff") {
      values["e"] = "[0.5]";
    }
    values[key] = "[1.0, " + value + "]";
    for (const auto& [k, v] : values) {
      grid += k + " = " + v + "\n";
    }
    scene("grid_" + key + "_" + value,
          "name = \"g\"\n" + grid + "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\n", refused());
  }
  // [grid] alpha, the equation's α (as --alpha): at every p, beside e and alpha_eff; beyond the
  // seed at one cell only.
  const std::string cvode = "[[solver]]\nname = \"cvode-bdf\"\nrtol = 1e-6\n" + json_only;
  scene("grid_alpha", "[grid]\np = [1.0, 1.5]\nalpha = [0.0, 0.3, 5.0]\nv0 = 1.0\n" + cvode, ok());
  scene("grid_alpha_with_e_and_alpha_eff",
        "[grid]\np = 1.5\ne = 0.5\nalpha = 0.3\nalpha_eff = 0.2\nv0 = 1.0\n" + cvode, ok());
  scene("grid_alpha_beyond_the_seed_one_cell",
        "[grid]\np = 1.5\ndamping_exponent = 0.5\nalpha = 0.3\nv0 = 2.0\n" + cvode, ok());
  scene("grid_alpha_beyond_the_seed_two_v0",
        "[grid]\np = 1.5\ndamping_exponent = 0.5\nalpha = 0.3\nv0 = [1.0, 2.0]\n" + cvode,
        refused(), err_mentions({"one v0, m and k"}));
  for (const char* alpha : {"-1.0", "nan", "inf", "1e9", "\"0.3\"", "[]", "true"}) {
    scene(std::string("grid_alpha_") + alpha,
          "[grid]\np = 1.5\nalpha = " + std::string(alpha) + "\nv0 = 1.0\n" + cvode, refused(),
          err_lacks("unknown key"));
  }
  // Solver sweeps with bad tolerances and steps.
  const std::string grid_only =
      "name = \"s\"\n[grid]\np = [1.5]\ne = [0.5]\nv0 = [1.0]\n" + json_only;
  for (const auto& [name, entry] : std::vector<std::pair<std::string, std::string>>{
           {"rtol_zero_in_sweep", "name = \"cvode-bdf\"\nrtol = [1e-6, 0.0]"},
           {"rtol_negative", "name = \"cvode-bdf\"\nrtol = [1e-6, -1e-6]"},
           {"rtol_nan", "name = \"cvode-bdf\"\nrtol = nan"},
           {"rtol_inf", "name = \"cvode-bdf\"\nrtol = inf"},
           {"rtol_one", "name = \"cvode-bdf\"\nrtol = 1.0"},
           {"rtol_below_epsilon", "name = \"cvode-bdf\"\nrtol = [1e-6, 1e-17]"},
           {"rtol_taylor_quad_below_epsilon",
            "name = \"taylor\"\nprecision = \"quad\"\nrtol = 1e-40"},
           {"rtol_empty_list", "name = \"cvode-bdf\"\nrtol = []"},
           {"rtol_string", "name = \"cvode-bdf\"\nrtol = \"tight\""},
           {"atol_huge", "name = \"cvode-bdf\"\nrtol = 1e-6\natol = 1e300"},
           {"atol_zero", "name = \"cvode-bdf\"\nrtol = 1e-6\natol = 0.0"},
           {"atol_negative", "name = \"cvode-bdf\"\nrtol = 1e-6\natol = -1.0"},
           {"steps_zero", "name = \"dem-verlet\"\nsteps_per_contact = [0]"},
           {"steps_huge", "name = \"dem-verlet\"\nsteps_per_contact = [1e10]"},
           {"steps_fraction", "name = \"dem-verlet\"\nsteps_per_contact = [2.5]"},
           {"onset_phases_zero", "name = \"dem-verlet\"\nonset_phases = 0"},
           {"precision_float", "name = \"taylor\"\nprecision = \"float\""}}) {
    scene("solver_" + name, grid_only + "[[solver]]\n" + entry + "\n", refused());
  }
  // repeats
  for (const char* repeats : {"0", "-1", "1000000000", "1.5", "\"3\""}) {
    scene(std::string("repeats_") + repeats, base_scene + "[timing]\nrepeats = " + repeats + "\n",
          refused());
  }
  // [limits]: a step budget every record runs out of, and bad limits.
  scene("limits_max_steps_10", base_scene + json_only + "[limits]\nmax_steps = 10\n", ok(),
        records_all_failed());
  for (const auto& [name, body] :
       std::vector<std::pair<std::string, std::string>>{{"max_steps_0", "max_steps = 0"},
                                                        {"max_steps_negative", "max_steps = -1"},
                                                        {"max_steps_fraction", "max_steps = 1.5"},
                                                        {"max_steps_string", "max_steps = \"x\""},
                                                        {"max_steps_huge", "max_steps = 1e300"},
                                                        {"max_steps_nan", "max_steps = nan"}}) {
    scene("limits_" + name, base_scene + json_only + "[limits]\n" + body + "\n", refused(),
          err_lacks("unknown key in the scene"));
  }
  scene("limits_unknown_key", base_scene + json_only + "[limits]\nmax_stepz = 10\n", refused(),
        err_mentions({"[limits]"}));
  scene("limits_not_a_table", "limits = 5\n" + base_scene + json_only, refused(),
        err_lacks("unknown key in the scene"));
  // The size of the plan: refused before any work, the size said.
  scene("huge_plan", huge_scene(), refused(), says_plan_size(), {}, 5);
  scene("huge_plan_max_runs_1000", huge_scene(), refused(),
        all_of({says_plan_size(), err_lacks("unknown argument")}), {"--max-runs", "1000"}, 5);
  scene("max_runs_below_plan",
        base_scene + json_only + "[[solver]]\nname = \"odeint-bs\"\nrtol = 1e-6\n", refused(),
        err_lacks("unknown argument"), {"--max-runs", "1"});
  scene("max_runs_above_plan", base_scene + json_only, ok(), nullptr, {"--max-runs", "100"});
  for (const char* n : {"0", "-1", "x", "", "1.5", "2e12", "1e99"}) {
    scene(std::string("max_runs_") + (n[0] ? n : "empty"), base_scene + json_only, refused(),
          err_lacks("unknown argument"), {"--max-runs", n});
  }
  // As --help writes defaults (issue 50: "1e6" was refused as "not an integer"), and read, not
  // ignored: 1e0 is the limit of 1 that refuses the plan above.
  scene("max_runs_1e6", base_scene + json_only, ok(), nullptr, {"--max-runs", "1e6"});
  scene("max_runs_1e0_below_plan",
        base_scene + json_only + "[[solver]]\nname = \"odeint-bs\"\nrtol = 1e-6\n", refused(),
        err_mentions({"above the limit of 1:"}), {"--max-runs", "1e0"});
  // Where the report cannot be written.
  add(t, "out_under_regular_file", {"run", "{dir}/scene.toml", "--out", "{dir}/file/sub"},
      refused(), nullptr, [](const fs::path& dir) {
        return write_text(dir / "scene.toml", base_scene + json_only) &&
                       write_text(dir / "file", "a regular file\n")
                   ? std::string()
                   : "cannot write";
      });
  add(t, "out_is_regular_file", {"run", "{dir}/scene.toml", "--out", "{dir}/file"}, refused(),
      nullptr, [](const fs::path& dir) {
        return write_text(dir / "scene.toml", base_scene + json_only) &&
                       write_text(dir / "file", "a regular file\n")
                   ? std::string()
                   : "cannot write";
      });
  add(t, "out_proc", {"run", "{dir}/scene.toml", "--out", "/proc/x"}, refused(), nullptr,
      write_scene(base_scene + json_only));
  add(t, "out_empty", {"run", "{dir}/scene.toml", "--out", ""}, refused(), nullptr,
      write_scene(base_scene + json_only));
  add(t, "out_newline", {"run", "{dir}/scene.toml", "--out", "{dir}/file/a\nb"}, refused(), nullptr,
      [](const fs::path& dir) {
        return write_text(dir / "scene.toml", base_scene + json_only) &&
                       write_text(dir / "file", "a regular file\n")
                   ? std::string()
                   : "cannot write";
      });
  add(t, "run_no_scene", {"run", "--out", "{dir}/out"}, refused(), no_report_folder());
  add(t, "run_two_scenes", {"run", "{dir}/scene.toml", "{dir}/scene.toml", "--out", "{dir}/out"},
      refused(), no_report_folder(), write_scene(base_scene + json_only));
  return t;
}

// -- check: a shipped trajectory (taylor, p = 1.5, e = 0.5, v0 = 1, every 0.1), its tolerance,
// arguments that contradict it.
std::vector<Case> check_cases() {
  std::vector<Case> t;
  const std::string file =
      std::string(PLDAMP_DATA_DIR) + "/trajectories/hertz_taylor_every_0.1.csv";
  const auto check = [&](std::vector<std::string> more) {
    return cat({"check", file, "--p", "1.5", "--e", "0.5", "--v0", "1"}, more);
  };
  add(t, "text", check({}), ok());
  add(t, "json", check({"--json"}), ok());
  add(t, "end_force", check({"--end", "force", "--json"}), ok());
  add(t, "alpha", {"check", file, "--p", "1.5", "--alpha", "0.4817692577645866", "--v0", "1"},
      ok());
  add(t, "alpha_eff",
      {"check", file, "--p", "1.5", "--alpha-eff", "0.2154537619662468", "--v0", "1", "--json"},
      ok());
  add(t, "missing_file", {"check", "{dir}/none.csv", "--p", "1.5", "--e", "0.5", "--v0", "1"},
      refused());
  add(t, "damping_exponent", check({"--damping-exponent", "0.5"}), refused(),
      err_mentions({"damping-exponent"}));
  add(t, "precision", check({"--precision", "quad"}), refused());
  // The file against its arguments (docs/check.md): another v0, a forgotten m or k.
  add(t, "v0_contradicts", {"check", file, "--p", "1.5", "--e", "0.5", "--v0", "2"}, refused(),
      err_mentions({"incoming speed"}));
  add(t, "k_contradicts", check({"--k", "7e9"}), refused(), err_mentions({"give --m and --k"}));
  add(t, "m_contradicts", check({"--m", "1e-300"}), refused());
  add(t, "k_m_scaled_together", check({"--m", "7", "--k", "7"}), ok()); // only k/m: consistent
  // --tolerance: within it (the file reads every observable within 2e-3), beyond it, per
  // observable, and what is refused.
  for (const char* tolerance :
       {"1e-2", "0.9999999", "e=1e-2,tau=1e-2", "tau=0.5", "delta_max=0.5"}) {
    add(t, std::string("tolerance_") + tolerance, check({"--tolerance", tolerance}), ok());
    add(t, std::string("tolerance_json_") + tolerance, check({"--tolerance", tolerance, "--json"}),
        ok());
  }
  for (const char* tolerance : {"1e-9", "5e-324", "e=1e-2,tau=1e-9", "t_peak=1e-12"}) {
    add(t, std::string("tolerance_fails_") + tolerance, check({"--tolerance", tolerance}),
        judged_failing());
    add(t, std::string("tolerance_fails_json_") + tolerance,
        check({"--tolerance", tolerance, "--json"}), judged_failing());
  }
  // At the force end, the file's own α (its e = 0.5 is the overlap end's).
  add(t, "tolerance_force_end",
      {"check", file, "--p", "1.5", "--alpha", "0.4817692577645866", "--v0", "1", "--end", "force",
       "--tolerance", "e_cap=1e-2,t_cut=1e-2"},
      ok());
  // A relative tolerance of 1 or more judges nothing (issue 29): refused.
  for (const char* tolerance : {"1", "1e308", "tau=1", "e=1e-3,tau=2"}) {
    add(t, std::string("tolerance_not_relative_") + tolerance, check({"--tolerance", tolerance}),
        refused(), err_mentions({"in (0, 1)"}));
  }
  for (const char* tolerance : {"0",
                                "-1e-3",
                                "nan",
                                "inf",
                                "-inf",
                                "1e400",
                                "e",
                                "e=",
                                "=1e-3",
                                "e=1e-3,",
                                ",e=1e-3",
                                "e=1e-3,,tau=1",
                                "e=1e-3,e=1e-2",
                                "speed=1e-3",
                                "e_cap=1e-3",
                                "E=1e-3",
                                "e = 1e-3",
                                "e=1e-3;tau=1e-3",
                                "e=0",
                                "tau=-1",
                                "tau=1e-3=2"}) {
    add(t, std::string("tolerance_bad_") + tolerance, check({"--tolerance", tolerance}), refused(),
        err_mentions({"tolerance"}));
  }
  add(t, "tolerance_bad_e_at_force_end", check({"--end", "force", "--tolerance", "e=1e-3"}),
      refused(), err_mentions({"e_cap"}));
  add(t, "tolerance_without_value", check({"--tolerance"}), refused());
  for (const Hostile& h : hostile_strings()) {
    add(t, "tolerance_hostile_" + h.name, check({"--tolerance", h.text}), refused());
  }
  return t;
}

// -- diff: a report made by a tiny scene, and damaged copies of it.
const std::string tiny_scene = R"(name = "tiny"
want = ["e", "delta_max", "t_peak", "tau", "energy"]
[grid]
p = 1.5
e = 0.5
v0 = 1.0
[[solver]]
name = "cvode-bdf"
rtol = 1e-6
[[claim]]
name = "tiny claim"
observable = "e"
solver = "cvode-bdf"
rtol = 1e-6
bound = 1e-3
[report]
formats = ["json"]
)";

// The text of a valid report.json, made once per process; "" with `why` set if it could not be.
const std::string& valid_report(std::string& why) {
  static std::string report, failure;
  static bool made = false;
  if (!made) {
    made = true;
    const fs::path dir =
        fs::temp_directory_path() / ("pldamp-probe-report-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    write_text(dir / "tiny.toml", tiny_scene);
    const Seen seen =
        run_isolated({"run", (dir / "tiny.toml").string(), "--out", (dir / "out").string()}, 60);
    if (seen.code == 0 && fs::exists(dir / "out" / "report.json")) {
      report = read_text(dir / "out" / "report.json");
    } else {
      failure = "the tiny scene did not make a report (exit " + std::to_string(seen.code) +
                "): " + escaped(first_line(seen.err));
    }
    fs::remove_all(dir);
  }
  why = failure;
  return report;
}

// old.json valid, new.json from `damage` (applied to the parsed report, or replacing the text).
Setup write_reports(std::function<std::string(const std::string& valid)> damage) {
  return [damage](const fs::path& dir) {
    std::string why;
    const std::string& valid = valid_report(why);
    if (valid.empty()) {
      return why;
    }
    if (!write_text(dir / "old.json", valid) || !write_text(dir / "new.json", damage(valid))) {
      return std::string("cannot write the reports");
    }
    return std::string();
  };
}

std::function<std::string(const std::string&)> edit(std::function<void(json&)> change) {
  return [change](const std::string& valid) {
    json j = json::parse(valid);
    change(j);
    return j.dump(1);
  };
}

std::vector<Case> diff_cases() {
  std::vector<Case> t;
  const std::vector<std::string> args{"diff", "{dir}/old.json", "{dir}/new.json"};
  const std::vector<std::string> reversed{"diff", "{dir}/new.json", "{dir}/old.json"};
  add(
      t, "valid_against_itself", {"diff", "{dir}/old.json", "{dir}/old.json"}, ok(),
      [](const Seen& seen, const fs::path&) {
        return seen.code == 0 && !contains(seen.out, "0 regressions")
                   ? std::string("stdout does not say 0 regressions")
                   : std::string();
      },
      write_reports([](const std::string& v) { return v; }));
  add(t, "valid_against_reformatted", args, ok(), nullptr, write_reports(edit([](json&) {})));
  add(t, "unknown_flag", cat(args, {"--frobnicate", "1"}), refused(), err_mentions({"frobnicate"}),
      write_reports([](const std::string& v) { return v; }));
  // Each field of a record removed, null, of another scalar type, an array.
  for (const char* field : {"key", "failed", "outcome", "rel_error"}) {
    const std::string f = field;
    const json wrong_scalar = (f == "key" || f == "outcome") ? json(5) : json("no");
    const std::vector<std::pair<std::string, std::function<void(json&)>>> damages{
        {"removed", [f](json& j) { j["records"][0].erase(f); }},
        {"null", [f](json& j) { j["records"][0][f] = nullptr; }},
        {"wrong_type", [f, wrong_scalar](json& j) { j["records"][0][f] = wrong_scalar; }},
        {"array", [f](json& j) {
           j["records"][0][f] = json::array({1, 2});
         }}};
    for (const auto& [how, damage] : damages) {
      add(t, "record_" + f + "_" + how, args, refused(), nullptr, write_reports(edit(damage)));
    }
    add(t, "old_record_" + f + "_null", reversed, refused(), nullptr,
        write_reports(edit([f](json& j) { j["records"][0][f] = nullptr; })));
  }
  add(t, "rel_error_negative", args, refused(), nullptr, write_reports(edit([](json& j) {
        for (auto& [k, v] : j["records"][0]["rel_error"].items()) {
          v = -1e-3;
        }
      })));
  add(t, "rel_error_string", args, refused(), nullptr, write_reports(edit([](json& j) {
        for (auto& [k, v] : j["records"][0]["rel_error"].items()) {
          v = "small";
        }
      })));
  add(t, "rel_error_huge_exponent", args, ok_or_refused(), nullptr,
      write_reports([](const std::string& valid) {
        json j = json::parse(valid);
        for (auto& [k, v] : j["records"][0]["rel_error"].items()) {
          v = 12345.0;
        }
        std::string text = j.dump(1);
        const std::size_t at = text.find("12345.0");
        return at == std::string::npos ? text : text.replace(at, 7, "1e999"); // inf as read
      }));
  add(t, "records_not_array", args, refused(), nullptr,
      write_reports(edit([](json& j) { j["records"] = json::object(); })));
  add(t, "record_not_object", args, refused(), nullptr,
      write_reports(edit([](json& j) { j["records"][0] = 7; })));
  add(t, "claims_missing", args, refused(), nullptr,
      write_reports(edit([](json& j) { j.erase("claims"); })));
  add(t, "claim_verdict_null", args, refused(), nullptr,
      write_reports(edit([](json& j) { j["claims"][0]["verdict"] = nullptr; })));
  add(t, "claim_name_array", args, refused(), nullptr,
      write_reports(edit([](json& j) { j["claims"][0]["name"] = json::array(); })));
  add(t, "record_precision_unknown", args, refused(), nullptr,
      write_reports(edit([](json& j) { j["records"][0]["precision"] = "float"; })));
  for (const auto& [name, schema] :
       std::vector<std::pair<std::string, json>>{{"0", json(0)},
                                                 {"1", json(1)},
                                                 {"string_1", json("1")},
                                                 {"null", json(nullptr)},
                                                 {"1_5", json(1.5)}}) {
    add(t, "schema_" + name, args, refused(), nullptr,
        write_reports(edit([schema](json& j) { j["schema"] = schema; })));
  }
  add(t, "truncated", args, refused(), nullptr,
      write_reports([](const std::string& v) { return v.substr(0, v.size() / 2); }));
  add(t, "empty_file", args, refused(), nullptr,
      write_reports([](const std::string&) { return std::string(); }));
  add(t, "not_json", args, refused(), nullptr,
      write_reports([](const std::string&) { return std::string("this is not json\n"); }));
  add(t, "binary", args, refused(), nullptr, write_reports([](const std::string&) {
        std::string garbage(1024, '\0');
        std::mt19937 random(7);
        for (char& c : garbage) {
          c = static_cast<char>(random() & 0xff);
        }
        return garbage;
      }));
  add(t, "json_array", args, refused(), nullptr,
      write_reports([](const std::string&) { return std::string("[1, 2, 3]\n"); }));
  add(t, "json_string", args, refused(), nullptr,
      write_reports([](const std::string&) { return std::string("\"report\"\n"); }));
  add(t, "nested_50_levels", args, refused(), nullptr, write_reports([](const std::string&) {
        std::string text;
        for (int i = 0; i < 50; ++i) {
          text += "{\"a\": ";
        }
        return text + "1" + std::string(50, '}') + "\n";
      }));
  add(t, "nested_100000_arrays", args, refused(), nullptr, write_reports([](const std::string&) {
        return std::string(100000, '[') + std::string(100000, ']') + "\n";
      }));
  add(t, "old_truncated", reversed, refused(), nullptr,
      write_reports([](const std::string& v) { return v.substr(0, v.size() / 3); }));
  add(t, "new_is_directory", {"diff", "{dir}/old.json", "{dir}"}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "old_is_directory", {"diff", "{dir}", "{dir}/old.json"}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "new_missing", {"diff", "{dir}/old.json", "{dir}/missing.json"}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "both_missing", {"diff", "{dir}/a.json", "{dir}/b.json"}, refused());
  add(t, "path_with_newline", {"diff", "{dir}/old.json", "{dir}/no\nsuch.json"}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "path_empty", {"diff", "{dir}/old.json", ""}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "one_argument", {"diff", "{dir}/old.json"}, refused(), nullptr,
      write_reports([](const std::string& v) { return v; }));
  add(t, "three_arguments", {"diff", "{dir}/old.json", "{dir}/old.json", "{dir}/old.json"},
      refused(), nullptr, write_reports([](const std::string& v) { return v; }));
  return t;
}

// ---------------------------------------------------------------------------------------------

std::vector<Case> unique(std::vector<Case> table) {
  std::map<std::string, int> seen;
  for (Case& c : table) {
    const int n = seen[c.name]++;
    if (n > 0) {
      c.name += '_';
      c.name += std::to_string(n + 1);
    }
  }
  return table;
}

class TempDir {
public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "pldamp-probe-XXXXXX").string();
    if (::mkdtemp(pattern.data()) != nullptr) {
      path_ = pattern;
    }
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path_.empty()) {
      fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
      fs::remove_all(path_, ignored);
    }
  }
  const fs::path& path() const { return path_; }

private:
  fs::path path_;
};

// "nan" in what the case feeds the program: its arguments and the files its setup wrote.
int nan_in_input(const std::vector<std::string>& args, const fs::path& dir) {
  int n = 0;
  for (const std::string& a : args) {
    n += count_word(a, "nan");
  }
  std::error_code ignored;
  for (const auto& entry : fs::recursive_directory_iterator(dir, ignored)) {
    if (entry.is_regular_file(ignored) && entry.file_size(ignored) < (4u << 20)) {
      n += count_word(read_text(entry.path()), "nan");
    }
  }
  return n;
}

class Probe : public ::testing::TestWithParam<Case> {};

TEST_P(Probe, Answers) {
  const Case& c = GetParam();
  const TempDir dir;
  ASSERT_FALSE(dir.path().empty()) << "mkdtemp failed";
  if (c.setup) {
    const std::string why = c.setup(dir.path());
    ASSERT_TRUE(why.empty()) << "setup: " << why;
  }
  std::vector<std::string> args;
  for (const std::string& a : c.args) {
    args.push_back(substitute(a, dir.path().string()));
  }
  const Seen seen = run_isolated(args, c.limit + 5);
  std::string problems = judge(c, args, seen, nan_in_input(args, dir.path()));
  if (c.extra && !seen.killed && seen.signal == 0) {
    if (std::string p = c.extra(seen, dir.path()); !p.empty()) {
      problems += (problems.empty() ? "" : "; ") + p;
    }
  }
  if (std::getenv("PLDAMP_PROBE_VERBOSE") != nullptr) { // every case's answer, for review
    std::fprintf(stderr, "[probe] %s | exit %d, %.3f s | %s\n", command_line(args).c_str(),
                 seen.code, seen.seconds,
                 escaped(first_line(seen.code == 0 ? seen.out : seen.err), 200).c_str());
  }
  if (!problems.empty()) {
    ADD_FAILURE() << command_line(args) << "\n  expected: " << describe(c.expect)
                  << "\n  wrong: " << problems << "\n  seen: exit " << seen.code << " in "
                  << seen.seconds << " s\n  stdout: \"" << escaped(seen.out, 400)
                  << "\"\n  stderr: \"" << escaped(seen.err, 400) << "\"";
  }
}

void PrintTo(const Case& c, std::ostream* os) {
  *os << command_line(c.args);
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.name;
}

INSTANTIATE_TEST_SUITE_P(Command, Probe, ::testing::ValuesIn(unique(command_cases())), case_name);
INSTANTIATE_TEST_SUITE_P(Calibrate, Probe, ::testing::ValuesIn(unique(calibrate_cases())),
                         case_name);
INSTANTIATE_TEST_SUITE_P(Observables, Probe, ::testing::ValuesIn(unique(observables_cases())),
                         case_name);
INSTANTIATE_TEST_SUITE_P(Solve, Probe, ::testing::ValuesIn(unique(solve_cases())), case_name);
INSTANTIATE_TEST_SUITE_P(Showcase, Probe, ::testing::ValuesIn(unique(showcase_cases())), case_name);
INSTANTIATE_TEST_SUITE_P(Run, Probe, ::testing::ValuesIn(unique(run_cases())), case_name);
INSTANTIATE_TEST_SUITE_P(Diff, Probe, ::testing::ValuesIn(unique(diff_cases())), case_name);
INSTANTIATE_TEST_SUITE_P(Check, Probe, ::testing::ValuesIn(unique(check_cases())), case_name);

// The table's own promise: every subcommand and every flag of each is probed.
TEST(ProbeTable, CoversEveryCommandAndFlag) {
  std::vector<Case> all;
  for (auto cases : {command_cases(), calibrate_cases(), observables_cases(), solve_cases(),
                     showcase_cases(), run_cases(), diff_cases(), check_cases()}) {
    all.insert(all.end(), cases.begin(), cases.end());
  }
  EXPECT_GE(all.size(), 220u);
  const std::map<std::string, std::vector<std::string>> flags{
      {"calibrate", {"--p", "--e", "--end", "--precision", "--json", "--code", "--limit-damping"}},
      {"observables",
       {"--p", "--e", "--alpha", "--alpha-eff", "--v0", "--m", "--k", "--precision", "--end",
        "--json"}},
      {"solve", {"--solver",      "--p",         "--e",
                 "--alpha",       "--alpha-eff", "--v0",
                 "--m",           "--k",         "--end",
                 "--precision",   "--rtol",      "--atol",
                 "--want",        "--dt",        "--steps-per-contact",
                 "--onset-phase", "--horizon",   "--sample-times",
                 "--max-steps",   "--json"}},
      {"run", {"--out", "--jobs", "--max-runs"}},
      {"diff", {}},
      {"check",
       {"--p", "--e", "--alpha", "--alpha-eff", "--v0", "--m", "--k", "--end", "--json",
        "--tolerance"}},
      {"showcase", {"--precision"}}};
  for (const auto& [command, wanted] : flags) {
    std::set<std::string> used;
    bool any = false;
    for (const Case& c : all) {
      if (!c.args.empty() && c.args.front() == command) {
        any = true;
        used.insert(c.args.begin(), c.args.end());
      }
    }
    EXPECT_TRUE(any) << command;
    for (const std::string& flag : wanted) {
      EXPECT_EQ(used.count(flag), 1u) << command << " " << flag;
    }
  }
}

} // namespace
} // namespace pldamp::robustness
