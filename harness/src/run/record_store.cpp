#include "run/record_store.hpp"

#include "common/files.hpp"
#include "common/input.hpp"
#include "run/shard.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <stdexcept>
#include <sys/mman.h>
#include <unistd.h>

namespace pldamp::harness {
namespace {

constexpr std::size_t buffer_bytes = std::size_t{1} << 20;

} // namespace

RecordStore::RecordStore(std::size_t count, const std::filesystem::path& folder)
    : folder_(folder), where_(count, absent) {
  std::string name = (folder / ".pldamp-records.XXXXXX").string();
  file_.reset(::mkstemp(name.data()));
  if (file_.get() < 0) {
    throw InputError("cannot make a file for the records in " + folder.string() + " (" +
                     std::strerror(errno) + ")");
  }
  ::unlink(name.c_str()); // open, it lives until closed; nothing is left behind
  buffer_.reserve(buffer_bytes);
}

RecordStore::~RecordStore() {
  if (mapped_ != nullptr) {
    ::munmap(const_cast<char*>(mapped_), mapped_size_);
  }
}

void RecordStore::flush() {
  for (std::size_t done = 0; done < buffer_.size();) {
    const ssize_t n = ::write(file_.get(), buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      // Before any report is written: the folder is as it was (a full disk, a file-size limit).
      const int error = errno;
      throw InputError("cannot write the records' file in " + folder_.string() + " (" +
                       std::strerror(error) + "); " + unchanged_reports(folder_));
    }
    done += static_cast<std::size_t>(n);
  }
  written_ += buffer_.size();
  buffer_.clear();
}

void RecordStore::put_bytes(std::size_t index, std::string_view bytes) {
  const std::lock_guard guard(lock_);
  if (mapped_ != nullptr || index >= where_.size() || where_[index] != absent) {
    throw std::logic_error("record " + std::to_string(index) + " stored twice or too late");
  }
  if (buffer_.size() + bytes.size() > buffer_bytes) {
    flush();
  }
  where_[index] = written_ + buffer_.size();
  buffer_.append(bytes);
  ++stored_;
}

void RecordStore::put(std::size_t index, const Record& record) {
  std::string bytes;
  append_record(bytes, record);
  put_bytes(index, bytes);
}

void RecordStore::seal() {
  const std::lock_guard guard(lock_);
  if (mapped_ != nullptr) {
    return;
  }
  flush();
  mapped_size_ = static_cast<std::size_t>(written_);
  if (mapped_size_ == 0) {
    return;
  }
  void* map = ::mmap(nullptr, mapped_size_, PROT_READ, MAP_SHARED, file_.get(), 0);
  if (map == MAP_FAILED) {
    throw InputError("cannot read the records' file back (" + std::string(std::strerror(errno)) +
                     ")");
  }
  mapped_ = static_cast<const char*>(map);
}

Record RecordStore::at(std::size_t index) const {
  const std::uint64_t offset = where_.at(index);
  if (offset == absent || offset >= mapped_size_) {
    throw std::logic_error("record " + std::to_string(index) + " was not stored or not sealed");
  }
  static const std::string source = "the records' file";
  return read_record(std::string_view(mapped_ + offset, mapped_size_ - offset), source);
}

const Record& RecordRange::iterator::operator*() const {
  if (range_->vector_ != nullptr) {
    return (*range_->vector_)[index_];
  }
  if (!decoded_ || decoded_index_ != index_) {
    range_->at(index_, decoded_);
    decoded_index_ = index_;
  }
  return *decoded_;
}

void add_to_totals(RecordRange records, RunTotals& totals) {
  for (const Record& record : records) {
    totals.rhs_evals += record.rhs_evals * record.phases;
    totals.solver_runs += record.runs;
  }
}

void solve_into(const Plan& plan, PlanRunner& runner, std::span<const std::size_t> cells,
                RecordStore& store, int jobs, const Progress& progress, std::size_t batch_records) {
  const std::size_t configs = plan.configs.size();
  // Batches of many cells still fill the threads and the fixed-step schemes' SIMD batches
  // (run.cpp, group_records); only their times depend on where one batch ends.
  const std::size_t per_batch =
      std::max<std::size_t>({1, 16 * static_cast<std::size_t>(std::max(jobs, 1)),
                             batch_records / std::max<std::size_t>(configs, 1)});
  const std::size_t total = cells.size() * configs;
  for (std::size_t first = 0; first < cells.size() && !stop_requested(); first += per_batch) {
    const std::span<const std::size_t> batch =
        cells.subspan(first, std::min(per_batch, cells.size() - first));
    const std::size_t before = first * configs;
    Progress counted;
    if (progress) {
      counted = [&](std::size_t done, std::size_t) { progress(before + done, total); };
    }
    const std::vector<Record> records = runner.run_cells(batch, counted);
    if (stop_requested()) {
      return; // some of the batch's records were never solved
    }
    for (std::size_t i = 0; i < records.size(); ++i) {
      store.put(before + i, records[i]);
    }
  }
}

} // namespace pldamp::harness
