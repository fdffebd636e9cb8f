// A record read back from bytes another process wrote (a shard file, for `pldamp merge`), held to
// what a run of this build could have written for its plan: a file is checksummed, but the
// checksum is easy to recompute by hand, so the checksum tells a torn file, and this tells a made
// one. A merged record is held to what its solver's answers were held to when it ran: every
// number finite (τ may be infinite against an infinite truth), no value outside its observable's
// range (pldamp's own solvers: e within 1 + the configuration's allowance, sizes and times ≥ 0;
// an external program's values as run/answers.hpp's impossible_answer holds its answers, each
// value alone where the record's onset phases may have given them), its truth the plan's to the
// bit (where the plan is its truth) and its error recomputed from its value and truth.
#pragma once

#include "run/run.hpp"

#include <string>

namespace pldamp::harness {

// Why `record` cannot be one a run of `plan` wrote; empty when it can.
std::string impossible_record(const Plan& plan, const Record& record);

} // namespace pldamp::harness
