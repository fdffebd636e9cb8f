// Claims judged on grids of their own (scene.hpp, RelationClaim to StabilityClaim), each into a
// verdict, the cell where it comes closest to failing, and a margin:
//
//   relation             per cell, a quantity (the truth in float128, or a solver in double)
//                        against a formula of the seed (analytic/seed.hpp) at the cell's inputs.
//                        equal_within: measured = the largest |a/f − 1| (|a − f| if absolute),
//                        holds if ≤ tolerance, margin = tolerance/measured. lower_bound (f ≤ a):
//                        measured = the smallest gap (a − f)/|f|, holds if ≥ −tolerance; cells
//                        equal within the tolerance are counted apart, and the margin is the
//                        smallest gap among the others (upper_bound the same with f − a).
//   asymptotic           per p, |a − f| at `points` α_eff log-spaced over `range` and the slope
//                        of its logarithm against log α_eff by least squares: the order at which
//                        the two agree; measured = the smallest order over p, holds if
//                        ≥ order − 0.05, margin = measured − order.
//   recovered_parameter  per cell, α found by TOMS 748 on the solver's e for the target e,
//                        against the seed's α(e): measured = the largest |α/α(e) − 1|, margin =
//                        bound/measured.
//   stability            per cell, the largest Δt at which the fixed-step scheme's contact ends
//                        without energy gained (e ≤ 1), scanning up from τ/1000 by 1.5× and
//                        then bisecting to 0.1 %, against the formula's Δt: measured = the
//                        smallest ratio, holds (the bound is conservative) if ≥ 1, margin =
//                        that ratio. Also e's relative error at the formula's Δt, in the note.
//
// A cell without an answer (a solver out of its limits, a formula not finite) fails the claim. A
// bound claim (judge/budget.cpp) also counts a cell without a value (a record skipped, a value
// the solver did not give, no truth) against it, unless it allows them (allow_missing): it then
// "holds on M of N cells", which `run --strict` still counts as not the verdict expected.
#pragma once

#include "judge/budget.hpp"
#include "judge/claim_grid.hpp"
#include "scene/scene.hpp"

namespace pldamp::harness {

// A claim's verdict with what the scene says of it (name, kind, source, expectation) and what its
// kind measures (observable, configuration, bound, meaning), not yet judged.
Verdict verdict_of(const Claim& claim);

// Judges a claim of the kinds relation, asymptotic, recovered_parameter or stability over its
// grid, and over the denser grid when the claim asks for it; its cells on the workers' threads
// and ranks, the verdict the same whatever their number (common/parallel.hpp, run/workers.hpp).
Verdict judge_on_grid(const Scene& scene, const Claim& claim, const Workers& workers = 1);

} // namespace pldamp::harness
