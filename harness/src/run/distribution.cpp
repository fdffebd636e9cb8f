// The parts of a run shared among MPI ranks that need no MPI (distribution.hpp).
#include "pldamp/harness/distribution.hpp"

#include "common/input.hpp"
#include "common/parallel.hpp"
#include "run/run.hpp"
#include "run/workers.hpp"
#include "scene/scene.hpp"
#include "truth/point_bytes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <limits>
#include <stdexcept>

namespace pldamp::harness {

bool launched_by_mpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(name) != nullptr) {
      return true;
    }
  }
  return false;
}

void refuse_tasks_that_are_not_ranks(std::string_view command) {
  const char* task = std::getenv("SLURM_PROCID");
  const char* tasks = std::getenv("SLURM_STEP_NUM_TASKS");
  if (task == nullptr || tasks == nullptr || std::atol(tasks) <= 1) {
    return;
  }
  if (command == "merge") {
    throw InputError(fmt::format("started by srun as task {} of {}: merge is one process's work, "
                                 "each task would write the same report; run it as one task (got "
                                 "SLURM_PROCID={} SLURM_STEP_NUM_TASKS={})",
                                 task, tasks, task, tasks));
  }
  // Under an MPI launch yet not a rank here: this build has no MPI.
  throw InputError(fmt::format(
      "started by srun as task {} of {} but not as an MPI rank: each task would run the whole "
      "scene into one folder; {} (got SLURM_PROCID={} SLURM_STEP_NUM_TASKS={})",
      task, tasks,
      launched_by_mpi() ? "this pldamp was built without MPI: give each task its own --shard K/N "
                          "and --out, or run one task"
                        : "add --mpi=pmix to srun for MPI ranks, or give each task its own "
                          "--shard K/N and --out",
      task, tasks));
}

NotReady not_ready_message(int rank, const std::vector<std::string>& failures) {
  if (rank != 0) {
    return {};
  }
  if (!failures.at(0).empty()) {
    return {failures[0], true};
  }
  const auto failed = [](const std::string& f) { return !f.empty(); };
  const auto first = std::find_if(failures.begin(), failures.end(), failed);
  if (first == failures.end()) {
    return {};
  }
  const auto more = std::count_if(first + 1, failures.end(), failed);
  return {"rank " + std::to_string(first - failures.begin()) + ": " + *first +
              (more == 0 ? ""
                         : " (and " + std::to_string(more) + " more rank" + (more == 1 ? "" : "s") +
                               " could not start)"),
          false};
}

std::vector<std::string> exchange_pieces(Distribution& ranks, const std::string& results,
                                         std::size_t failed_at, std::exception_ptr failure) {
  // What a failed piece threw, as the command line tells them apart (cli.cpp).
  enum : std::uint8_t { none, scene_error, input_error, internal_error };
  std::uint8_t kind = none;
  std::string why;
  if (failure) {
    try {
      std::rethrow_exception(failure);
    } catch (const SceneError& e) {
      kind = scene_error;
      why = e.what();
    } catch (const std::invalid_argument& e) {
      kind = input_error;
      why = e.what();
    } catch (const std::exception& e) {
      kind = internal_error;
      why = e.what();
    } catch (...) {
      kind = internal_error;
      why = "an unknown exception";
    }
  }
  std::string bytes;
  ByteWriter out(bytes);
  // Stopped: by which signal (1 when by another rank's, not known here).
  out.put<std::uint8_t>(
      stop_requested() ? static_cast<std::uint8_t>(std::clamp(stop_signal().load(), 1, 255)) : 0);
  out.put(kind);
  out.put<std::uint64_t>(failed_at);
  out.put(why);
  bytes += results;
  std::vector<std::string> shares = ranks.all_gather(bytes);
  std::uint64_t first_failure = std::numeric_limits<std::uint64_t>::max();
  std::uint8_t first_kind = none;
  std::string first_why;
  for (std::size_t r = 0; r < shares.size(); ++r) {
    ByteReader in(shares[r], "rank " + std::to_string(r) + "'s results");
    if (const std::uint8_t stopped = in.get<std::uint8_t>(); stopped != 0) {
      stop_requested() = true;
      int none = 0;
      if (stopped > 1) { // the first rank's signal, kept once known
        stop_signal().compare_exchange_strong(none, stopped);
      }
    }
    const auto said_kind = in.get<std::uint8_t>();
    const auto at = in.get<std::uint64_t>();
    std::string said = in.string();
    if (said_kind > internal_error) {
      in.corrupt();
    }
    if (said_kind != none && at < first_failure) {
      first_failure = at;
      first_kind = said_kind;
      first_why = std::move(said);
    }
    shares[r].erase(0, shares[r].size() - in.rest().size());
  }
  if (first_kind != none) {
    ranks.shared_work_done(true); // every rank throws it: none waits for another
  }
  switch (first_kind) {
  case scene_error:
    throw SceneError(first_why);
  case input_error:
    throw InputError(first_why);
  case internal_error:
    throw InternalError(first_why);
  default:
    return shares;
  }
}

// A point as a piece of a shared map (run/workers.hpp).
void put_piece(ByteWriter& out, const Point& point) {
  put_point(out, point);
}
void get_piece(ByteReader& in, Point& point) {
  point = get_point(in);
}

std::vector<Point> points_on_ranks(Distribution& distribution, std::size_t count,
                                   const std::function<Point(std::size_t)>& point_at, int jobs) {
  return map_shared<Point>(count, Workers(jobs, &distribution), point_at);
}

} // namespace pldamp::harness
