// `pldamp` under mpirun or srun (built with PLDAMP_MPI): the ranks share a run's cells, handed
// out by rank 0 as ranks ask for more, and rank 0 writes the one report (distribution.hpp).
//
// Protocol, on MPI_COMM_WORLD: a rank other than 0 sends a request (tag_request: a byte saying
// whether it was stopped, then the records of the chunk it solved last, shard.hpp's bytes) and
// receives the next chunk's number (tag_chunk; −1: none left, the rank is done). Rank 0 solves
// chunks too, on a thread of its own, while its main thread answers the requests (MPI is called
// from the main thread only: MPI_THREAD_FUNNELED). Chunks are runs of consecutive cells, which
// share p and β, so that a chunk's fixed-step records still fill SIMD batches (run.cpp).
#include "mpi/mpi_main.hpp"

#include "pldamp/harness/cli.hpp"
#include "pldamp/harness/distribution.hpp"
#include "run/record_store.hpp"
#include "run/run.hpp"
#include "run/shard.hpp"

#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace pldamp::harness {
namespace {

constexpr int tag_request = 1, tag_chunk = 2;

class MpiDistribution final : public Distribution {
public:
  MpiDistribution() {
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &node_ranks_);
    MPI_Comm_free(&node);
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int ranks_on_node() const override { return node_ranks_; }

  bool all_ready(const std::string& failure, std::string& why) override {
    const std::vector<std::string> failures = all_gather(failure);
    if (std::all_of(failures.begin(), failures.end(), [](auto& f) { return f.empty(); })) {
      speaks_ = true; // from here on a failure is this rank's own
      return true;
    }
    const NotReady said = not_ready_message(rank_, failures);
    why = said.why;
    speaks_ = said.speaks;
    return false;
  }

  std::vector<std::string> all_gather(const std::string& mine) override {
    // The sizes first, which every rank checks alike: no rank leaves the collective alone.
    const auto size = static_cast<std::int64_t>(mine.size());
    std::vector<std::int64_t> sizes(static_cast<std::size_t>(size_));
    MPI_Allgather(&size, 1, MPI_INT64_T, sizes.data(), 1, MPI_INT64_T, MPI_COMM_WORLD);
    std::vector<int> counts, offsets;
    std::int64_t total = 0;
    for (const std::int64_t bytes : sizes) {
      if (total + bytes > INT_MAX) {
        throw std::length_error("the ranks' shares of the plan exceed one MPI message (2 GiB)");
      }
      counts.push_back(static_cast<int>(bytes));
      offsets.push_back(static_cast<int>(total));
      total += bytes;
    }
    std::string all(static_cast<std::size_t>(total), '\0');
    MPI_Allgatherv(mine.data(), static_cast<int>(size), MPI_BYTE, all.data(), counts.data(),
                   offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
    std::vector<std::string> shares;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      shares.push_back(
          all.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(counts[r])));
    }
    return shares;
  }

  void run(const Plan& plan, PlanRunner& runner, RecordStore* all,
           const std::function<void(std::size_t, std::size_t)>& progress, bool& stopped) override {
    running_ = true;
    const std::size_t cells = plan.cells.size();
    // Chunks of 16 cells or more where the grid allows, so that a fixed-step configuration's
    // records still fill their 16-lane batches (one cell a chunk made quick.toml's
    // verlet-predicted cost twice its CPU); up to 16 a rank, so that the last ranks finish
    // together when cells' costs differ; and at least 4 a rank, where there are cells enough.
    const std::size_t ranks = static_cast<std::size_t>(size_);
    const std::size_t chunks =
        std::max({std::size_t(1), std::min(cells, 4 * ranks), std::min(cells / 16, 16 * ranks)});
    const auto chunk_cells = [&](std::size_t chunk) {
      std::vector<std::size_t> mine;
      for (std::size_t cell = chunk * cells / chunks; cell < (chunk + 1) * cells / chunks; ++cell) {
        mine.push_back(cell);
      }
      return mine;
    };
    if (rank_ == 0) {
      if (all == nullptr || all->size() != cells * plan.configs.size()) {
        throw std::logic_error("rank 0 has no store for the plan's records");
      }
      hand_out(plan, runner, *all, chunks, chunk_cells, progress, stopped);
    } else {
      ask_for_work(runner, chunk_cells);
    }
  }

  void shared_work_done(bool failed_alike) override {
    running_ = false;
    speaks_ = speaks_ && !failed_alike;
  }

