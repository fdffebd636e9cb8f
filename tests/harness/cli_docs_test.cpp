// What docs/cli.md says of the command line against what the command line says of itself: its
// synopsis lists exactly the options of each command's --help, and every --code the docs name is
// taken by calibrate and listed in its --help. So they cannot drift.
// And every document the sources and the docs cite (a name ending in .md) is in the repository.
#include "cli_run.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace pldamp::harness {
namespace {

using testing::CliRun;
using testing::help_options;
using testing::options_in;
using testing::run;

std::string document(const char* name) {
  // A path, not a std::string sum: GCC 12 warns falsely (-Warray-bounds) on that sum here.
  std::ifstream in(std::filesystem::path(PLDAMP_DATA_DIR) / ".." / "docs" / name);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The synopsis: the block of `pldamp <command> ...` lines (and their continuation lines) under
// docs/cli.md's "## Synopsis", before "Examples:".
std::map<std::string, std::set<std::string>> synopsis() {
  const std::string text = document("cli.md");
  const std::size_t from = text.find("## Synopsis");
  const std::size_t to = text.find("Examples:", from);
  std::istringstream block(text.substr(from, to - from));
  std::map<std::string, std::set<std::string>> out;
  std::string command;
  for (std::string line; std::getline(block, line);) {
    if (line.rfind("pldamp ", 0) == 0) {
      std::istringstream words(line.substr(7));
      words >> command;
      line = line.substr(7 + command.size());
    } else if (line.rfind("        ", 0) != 0) {
      continue; // prose, blank lines
    }
    if (!command.empty()) {
      const std::set<std::string> found = options_in(line);
      out[command].insert(found.begin(), found.end());
    }
  }
  return out;
}

TEST(CliDocs, TheSynopsisListsExactlyTheOptionsOfEachCommandsHelp) {
  const auto documented = synopsis();
  const std::set<std::string> commands{"calibrate", "observables", "solve", "timestep", "run",
                                       "merge",     "diff",        "check", "showcase"};
  std::set<std::string> seen;
  for (const auto& [command, options] : documented) {
    seen.insert(command);
  }
  EXPECT_EQ(seen, commands);
  for (const std::string& command : commands) {
    const std::set<std::string> helped = help_options(command);
    const std::set<std::string>& documented_options =
        documented.count(command) != 0 ? documented.at(command) : std::set<std::string>{};
    EXPECT_FALSE(helped.empty()) << command;
    for (const std::string& option : helped) {
      EXPECT_EQ(documented_options.count(option), 1u)
          << "pldamp " << command << " --help lists " << option << "; docs/cli.md's synopsis does "
          << "not";
    }
    for (const std::string& option : documented_options) {
      EXPECT_EQ(helped.count(option), 1u) << "docs/cli.md's synopsis gives pldamp " << command
                                          << " " << option << "; its --help does not";
    }
  }
}

// Every `--code NAME` (or `--code A | B | C`, across lines) docs/calibrate.md writes.
std::set<std::string> documented_codes() {
  const std::string text = document("calibrate.md");
  std::set<std::string> out;
  for (std::size_t at = text.find("--code "); at != std::string::npos;
       at = text.find("--code ", at + 7)) {
    std::size_t next = at + 7;
    for (std::string name = testing::name_at(text, next); !name.empty();) {
      out.insert(name);
      next += name.size();
      const std::size_t bar = text.find_first_not_of(" \n", next);
      if (bar == std::string::npos || text[bar] != '|') {
        break;
      }
      next = text.find_first_not_of(" \n", bar + 1);
      name = next == std::string::npos ? "" : testing::name_at(text, next);
    }
  }
  return out;
}

TEST(CliDocs, EveryCodeTheDocsNameIsTakenByCalibrateAndListedInItsHelp) {
  const std::set<std::string> codes = documented_codes();
  EXPECT_GE(codes.size(), 12u); // the 9 conventions and LAMMPS's 3 velocity-dependent models
  const CliRun help = run({"calibrate", "--help"});
  const std::size_t at = help.out.find("--code");
  ASSERT_NE(at, std::string::npos);
  const std::string line = help.out.substr(at, help.out.find('\n', at) - at);
  std::set<std::string> listed;
  std::istringstream names(line.substr(line.rfind(": ") + 2));
  for (std::string name; std::getline(names, name, '|');) {
    listed.insert(name);
  }
  EXPECT_EQ(listed, codes) << line;
  for (const std::string& name : codes) {
    // Hertz: every code has a model at p = 1.5 but yade-viscel, a linear one (p = 1).
    const std::string p = name == "yade-viscel" ? "1" : "1.5";
    const CliRun r = run({"calibrate", "--code", name, "--p", p, "--e", "0.5", "--json"});
    EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find("\"code\": \"" + name + "\""), std::string::npos) << r.out;
  }
  const CliRun unknown = run({"calibrate", "--code", "ode45", "--p", "1.5", "--e", "0.5"});
  EXPECT_EQ(unknown.err, "error: unknown --code, expected " + line.substr(line.rfind(": ") + 2) +
                             " (got ode45)\n");
}

// The documents a file cites: each word ending in ".md" (letters, digits and "_./-" before it),
// other than the report.md a run writes.
std::vector<std::string> cited_documents(const std::string& text) {
  const auto in_name = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '/' ||
           c == '-';
  };
  std::vector<std::string> out;
  for (std::size_t at = text.find(".md"); at != std::string::npos; at = text.find(".md", at + 3)) {
    if (at + 3 < text.size() &&
        (std::isalnum(static_cast<unsigned char>(text[at + 3])) || text[at + 3] == '_')) {
      continue; // ".mdx", ".md_"...: not a document's name
    }
    std::size_t from = at;
    while (from > 0 && in_name(text[from - 1])) {
      --from;
    }
    std::string name = text.substr(from, at + 3 - from);
    while (!name.empty() && (name.front() == '.' || name.front() == '/') &&
           name.rfind("../", 0) != 0) {
      name.erase(0, 1); // a leading "./", or the dots of an ellipsis
    }
    if (name.size() > 3 && name != "report.md" && !name.ends_with("/report.md")) {
      out.push_back(name);
    }
  }
  return out;
}

