// The `pldamp` command line (docs/design.md §7), callable in-process so tests can check
// outputs and exit codes: 0 success, 2 bad input (one line "error: <what> (got <value>)" on
// `err`), 3 an internal failure (a non-finite result where a finite one was due).
#pragma once

#include <ostream>

namespace pldamp::harness {

class Distribution;

// `distribution`: the MPI job the program runs in (distribution.hpp), if any; `pldamp run` shares
// its cells among the ranks. `progress`: where `pldamp run` shows its progress (a bar on a
// terminal, else a line every 5 s); `err` without one. A stream that discards (no buffer)
// shows none: the Python module's default.
int run_cli(int argc, const char* const* argv, std::ostream& out, std::ostream& err,
            Distribution* distribution = nullptr, std::ostream* progress = nullptr);

} // namespace pldamp::harness
