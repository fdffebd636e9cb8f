// Shard files on disk (run/shard.hpp); their bytes are shard_bytes.cpp's.
#include "run/shard.hpp"

#include "build_id.hpp"
#include "common/bytes.hpp"
#include "common/files.hpp"
#include "common/input.hpp"

#include <cstdint>
#include <fstream>

namespace pldamp::harness {

std::string_view build_id() {
  return PLDAMP_BUILD_ID;
}

std::vector<std::size_t> shard_cells(std::size_t cells, std::size_t index, std::size_t count) {
  std::vector<std::size_t> mine;
  for (std::size_t cell = index - 1; cell < cells; cell += count) {
    mine.push_back(cell);
  }
  return mine;
}

void write_shard(const std::filesystem::path& folder, const ShardHeader& h, RecordRange records) {
  write_file_atomically(folder / shard_file_name, [&](const TextSink& put) {
    // A checksum of everything before it, made as the pieces go (a flipped bit is refused, not
    // merged); the records encoded one at a time, a MiB of them a piece.
    std::uint64_t hash = fnv1a_basis;
    std::string bytes;
    append_shard_head(bytes, h);
    const auto hand_over = [&] {
      hash = fnv1a(bytes, hash);
      put(bytes);
      bytes.clear();
    };
    ByteWriter out(bytes);
    out.put<std::uint64_t>(records.size()); // put_records' layout
    for (const Record& record : records) {
      append_record(bytes, record);
      if (bytes.size() >= (std::size_t{1} << 20)) {
        hand_over();
      }
    }
    hand_over();
    out.put(hash);
    put(bytes);
  });
}

void write_shard(const std::filesystem::path& folder, const Shard& shard) {
  write_shard(folder, shard.header, shard.records);
}

ShardHeader read_shard_records(const std::filesystem::path& folder, const RecordVisitor& visit) {
  const std::string source = (folder / shard_file_name).string();
  if (const std::optional<std::string> why = unreadable_file(folder / shard_file_name)) {
    throw InputError("not a shard: " + one_line(source) + ": " + *why +
                     " (a shard is the --out folder of `pldamp run SCENE --shard K/N`)");
  }
  std::ifstream in(folder / shard_file_name, std::ios::binary | std::ios::ate);
  std::string bytes;
  if (in) { // its size first, then one read (a character at a time took 6 % of a merge)
    bytes.resize(static_cast<std::size_t>(in.tellg()));
    in.seekg(0);
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  if (!in) {
    throw InputError("cannot read " + source);
  }
  return read_shard_bytes(bytes, source, visit);
}

Shard read_shard(const std::filesystem::path& folder) {
  Shard shard;
  shard.header = read_shard_records(folder, [&](Record&& record, std::string_view) {
    shard.records.push_back(std::move(record));
  });
  return shard;
}

} // namespace pldamp::harness
