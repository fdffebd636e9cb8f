// Starting another program without a shell: an argument vector (argv[0] looked up on PATH), its
// standard input written from a string, its standard output read into one, its standard error
// discarded, a wall-clock limit. No temporary file, no string ever interpreted by a shell.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace pldamp::harness {

struct ProgramRun {
  bool started = false;   // false: the program could not be started (not found, not executable)
  bool timed_out = false; // killed at the limit
  int exit_code = -1;     // its exit status; -1 if it was killed or died by a signal
  std::string out;        // what it wrote on standard output
  bool succeeded() const { return started && !timed_out && exit_code == 0; }
};

ProgramRun run_program(const std::vector<std::string>& argv, const std::string& input,
                       std::chrono::milliseconds limit = std::chrono::seconds(60));

} // namespace pldamp::harness

namespace pldamp::harness {

// A program kept running and spoken to in lines (the external-solver protocol, docs/external.md
// "Your code in the loop"): lines written to its standard input, lines read from its standard
// output within a time limit, the last line of its standard error kept for messages. Started with
// an argument vector, never a shell, in a process group of its own: finish() stops the group, so
// what the program forked (and left running, holding its pipes) goes with it. Killed when destroyed
// if it has not exited by then.
class LineProgram {
public:
  // Starts argv (argv[0] looked up on PATH unless it names a path); started() tells. While
  // `stop` (a signal handler's flag) is set, no wait for the program goes on: it says `stopped`.
  explicit LineProgram(const std::vector<std::string>& argv,
                       const std::atomic<bool>* stop = nullptr);
  LineProgram(const LineProgram&) = delete;
  LineProgram& operator=(const LineProgram&) = delete;
  ~LineProgram();

  bool started() const { return pid_ > 0; }
  enum class Write { done, closed, timeout, stopped };
  // Writes `line` and a newline within `limit`: `closed` when the program no longer reads (it
  // exited or closed its input), `timeout` when it did not take the line in time.
  Write write_line(const std::string& line, std::chrono::milliseconds limit);

  enum class Read { line, end, timeout, too_long, stopped };
  // The next line of its standard output (without the newline) within `limit`; `end` when it
  // closed its output or exited (at once, though a child it forked holds its output open: looked
  // at every 10 ms), `too_long` for a line beyond max_line_bytes.
  Read read_line(std::string& line, std::chrono::milliseconds limit);
  // Closes its standard input and waits up to `limit` for it to exit; then stops its process
  // group: SIGTERM, and SIGKILL to what is left after `limit` more.
  void finish(std::chrono::milliseconds limit = std::chrono::seconds(2));
  // How it ended, after finish(): "exited with status 3", "killed by signal 11", or, when finish()
  // killed it, "stopped answering but did not exit (pldamp stopped it)" (not "killed by signal 9",
  // which read as a crash of its own).
  std::string status() const { return status_; }
  // The last non-empty line it wrote on standard error (at most 300 characters), or "".
  std::string last_error_line() const;

  static constexpr std::size_t max_line_bytes = 1 << 20;

private:
  void drain_error(); // reads what standard error holds without waiting
  bool read_output(); // reads what standard output holds, once; false if nothing
  bool has_exited();  // the program itself (not its children), without reaping it
  bool stop_requested() const;
  int pid_ = -1; // also its process group's id
  bool exited_ = false;
  const std::atomic<bool>* stop_ = nullptr;
  int in_ = -1, out_ = -1, err_ = -1;
  std::string pending_; // read from standard output, not yet returned as a line
  std::string error_;   // the tail of standard error
  std::string status_;
};

} // namespace pldamp::harness
