// Starting another program without a shell: an argument vector (argv[0] looked up on PATH), its
// standard input written from a string, its standard output read into one, its standard error
// discarded, a wall-clock limit. No temporary file, no string ever interpreted by a shell.
#pragma once

#include <chrono>
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
