// Files a person reads, written so that a reader sees the old file or the new one, never a torn
// one: the content goes to a fresh temporary name beside the target (created exclusively, so no
// planted symlink is followed), is flushed to the disk, and is renamed into place.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

namespace pldamp::harness {

// A file descriptor closed when it goes out of scope (files here, pipes in process.cpp).
class Descriptor {
public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { reset(); }
  int get() const { return fd_; }
  void release() { fd_ = -1; } // ownership passed on
  void reset(int fd = -1);

private:
  int fd_;
};

// 64-bit FNV-1a of bytes: a name for what a scene computes (report.json's fingerprint), a check
// against a torn or altered shard file; not a security measure. Of bytes in pieces: each piece's
// with the hash so far, fnv1a(b, fnv1a(a)) == fnv1a(a + b).
inline constexpr std::uint64_t fnv1a_basis = 14695981039346656037ULL;
std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash = fnv1a_basis);

// Where a text made piece by piece goes, each piece as soon as it is made.
using TextSink = std::function<void(std::string_view)>;

// A file written whole, flushed to the disk, under a temporary name beside its target, and put
// in place only by commit() (a rename: the target is the old file or the new one, never a torn
// one). Dropped uncommitted, its temporary is removed. Files that must change together (a run's
// report set) are all staged first and committed only when every one was written.
class StagedFile {
public:
  // Throws InputError "cannot write PATH (reason)", leaving nothing behind.
  StagedFile(std::filesystem::path path, const std::function<void(const TextSink&)>& produce);
  StagedFile(StagedFile&& other) noexcept;
  StagedFile& operator=(StagedFile&&) = delete;
  StagedFile(const StagedFile&) = delete;
  StagedFile& operator=(const StagedFile&) = delete;
  ~StagedFile();
  // Renames the temporary onto the target; throws InputError "cannot write PATH (reason)".
  void commit();
  const std::filesystem::path& path() const { return path_; }

private:
  std::filesystem::path path_;
  std::string temporary_; // its name, where it has one; empty once committed or moved from
  int unnamed_ = -1;      // or its open descriptor (O_TMPFILE), named only by commit()
};

// A StagedFile committed at once. Throws InputError "cannot write PATH (reason)"; the temporary
// is removed on failure.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);
// The same, of a content `produce` hands to its sink in pieces, written as they come (through a
// buffer of 1 MiB): a report of 10^6 records is never held whole. An exception from `produce`
// removes the temporary and goes on.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const TextSink&)>& produce);
// A content made in pieces, gathered into one string.
std::string gather_text(const std::function<void(const TextSink&)>& produce);

// Why `path` cannot be read as a file, or none when it can: it must be a regular file one may
// open. It is opened without blocking and its type checked before any reader opens it: a FIFO
// with no writer blocks open() for ever, and a device such as /dev/zero never ends. The reasons
// read "a FIFO (a named pipe), not a regular file", "a directory, not a regular file", or the
// system's ("No such file or directory").
std::optional<std::string> unreadable_file(const std::filesystem::path& path);

// What a run that stopped before renaming any report says of its folder: "no report file was
// changed: FOLDER holds the previous run's, if any" (the records' file, or a report that could
// not be written).
std::string unchanged_reports(const std::filesystem::path& folder);

// Creates `folder` if needed and checks that a file can be created in it (and removes that
// file): a read-only mount or a folder of another user fails here, before any work. Throws
// InputError.
// `what` names it in the message: "report folder", or "shard's folder" for a shard's --out.
void require_writable_folder(const std::filesystem::path& folder,
                             std::string_view what = "report folder");

} // namespace pldamp::harness
