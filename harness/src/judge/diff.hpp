// `pldamp diff`: what regressed between two runs' report.json.
#pragma once

#include "pldamp/core/real_types.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pldamp::harness {

// The version of report.json (report/ writes it, diff reads it).
inline constexpr int report_schema = 1;

// The regressions from OLD to NEW (an error grown more than tenfold above the precision's noise,
// a claim that flipped from holds to fails, a record that now fails or is gone), one line each.
std::vector<std::string> regressions(const nlohmann::json& old_report,
                                     const nlohmann::json& new_report);

} // namespace pldamp::harness
