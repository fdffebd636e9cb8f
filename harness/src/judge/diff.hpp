// `pldamp diff`: what regressed between two runs' report.json.
#pragma once

#include "pldamp/core/real_types.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// The version of report.json (report/ writes it, diff reads it).
inline constexpr int report_schema = 1;

// A report.json's text, parsed and checked for everything `regressions` reads (schema, claims'
// names and verdicts, records' keys, outcomes, failed flags and errors); throws InputError
// naming `path` and the first thing amiss, so a damaged or foreign file is one line, exit 2.
nlohmann::json read_report(std::string_view text, const std::string& path);

// The regressions from OLD to NEW (an error grown more than tenfold above the precision's noise,
// a claim that flipped from holds to fails, a record that now fails or is gone), one line each.
std::vector<std::string> regressions(const nlohmann::json& old_report,
                                     const nlohmann::json& new_report);

} // namespace pldamp::harness
