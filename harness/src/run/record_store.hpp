// A run's records where one process gathers them all (rank 0 under MPI, `pldamp merge`): held as
// their bytes (run/shard.hpp's, about 500 B a record, against 1.4 KB decoded) in a file of their
// own beside the report, which the system pages in and out as it needs, and decoded one at a time
// as the budgets and the report files read them in plan order. The process then holds 8 bytes a
// record (where each one is) besides its plan. The file is unlinked as soon as it is made: a run
// that ends, or is killed, leaves nothing behind.
#pragma once

#include "common/files.hpp"
#include "run/run.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

class RecordStore {
public:
  // Room for `count` records, in a file made in `folder` (InputError when it cannot be).
  RecordStore(std::size_t count, const std::filesystem::path& folder);
  ~RecordStore();
  RecordStore(const RecordStore&) = delete;
  RecordStore& operator=(const RecordStore&) = delete;

  std::size_t size() const { return where_.size(); }
  // Record `index` (its place in plan order), once each; safe from several threads. put_bytes
  // takes one record's bytes as shard.hpp writes them (for_each_record_bytes).
  void put(std::size_t index, const Record& record);
  void put_bytes(std::size_t index, std::string_view bytes);
  bool has(std::size_t index) const { return where_.at(index) != absent; }
  std::size_t stored() const { return stored_; }
  // Ends the writing; then records are read, from any thread.
  void seal();
  Record at(std::size_t index) const;

private:
  static constexpr std::uint64_t absent = ~std::uint64_t{0};
  void flush();
  std::filesystem::path folder_;
  Descriptor file_;
  std::vector<std::uint64_t> where_; // each record's offset in the file
  std::uint64_t written_ = 0;        // bytes in the file, the buffer's beyond them
  std::string buffer_;
  std::size_t stored_ = 0;
  std::mutex lock_;
  const char* mapped_ = nullptr;
  std::size_t mapped_size_ = 0;
};

// A run's records in plan order, one at a time: a vector's, or a store's decoded as they are read
// (each from the iterator that reads it: the reference lives until the iterator moves on).
class RecordRange {
public:
  RecordRange(const std::vector<Record>& records) : vector_(&records) {} // NOLINT: a view of it
  RecordRange(const RecordStore& store) : store_(&store) {}              // NOLINT
  std::size_t size() const { return vector_ != nullptr ? vector_->size() : store_->size(); }
  bool empty() const { return size() == 0; }
  // Record `index`: the vector's, or the store's decoded into `holder` (from any thread).
  const Record& at(std::size_t index, std::optional<Record>& holder) const {
    if (vector_ != nullptr) {
      return vector_->at(index);
    }
    holder = store_->at(index);
    return *holder;
  }

  class iterator {
  public:
    using value_type = Record;
    using difference_type = std::ptrdiff_t;
    using reference = const Record&;
    using pointer = const Record*;
    using iterator_category = std::input_iterator_tag;
    iterator() = default;
    iterator(const RecordRange* range, std::size_t index) : range_(range), index_(index) {}
    const Record& operator*() const;
    const Record* operator->() const { return &**this; }
    iterator& operator++() {
      ++index_;
      return *this;
    }
    void operator++(int) { ++index_; }
    bool operator==(const iterator& other) const { return index_ == other.index_; }

  private:
    const RecordRange* range_ = nullptr;
    std::size_t index_ = 0;
    mutable std::optional<Record> decoded_;
    mutable std::size_t decoded_index_ = 0;
  };
  iterator begin() const { return {this, 0}; }
  iterator end() const { return {this, size()}; }

private:
  const std::vector<Record>* vector_ = nullptr;
  const RecordStore* store_ = nullptr;
};

// Adds records' rhs evaluations and solver runs to `totals` (run_plan's sums).
void add_to_totals(RecordRange records, RunTotals& totals);

// Solves `cells` of the plan (PlanRunner::run_cells) into `store`, about `batch_records` records
// at a time (16 cells a thread at least), each batch's records decoded only until they are stored
// as bytes: a process that solves 10^6 records holds their bytes in the store's file, not 1.4 GB
// of records. Record k of cells[i] lands at i × configurations + k, the same whatever the batches
// (only times differ); `progress` counts over all of them. No new batch once a stop was requested
// (the store then lacks the records not solved).
void solve_into(const Plan& plan, PlanRunner& runner, std::span<const std::size_t> cells,
                RecordStore& store, int jobs, const Progress& progress,
                std::size_t batch_records = 32768);

} // namespace pldamp::harness