TEST(CliDocs, EveryDocumentTheSourcesAndDocsCiteIsInTheRepository) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(PLDAMP_DATA_DIR).parent_path();
  // A bare name is looked for where a reader would: beside the citing file, at the top, in docs/.
  const auto found = [&](const fs::path& citing, const std::string& name) {
    for (const fs::path& base : {citing.parent_path(), root, root / "docs"}) {
      if (fs::is_regular_file(base / name)) {
        return true;
      }
    }
    return false;
  };
  const std::set<std::string> kinds{".cpp",  ".hpp", ".txt",   ".sh",  ".py",
                                    ".toml", ".md",  ".cmake", ".yml", ""};
  std::vector<fs::path> files{root / "CMakeLists.txt", root / "README.md"};
  for (const char* folder : {"core", "analytic", "solvers", "harness", "tests", "bench", "data",
                             "adapters", "scripts", "docs", ".ci"}) {
    if (!fs::is_directory(root / folder)) {
      continue;
    }
    for (const auto& entry : fs::recursive_directory_iterator(root / folder)) {
      if (entry.is_regular_file() && kinds.count(entry.path().extension().string()) != 0 &&
          entry.path().string().find("/fuzz/corpus") == std::string::npos) {
        files.push_back(entry.path());
      }
    }
  }
  std::size_t citations = 0;
  for (const fs::path& file : files) {
    std::ifstream in(file);
    std::ostringstream text;
    text << in.rdbuf();
    for (const std::string& name : cited_documents(text.str())) {
      ++citations;
      EXPECT_TRUE(found(file, name))
          << fs::relative(file, root).string() << " cites " << name << ", not in the repository";
    }
  }
  EXPECT_GT(citations, 100u); // MATH.md alone is cited in well over a hundred places
}

} // namespace
} // namespace pldamp::harness