  // Whether this rank should print its error (rank 0 says what fails on every rank), and whether
  // it failed amid the shared work, where the other ranks wait for it: MPI_Abort then.
  bool speaks() const { return rank_ == 0 || speaks_; }
  bool failed_while_running() const { return running_; }

private:
  template <class ChunkCells>
  void hand_out(const Plan& plan, PlanRunner& runner, RecordStore& all, std::size_t chunks,
                ChunkCells&& chunk_cells,
                const std::function<void(std::size_t, std::size_t)>& progress, bool& stopped) {
    const std::size_t configs = plan.configs.size();
    std::size_t placed = 0;
    std::mutex lock;
    std::size_t next_chunk = 0;
    const auto take = [&]() -> std::optional<std::size_t> {
      const std::lock_guard guard(lock);
      if (stop_requested() || next_chunk == chunks) {
        return std::nullopt;
      }
      return next_chunk++;
    };
    // A record into its place in plan order, as its bytes (those a rank sent, or its own
    // encoded): a record outside the plan or placed twice is a rank that misbehaved.
    const auto place = [&](const Record& record, std::string_view bytes) {
      const std::size_t at = record.cell * configs + record.config;
      if (record.cell >= plan.cells.size() || record.config >= configs || all.has(at)) {
        throw std::runtime_error("a rank sent a record outside the plan or twice (cell " +
                                 std::to_string(record.cell) + ")");
      }
      if (bytes.empty()) {
        all.put(at, record);
      } else {
        all.put_bytes(at, bytes);
      }
      const std::lock_guard guard(lock);
      if (progress) {
        progress(++placed, all.size());
      } else {
        ++placed;
      }
    };
    std::exception_ptr thrown;
    std::thread own([&] {
      try {
        while (const std::optional<std::size_t> chunk = take()) {
          for (const Record& record : runner.run_cells(chunk_cells(*chunk))) {
            place(record, {});
          }
        }
      } catch (...) {
        thrown = std::current_exception();
      }
    });
    try {
      answer_requests(take, place);
    } catch (...) {
      stop_requested() = true; // this rank's own chunks end too, and the thread with them
      own.join();
      throw;
    }
    own.join();
    if (thrown) {
      std::rethrow_exception(thrown);
    }
    stopped = a_rank_stopped_ || stop_requested();
    if (!stopped && placed != all.size()) {
      throw std::logic_error("the ranks returned " + std::to_string(placed) + " of " +
                             std::to_string(all.size()) + " records");
    }
  }

  // Rank 0's main thread: each request's records placed, the next chunk (or −1) sent back, until
  // every other rank has been told there is none.
  template <class Take, class Place>
  void answer_requests(Take&& take, Place&& place) {
    int working = size_ - 1;
    while (working > 0) {
      int arrived = 0;
      MPI_Status status;
      MPI_Iprobe(MPI_ANY_SOURCE, tag_request, MPI_COMM_WORLD, &arrived, &status);
      if (arrived == 0) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        continue;
      }
      int bytes = 0;
      MPI_Get_count(&status, MPI_BYTE, &bytes);
      std::string message(static_cast<std::size_t>(bytes), '\0');
      MPI_Recv(message.data(), bytes, MPI_BYTE, status.MPI_SOURCE, tag_request, MPI_COMM_WORLD,
               MPI_STATUS_IGNORE);
      if (message.empty() || static_cast<unsigned char>(message[0]) > 1) {
        throw std::runtime_error("rank " + std::to_string(status.MPI_SOURCE) +
                                 " sent a message pldamp does not write");
      }
      if (message[0] == 1) { // a signal there: no report; every rank stops
        a_rank_stopped_ = true;
        stop_requested() = true;
      }
      for_each_record_bytes(std::string_view(message).substr(1),
                            "rank " + std::to_string(status.MPI_SOURCE) + "'s records",
                            [&](Record&& record, std::string_view held) { place(record, held); });
      const std::int64_t chunk = [&]() -> std::int64_t {
        const std::optional<std::size_t> next = take();
        return next ? static_cast<std::int64_t>(*next) : -1;
      }();
      MPI_Send(&chunk, 1, MPI_INT64_T, status.MPI_SOURCE, tag_chunk, MPI_COMM_WORLD);
      working -= chunk < 0 ? 1 : 0;
    }
  }

  template <class ChunkCells>
  void ask_for_work(PlanRunner& runner, ChunkCells&& chunk_cells) {
    std::vector<Record> solved;
    for (;;) {
      std::string message(1, stop_requested() ? 1 : 0);
      append_records(message, solved);
      if (message.size() > static_cast<std::size_t>(INT_MAX)) {
        throw std::length_error("a chunk's records exceed one MPI message (2 GiB)");
      }
      MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, 0, tag_request,
               MPI_COMM_WORLD);
      std::int64_t chunk = -1;
      MPI_Recv(&chunk, 1, MPI_INT64_T, 0, tag_chunk, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      if (chunk < 0) {
        return;
      }
      solved = stop_requested() ? std::vector<Record>{}
                                : runner.run_cells(chunk_cells(static_cast<std::size_t>(chunk)));
    }
  }

  int rank_ = 0, size_ = 1, node_ranks_ = 1;
  bool speaks_ = false, running_ = false;
  bool a_rank_stopped_ = false; // a request said its rank was stopped (rank 0)
};

} // namespace

int run_under_mpi(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  if (provided < MPI_THREAD_FUNNELED) {
    std::cerr << "error: internal: this MPI cannot be used from a threaded program\n";
    MPI_Abort(MPI_COMM_WORLD, 3);
  }
  MpiDistribution distribution;
  // Rank 0 prints; the others only what fails on them alone.
  std::ostringstream quiet_out, held_err;
  const bool first = distribution.rank() == 0;
  const int code = run_cli(argc, argv, first ? std::cout : quiet_out, first ? std::cerr : held_err,
                           &distribution);
  if (!first && distribution.speaks()) {
    std::cerr << held_err.str() << std::flush;
  }
  if (code != 0 && distribution.failed_while_running()) {
    // The other ranks wait on this one: end them all.
    MPI_Abort(MPI_COMM_WORLD, code);
  }
  MPI_Finalize();
  return code;
}

} // namespace pldamp::harness
