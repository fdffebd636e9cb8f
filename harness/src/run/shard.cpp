// Shard files on disk (run/shard.hpp); their bytes are shard_bytes.cpp's.
#include "run/shard.hpp"

#include "common/bytes.hpp"
#include "common/files.hpp"
#include "common/input.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace pldamp::harness {

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
  // Mapped, not read into memory: the file's pages are the system's to drop (a 4 GiB file was
  // read whole, 4.2 GB, before its checksum was refused), and a merge holds its shards' bytes
  // one file at a time this way.
  const Descriptor file(::open((folder / shard_file_name).c_str(), O_RDONLY | O_CLOEXEC));
  struct stat status {};
  if (file.get() < 0 || ::fstat(file.get(), &status) != 0) {
    throw InputError("cannot read " + one_line(source) + " (" + std::strerror(errno) + ")");
  }
  const auto size = static_cast<std::size_t>(status.st_size);
  if (size == 0) {
    return read_shard_bytes({}, source, visit);
  }
  void* mapped = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE, file.get(), 0);
  if (mapped == MAP_FAILED) {
    throw InputError("cannot read " + one_line(source) + " (" + std::strerror(errno) + ")");
  }
  struct Unmap {
    void* at;
    std::size_t size;
    ~Unmap() { ::munmap(at, size); }
  } const unmap{mapped, size};
  ::madvise(mapped, size, MADV_SEQUENTIAL);
  return read_shard_bytes(std::string_view(static_cast<const char*>(mapped), size), source, visit);
}

Shard read_shard(const std::filesystem::path& folder) {
  Shard shard;
  shard.header = read_shard_records(folder, [&](Record&& record, std::string_view) {
    shard.records.push_back(std::move(record));
  });
  return shard;
}

} // namespace pldamp::harness
