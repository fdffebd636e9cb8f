// A run's records as bytes, bit for bit (every double, every message): the body of a shard file
// (`pldamp run SCENE --shard K/N`, merged by `pldamp merge`) and of the messages an MPI rank sends
// to the rank that writes the report. A report made from them is the serial run's, times aside.
#pragma once

#include "common/bytes.hpp"
#include "common/provenance.hpp"
#include "run/record_store.hpp"
#include "run/run.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pldamp::harness {

// Appends `records` to `bytes`; read_records reads them back (InputError naming `source` when the
// bytes end early or hold what no writer writes).
void append_records(std::string& bytes, const std::vector<Record>& records);
std::vector<Record> read_records(std::string_view bytes, const std::string& source);

// The same through a writer and a reader: a count, then each record.
void put_records(ByteWriter& out, const std::vector<Record>& records);
std::vector<Record> get_records(ByteReader& in);

// One record's bytes appended to `bytes`; read_record reads the record `bytes` begin with.
void append_record(std::string& bytes, const Record& record);
Record read_record(std::string_view bytes, const std::string& source);
// Each record of bytes append_records wrote, in order, with the bytes that hold it.
using RecordVisitor = std::function<void(Record&&, std::string_view bytes)>;
void for_each_record_bytes(std::string_view bytes, const std::string& source,
                           const RecordVisitor& visit);

// The cells of shard `index` of `count` (1 ≤ index ≤ count): every count-th cell from index − 1,
// so that each shard holds every p, damping and scale of the grid in about equal shares.
std::vector<std::size_t> shard_cells(std::size_t cells, std::size_t index, std::size_t count);

// The fewest bytes append_record writes (a default Record's): each fixed field, each optional's
// flag, each string's and list's length. A count of records is checked against the bytes left
// before any is allocated, and a shard set's size bounds the records it holds.
inline constexpr std::size_t least_record_bytes =
    8 + 8 + 1 + 8 + 8 + 8 + 8 + 8 + 1 + 1 + 8 + 8 + 4 + 8 + 1 + 7 * 8 + 8 + 8 + 8;

// The most shards a run is split into (--shard K/N: N ≤ max_shards).
inline constexpr std::size_t max_shards = 1000000;

// Where a shard's run writes its records, in its --out folder.
inline constexpr const char* shard_file_name = "shard.pldamp";

// What a shard file says of itself besides its records: the scene exactly as read (its path and
// text; a merge plans it again from the text) and the limits the run applied, which shard of how
// many it is, and what its run measured.
struct ShardHeader {
  std::string build; // build_id() of the writer
  std::string scene_path, scene_text;
  long max_steps = 0, max_runs = 0;
  double max_seconds = 0;
  std::size_t index = 0, count = 0;   // shard index of count, from 1
  std::size_t cells = 0, configs = 0; // of the whole plan
  RunTotals totals;                   // of this shard's records (external: the handshakes)
};

struct Shard {
  ShardHeader header;
  std::vector<Record> records;
};

// Writes FOLDER/shard.pldamp (to a temporary name, renamed into place), its records as they are
// read (a vector's, or a store's: run/record_store.hpp).
void write_shard(const std::filesystem::path& folder, const ShardHeader& header,
                 RecordRange records);
void write_shard(const std::filesystem::path& folder, const Shard& shard);
// A shard file's bytes up to its records' count: its magic line, format, byte order and header.
void append_shard_head(std::string& bytes, const ShardHeader& header);

// Reads FOLDER/shard.pldamp; InputError with one line when it cannot be read or is not one.
Shard read_shard(const std::filesystem::path& folder);
// The same, its records handed to `visit` one at a time with their bytes (none without a visitor:
// the header alone, the whole file's checksum checked).
ShardHeader read_shard_records(const std::filesystem::path& folder, const RecordVisitor& visit);
// The same of a shard file's bytes, named `source` in messages (tests/fuzz drives it).
ShardHeader read_shard_bytes(std::string_view bytes, const std::string& source,
                             const RecordVisitor& visit);

} // namespace pldamp::harness
