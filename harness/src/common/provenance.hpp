// What made a file, for a reader who must trust it: the pldamp build (its version and the commit
// it was built from), when, on which host, by which command, from which scene text. report.json
// carries it as `run`, report.md and report.html in their first lines, `pldamp --version` prints
// the build, and `pldamp diff` says when two reports come from different builds.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// "VERSION+COMMIT" ("-dirty" with uncommitted changes to tracked files), fixed at build time
// (cmake/build_id.cmake). A shard set is merged only by the build that ran it.
std::string_view build_id();

// The process's command line, as the report names it: remembered once by run_cli.
void remember_command_line(const std::vector<std::string>& words);

struct Provenance {
  std::string build;                // build_id()
  std::string date;                 // UTC, ISO 8601 to the second
  std::string host;                 // gethostname
  std::vector<std::string> command; // argv, the program's name first
  std::string scene_checksum;       // FNV-1a of the scene file's text, 16 hex digits
};

// This process, now, for a scene of this text.
Provenance provenance_of(std::string_view scene_text);

// "pldamp BUILD on HOST, DATE: COMMAND" (a word holding a space or a quote quoted).
std::string provenance_line(const Provenance& made);

} // namespace pldamp::harness
