// The bytes of a shard file and of a record (run/shard.hpp), apart from the files: what a shard
// writes and merge, MPI ranks and the fuzzer (tests/fuzz/exchange_fuzz.cpp) read.
#include "run/shard.hpp"

#include "common/bytes.hpp"
#include "common/files.hpp"
#include "common/input.hpp"

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <type_traits>

namespace pldamp::harness {
namespace {

// The bytes are the host's: shards are merged where they ran (one cluster), and a file from a
// machine of the other byte order is refused by its marker rather than misread.
static_assert(std::endian::native == std::endian::little ||
              std::endian::native == std::endian::big);
constexpr std::string_view shard_magic = "pldamp shard\n";
constexpr std::uint32_t shard_format = 2; // 2: a checksum at the end
constexpr std::uint32_t byte_order_marker = 0x01020304;

// Every field of a Record, in declaration order: a field added to Record changes its size and
// stops the build here until it is written and read too.
static_assert(sizeof(Record) == 448, "a new Record field: write and read it below");

void put_record(ByteWriter& out, const Record& r) {
  out.put<std::uint64_t>(r.cell);
  out.put<std::uint64_t>(r.config);
  out.put<std::int8_t>(r.outcome ? static_cast<std::int8_t>(*r.outcome) : std::int8_t(-1));
  out.put(r.failure);
  out.put<std::int64_t>(r.steps);
  out.put<std::int64_t>(r.rhs_evals);
  out.put(r.wall_seconds);
  out.put(r.wall_seconds_slowest);
  out.put(r.cpu_seconds);
  out.put(r.cpu_seconds_slowest);
  out.put(r.alpha);
  out.put(r.alpha_digits);
  out.put<std::int32_t>(r.phases);
  out.put<std::int64_t>(r.runs);
  out.put(r.dt);
  for (const auto* values :
       {&r.value, &r.reference, &r.error, &r.abs_error, &r.rel_error, &r.spread, &r.worst_phase}) {
    out.put(*values);
  }
  out.put(r.skip_reason);
  out.put(r.note);
  out.put(r.replica_difference);
}

// The longest text a record holds: a solver's message, an external program's reason (cut to 200
// bytes), a note. A shard with a 200 MiB failure text took 23 s and 3.4 GB to merge, and wrote a
// report diff refuses.
constexpr std::size_t max_record_text = 16384;
// The most bytes put_record writes: its fixed fields, four texts at their limit, eight lists of
// up to 64 values (an observable each, far more than the table's), a flag and a double each.
constexpr std::size_t max_record_bytes = 256 + 4 * max_record_text + 8 * 64 * 9;

Record get_record(ByteReader& in) {
  Record r;
  r.cell = in.get<std::uint64_t>();
  r.config = in.get<std::uint64_t>();
  const auto outcome = in.get<std::int8_t>();
  if (outcome < -1 || outcome > static_cast<std::int8_t>(solvers::Outcome::unstable)) {
    in.corrupt();
  }
  if (outcome >= 0) {
    r.outcome = static_cast<solvers::Outcome>(outcome);
  }
  r.failure = in.text(max_record_text);
  r.steps = in.get<std::int64_t>();
  r.rhs_evals = in.get<std::int64_t>();
  r.wall_seconds = in.get<double>();
  r.wall_seconds_slowest = in.get<double>();
  r.cpu_seconds = in.optional();
  r.cpu_seconds_slowest = in.optional();
  r.alpha = in.get<double>();
  r.alpha_digits = in.text(max_record_text);
  r.phases = in.get<std::int32_t>();
  r.runs = in.get<std::int64_t>();
  r.dt = in.optional();
  for (auto* values :
       {&r.value, &r.reference, &r.error, &r.abs_error, &r.rel_error, &r.spread, &r.worst_phase}) {
    *values = in.optionals();
  }
  r.skip_reason = in.text(max_record_text);
  r.note = in.text(max_record_text);
  r.replica_difference = in.optionals();
  return r;
}

} // namespace

void put_records(ByteWriter& out, const std::vector<Record>& records) {
  out.put<std::uint64_t>(records.size());
  for (const Record& record : records) {
    put_record(out, record);
  }
}

std::vector<Record> get_records(ByteReader& in) {
  std::vector<Record> records(in.size(least_record_bytes));
  for (Record& record : records) {
    record = get_record(in);
  }
  return records;
}

void append_records(std::string& bytes, const std::vector<Record>& records) {
  ByteWriter out(bytes);
  put_records(out, records);
}

std::vector<Record> read_records(std::string_view bytes, const std::string& source) {
  ByteReader in(bytes, source);
  std::vector<Record> records = get_records(in);
  if (!in.at_end()) {
    in.corrupt();
  }
  return records;
}

void append_record(std::string& bytes, const Record& record) {
  ByteWriter out(bytes);
  put_record(out, record);
}

Record read_record(std::string_view bytes, const std::string& source) {
  ByteReader in(bytes, source);
  return get_record(in);
}

void for_each_record_bytes(std::string_view bytes, const std::string& source,
                           const RecordVisitor& visit) {
  ByteReader in(bytes, source);
  for (std::size_t n = in.size(least_record_bytes); n > 0; --n) {
    const std::string_view from = in.rest();
    Record record = get_record(in);
    visit(std::move(record), from.substr(0, from.size() - in.rest().size()));
  }
  if (!in.at_end()) {
    in.corrupt();
  }
}

void append_shard_head(std::string& bytes, const ShardHeader& h) {
  bytes.append(shard_magic);
  ByteWriter out(bytes);
  out.put(shard_format);
  out.put(byte_order_marker);
  out.put(h.build);
  out.put(h.scene_path);
  out.put(h.scene_text);
  out.put<std::int64_t>(h.max_steps);
  out.put<std::int64_t>(h.max_runs);
  out.put(h.max_seconds);
  out.put<std::uint64_t>(h.index);
  out.put<std::uint64_t>(h.count);
  out.put<std::uint64_t>(h.cells);
  out.put<std::uint64_t>(h.configs);
  out.put<std::int64_t>(h.totals.rhs_evals);
  out.put<std::int64_t>(h.totals.solver_runs);
  out.put(h.totals.wall_seconds);
  out.put<std::uint64_t>(h.totals.external.size());
  for (const std::string& said : h.totals.external) {
    out.put(said);
  }
}

ShardHeader read_shard_bytes(std::string_view bytes, const std::string& source,
                             const RecordVisitor& visit) {
  if (!bytes.starts_with(shard_magic) ||
      bytes.size() < shard_magic.size() + sizeof(std::uint64_t)) {
    throw InputError(source + " is not a shard file pldamp wrote");
  }
  const std::string_view body = bytes.substr(0, bytes.size() - sizeof(std::uint64_t));
  ByteReader read(body.substr(shard_magic.size()), source);
  const auto format = read.get<std::uint32_t>();
  const auto marker = read.get<std::uint32_t>();
  if (format != shard_format || marker != byte_order_marker) {
    throw InputError(source + " was written by another pldamp version (shard format " +
                     std::to_string(format) + ", this pldamp reads " +
                     std::to_string(shard_format) + ") or on a machine of another byte order");
  }
  ShardHeader h;
  h.build = read.text(256);
  h.scene_path = read.text(4096);
  h.scene_text = read.text(max_scene_bytes);
  h.max_steps = read.get<std::int64_t>();
  h.max_runs = read.get<std::int64_t>();
  h.max_seconds = read.get<double>();
  h.index = read.get<std::uint64_t>();
  h.count = read.get<std::uint64_t>();
  h.cells = read.get<std::uint64_t>();
  h.configs = read.get<std::uint64_t>();
  h.totals.rhs_evals = read.get<std::int64_t>();
  h.totals.solver_runs = read.get<std::int64_t>();
  h.totals.wall_seconds = read.get<double>();
  h.totals.external.resize(read.size(sizeof(std::uint64_t)));
  for (std::string& said : h.totals.external) {
    said = read.text(std::size_t{1} << 20); // a handshake's description: at most a line of it
  }
  // What the writer's run could hold: its shard of a set, the limits the command line and
  // [limits] accept (a header's limits are the run's: merge plans under them).
  const auto within = [](auto x, auto low, auto high) { return x >= low && x <= high; };
  if (h.index < 1 || h.index > h.count || h.count > max_shards || !within(h.max_steps, 1, 1e12) ||
      !within(h.max_runs, 1, 1e12) || !within(h.max_seconds, 1e-300, 86400.0) ||
      h.totals.external.size() != h.configs || !within(h.totals.wall_seconds, 0.0, 1e9) ||
      h.totals.rhs_evals < 0 || h.totals.solver_runs < 0) {
    read.corrupt();
  }
  // The bytes its records could take at most (each text at its limit, every value present) bound
  // the file before its checksum is computed: a 4 GiB file with a shard's first line was hashed
  // whole (24 s) before it was refused.
  const std::size_t records =
      h.cells >= h.index ? std::size_t((h.cells - h.index) / h.count + 1) * h.configs : 0;
  const double most = double(read.rest().size()) - double(sizeof(std::uint64_t));
  if (most > double(records) * double(max_record_bytes)) {
    throw InputError(source + " holds more bytes than the " + std::to_string(records) +
                     " records its header names could take: it is not a shard file pldamp wrote");
  }
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), sizeof stored);
  if (stored != fnv1a(body)) {
    throw InputError(source + " is truncated or corrupt (its checksum does not match): run its "
                              "shard again");
  }
  if (visit) {
    for_each_record_bytes(read.rest(), source, visit);
  }
  return h;
}
} // namespace pldamp::harness
