// The size of a scene's plan before it is made: its solver runs counted from the scene alone
// (cells, configurations, onset phases, repeats, and the solves of its claims on grids of their
// own, its searches and its time-step study, as those are judged: judge/claims.hpp, search.hpp,
// step_study.hpp), printed as the run's first line and held to [limits] max_runs before anything
// is built. Here rather than in truth/: the judged solves are bounded by the algorithms that
// make them, which live in judge/.
#pragma once

#include "scene/scene.hpp"

#include <ostream>
#include <string>

namespace pldamp::harness {

// The grid's cells (as a double: a hostile grid overflows long).
double grid_cells(const Scene& scene);
// The solves of the claims judged on grids of their own, the searches and the time-step study.
double claim_and_search_runs(const Scene& scene);
// Every solver run the scene asks for: cells × each configuration's onset phases × repeats
// (claim configurations on the plan included), and claim_and_search_runs.
double planned_runs(const Scene& scene);

// The plan's size, refused beyond scene.limits.max_runs (InputError naming `scene_path`). The
// grid's runs are shared among `shares` processes (shards or ranks), and among MPI ranks
// (`judging_shared`) the claims' and searches' solves too (run/workers.hpp), which a shard set's
// merge makes in one process: the limit counts one process's.
void check_plan_size(const Scene& scene, const std::string& scene_path, double shares,
                     bool judging_shared);
// The plan's size as the run's first line: cells, configurations, solver runs, report.json's size.
void print_plan_size(const Scene& scene, std::ostream& out);

} // namespace pldamp::harness
