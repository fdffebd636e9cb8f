// A run shared among the processes of one job (MPI ranks): the `pldamp` program built with MPI
// (PLDAMP_MPI, harness/src/mpi/) gives run_cli one of these when mpirun or srun started it, and
// `pldamp run` then solves the plan's cells on every rank and writes the report on rank 0. The
// library itself never calls MPI: without one, or with one of size 1, a run is the serial run.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// Whether an MPI launcher started this process, by what mpirun (OMPI_*), PMIx launchers (srun
// --mpi=pmix) and PMI-1/2 ones set: only then does a build with MPI initialise it.
bool launched_by_mpi();

// srun -n N without an MPI plugin (docs/cluster.md's example once omitted --mpi=pmix) starts N
// serial processes: each would run the whole scene (`command` "run") or write the same report
// ("merge") into one folder, N times the work and N writers, all exiting 0. Throws
// std::invalid_argument (the one-line error) for a process srun started as one of several tasks
// that is no MPI rank; call it only where the process is not one (a task given its own --shard
// is a job array's, and fine).
void refuse_tasks_that_are_not_ranks(std::string_view command);

struct Plan;
struct Point;
struct Record;
class PlanRunner;
class RecordStore;

class Distribution {
public:
  virtual ~Distribution() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // The processes sharing this node (for --jobs' default: the node's cores among them).
  virtual int ranks_on_node() const = 0;
  // Called by every rank once its preparation (scene, plan, external programs) ended, with what
  // went wrong if anything did: true when every rank is ready. Otherwise false, and `why` is what
  // this rank should say (empty when another rank says it).
  virtual bool all_ready(const std::string& failure, std::string& why) = 0;
  // Every rank's `mine`, in rank order, on every rank (a collective: every rank calls it).
  virtual std::vector<std::string> all_gather(const std::string& mine) = 0;
  // Solves every record of the plan, each rank a share of its cells handed out as ranks ask for
  // more (one cell's cost differs ×10⁴ between a closed form and a float128 truth), on the rank's
  // own threads (`runner`). Rank 0 stores every record in `all` (its own, not sealed; the other
  // ranks pass none) and calls `progress`. A stop request (a signal on any rank) ends the handing
  // out: rank 0 then holds what was solved, with `stopped` set.
  virtual void run(const Plan& plan, PlanRunner& runner, RecordStore* all,
                   const std::function<void(std::size_t, std::size_t)>& progress,
                   bool& stopped) = 0;
  // Called by every rank together when the work the ranks share is over: the cells (run), then
  // the claims, searches and time-step study (make_budgets, run/workers.hpp); or when a piece of
  // that work failed, thrown on every rank alike (`failed_alike`: rank 0 alone says why). Until
  // then a rank that fails alone would leave the others waiting for it: it ends them all
  // (mpi_main.cpp). After it, a failure (rank 0's report) ends its rank alone.
  virtual void shared_work_done(bool failed_alike) { (void)failed_alike; }
};

// make_plan's points (PointMap, truth/plan.hpp) computed once in the run: rank r computes points
// r, r + N, r + 2N, ... of the `count` (point_at(i), on `jobs` threads) and the ranks exchange
// them as bytes, bit for bit, so that every rank holds the serial plan's points. A point that
// fails fails the plan on every rank alike, with the error the serial plan would throw (the
// lowest failing index's). A collective: every rank calls it.
std::vector<Point> points_on_ranks(Distribution& distribution, std::size_t count,
                                   const std::function<Point(std::size_t)>& point_at, int jobs);

// What rank `rank` says when not every rank is ready (Distribution::all_ready; `failures[r]`: what
// failed on rank r, empty where nothing did). Rank 0 says it, once, for every rank (mpirun may
// drop the last lines of a rank that is not 0 as it ends the job): what fails on rank 0 fails
// everywhere (the scene, its plan) and is said as it is; what fails on other ranks only (a file
// or program their node lacks, another copy of the scene) is the first such rank's, prefixed
// "rank R: ", with how many more failed. The other ranks say nothing. `speaks`: whether this
// rank's own failure is the message.
struct NotReady {
  std::string why;
  bool speaks = false;
};
NotReady not_ready_message(int rank, const std::vector<std::string>& failures);

} // namespace pldamp::harness
