// Runs the `pldamp` command line in-process, for the harness tests.
#pragma once

#include "pldamp/harness/cli.hpp"

#include <regex>
#include <set>
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

// The digits of a JSON answer's number as printed (nlohmann would parse them into a double).
inline std::string raw_number(const std::string& json, const std::string& key) {
  const std::string quoted = "\"" + key + "\": ";
  const auto at = json.find(quoted);
  if (at == std::string::npos) {
    return "missing " + key;
  }
  const std::string rest = json.substr(at + quoted.size());
  return rest.substr(0, rest.find_first_of(",}"));
}

// The options a command's --help lists (its "Options:" lines), --help itself aside.
inline std::set<std::string> help_options(const std::string& command) {
  const CliRun help = run({command, "--help"});
  static const std::regex listed(R"(^\s+(?:-[a-z],)?(--[a-z][a-z0-9-]*))");
  std::set<std::string> out;
  std::istringstream lines(help.out);
  for (std::string line; std::getline(lines, line);) {
    std::smatch match;
    if (std::regex_search(line, match, listed) && match[1] != "--help") {
      out.insert(match[1]);
    }
  }
  return out;
}

} // namespace pldamp::harness::testing
