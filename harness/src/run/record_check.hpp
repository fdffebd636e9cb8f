// A record read back from bytes another process wrote (a shard file, for `pldamp merge`), held to
// what a run of this build could have written for its plan: a file is checksummed, but the
// checksum is easy to recompute by hand, so the checksum tells a torn file, and this tells a made
// one. A merged record is held to what any record's numbers say of each other
// (common/record_consistency.hpp: nothing NaN, only τ infinite, sizes and times ≥ 0, its error
// and relative error those of its value and reference, its values those its outcome leaves), and
// to what its solver's answers were held to when it ran: e within 1 + the configuration's
// allowance, an external program's values as run/answers.hpp's impossible_answer held its answers
// (each value alone where the record's onset phases may have given them), its truth the plan's to
// the bit (where the plan is its truth), its work and times within the run's limits.
#pragma once

#include "run/run.hpp"

#include <string>

namespace pldamp::harness {

// Why `record` cannot be one a run of `plan` wrote; empty when it can.
std::string impossible_record(const Plan& plan, const Record& record);

} // namespace pldamp::harness
