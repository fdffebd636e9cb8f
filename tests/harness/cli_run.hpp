// Runs the `pldamp` command line in-process, for the harness tests.
#pragma once

#include "pldamp/harness/cli.hpp"

#include <sstream>
#include <string>
#include <vector>

namespace pldamp::harness::testing {

struct CliRun {
  int code;
  std::string out, err;
};

inline CliRun run(std::vector<std::string> args) {
  args.insert(args.begin(), "pldamp");
  std::vector<const char*> argv;
  for (const std::string& a : args) {
    argv.push_back(a.c_str());
  }
  std::ostringstream out, err;
  const int code = run_cli(static_cast<int>(argv.size()), argv.data(), out, err);
  return {code, out.str(), err.str()};
}

} // namespace pldamp::harness::testing
