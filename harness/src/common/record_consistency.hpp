// What a record's numbers say of each other, as run/run.cpp makes them (Record, run/run.hpp) and
// report.json writes them (docs/run.md "Reports"). Per observable: the signed error is value −
// reference and the relative error |error| / |reference| (|error| where the reference is 0 or
// infinite, and for e compared absolutely on a late return), both computed in Exact from the
// solver's value and the truth and rounded once to double, as the value and the reference are;
// nothing is NaN, only τ infinite (a contact that never ends); sizes and times are not negative,
// nor is a spread over the onset phases or a difference from a replica. Per record: nothing
// measured when the solver threw, gave an impossible answer (unstable) or was skipped, nothing
// after the peak at `peak`, and e = 0 at `no_exit`.
//
// Two readers hold records to these, so that a record is judged alike wherever it comes from:
// `pldamp merge` (run/record_check.cpp: a shard's records, infinities kept, and what only the plan
// tells beside: the truth to the bit, the ranges of e and of the energies, the work, the times),
// and report.json's reader for `pldamp diff` (common/report_schema.cpp: JSON writes an infinity as
// null, and a record's outcome and failed flag are a word and a flag to check too).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace pldamp::harness {

// A record's outcome when its solver threw, and when it was skipped (an external program's cell it
// does not run); else the solver's outcome (solvers::outcome_name).
inline constexpr std::string_view threw_outcome = "error";
inline constexpr std::string_view skipped_outcome = "skipped";

// One observable's numbers in a record; none where the record has none.
struct ObservedNumbers {
  std::string_view key; // the observable's: "e"
  std::optional<double> value{}, reference{}, error{}, rel_error{}, spread{}, replica_difference{};
};

// What a record's numbers stand beside: its outcome's name, and whether it ran several onset
// phases (its numbers are then those of its worst phase, whose outcome need not be the record's:
// the record keeps its first phase's unless one fails).
struct RecordRun {
  std::string_view outcome;
  bool several_phases = false;
};

// Why one observable's numbers cannot be ones a run made; empty when they can.
std::string inconsistent_numbers(const ObservedNumbers& numbers, const RecordRun& run);

// Why a record's values cannot stand beside its outcome; empty when they can. With several onset
// phases the outcome is the first phase's while each value is its worst phase's: no_exit beside
// another phase's e is what a run writes.
std::string inconsistent_with_outcome(const RecordRun& run,
                                      std::span<const ObservedNumbers> observed);

// A record of report.json as its reader has it: each of its numbers none where it is null or
// absent (or not a number).
struct ReportedRecord {
  RecordRun run;
  bool failed = false;      // its "failed"
  bool has_failure = false; // a "failure" text
  std::span<const ObservedNumbers> observed;
};

// Why a record of report.json cannot be one a run wrote; empty when it can: an outcome no record
// has, a failed flag its outcome or failure contradicts (a record fails when its solver threw or
// its outcome fails, and when it has a failure; a skipped one never), values its outcome leaves
// none of, or numbers that disagree (inconsistent_numbers, a null value and reference beside a τ's
// error being the infinities JSON cannot write).
std::string inconsistent_reported(const ReportedRecord& record);

} // namespace pldamp::harness
