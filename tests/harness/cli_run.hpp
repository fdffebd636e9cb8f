// Runs the `pldamp` command line in-process, for the harness tests.
#pragma once

#include "pldamp/harness/cli.hpp"

#include <cmath>
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

// A name such as an option's: [a-z][a-z0-9-]*, at `at`; empty if none starts there. (No
// <regex>: GCC 12 warns falsely inside it under ASan at -O1, and CI builds with -Werror.)
inline std::string name_at(const std::string& text, std::size_t at) {
  std::size_t end = at;
  while (end < text.size() &&
         ((text[end] >= 'a' && text[end] <= 'z') ||
          (end > at && ((text[end] >= '0' && text[end] <= '9') || text[end] == '-')))) {
    ++end;
  }
  return text.substr(at, end - at);
}

// Every "--name" in `text` that starts a word (after a blank, '[', '(' or '|', or at the start).
inline std::set<std::string> options_in(const std::string& text) {
  std::set<std::string> out;
  for (std::size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at + 2)) {
    const bool starts_word =
        at == 0 || std::string(" \t\n[(|").find(text[at - 1]) != std::string::npos;
    const std::string name = name_at(text, at + 2);
    if (starts_word && !name.empty()) {
      out.insert("--" + name);
    }
  }
  return out;
}

// The options a command's --help lists (its "Options:" lines: blanks, perhaps "-x,", then
// "--name"), --help itself aside.
inline std::set<std::string> help_options(const std::string& command) {
  const CliRun help = run({command, "--help"});
  std::set<std::string> out;
  std::istringstream lines(help.out);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t first = line.find_first_not_of(' ');
    if (first == 0 || first == std::string::npos) {
      continue;
    }
    std::size_t at = first;
    if (line.compare(at, 1, "-") == 0 && line.compare(at, 2, "--") != 0 && line.size() > at + 3 &&
        line[at + 2] == ',') {
      at += 3; // "-h,"
    }
    if (line.compare(at, 2, "--") == 0) {
      const std::string name = name_at(line, at + 2);
      if (!name.empty() && name != "help") {
        out.insert("--" + name);
      }
    }
  }
  return out;
}

// |got − want| / |want|: a number the CLI printed against its expected value.
inline double relative(double got, double want) {
  return std::abs(got - want) / std::abs(want);
}

} // namespace pldamp::harness::testing
