#include "common/files.hpp"

#include "common/input.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>
#include <vector>

namespace pldamp::harness {
namespace {

// mkstemp on ".NAME.XXXXXX" beside `path`: O_CREAT | O_EXCL, mode 0600.
// Throws InputError "`what` (reason)".
std::string create_temporary(const std::filesystem::path& path, Descriptor& file,
                             const std::string& what) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on "." + name + ".XXXXXX".
  std::string name = folder.string();
  name.append("/.");
  name.append(path.filename().string());
  name.append(".XXXXXX");
  std::vector<char> buffer(name.begin(), name.end());
  buffer.push_back('\0');
  file.reset(::mkstemp(buffer.data()));
  if (file.get() < 0) {
    throw InputError(what + " (" + std::strerror(errno) + ")");
  }
  return std::string(buffer.data());
}

// Gives the unnamed file `fd` (O_TMPFILE) a fresh temporary name beside `path` (linkat through
// /proc/self/fd, which needs no privilege; a name taken meanwhile is tried again).
std::string link_temporary(const std::filesystem::path& path, int fd) {
  const std::string proc = "/proc/self/fd/" + std::to_string(fd);
  for (int attempt = 0;; ++attempt) {
    Descriptor probe;
    std::string name = create_temporary(path, probe, "cannot write " + path.string());
    ::unlink(name.c_str()); // a unique name, free again: linkat does not replace
    if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0) {
      return name;
    }
    if (errno != EEXIST || attempt == 100) {
      throw InputError("cannot write " + path.string() + " (" + std::strerror(errno) + ")");
    }
  }
}

} // namespace

void Descriptor::reset(int fd) {
  if (fd_ >= 0) {
    ::close(fd_);
  }
  fd_ = fd;
}

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t hash) {
  for (const char c : bytes) {
    hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  }
  return hash;
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  write_file_atomically(path, [content](const TextSink& put) { put(content); });
}

void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const TextSink&)>& produce) {
  StagedFile(path, produce).commit();
}

StagedFile::StagedFile(std::filesystem::path path,
                       const std::function<void(const TextSink&)>& produce)
    : path_(std::move(path)) {
  // Where the filesystem allows it (O_TMPFILE: ext4, xfs, btrfs, tmpfs), the file has no name
  // while it is written, so a process killed meanwhile leaves nothing behind; it is linked to a
  // temporary name when whole, and renamed into place by commit(). Elsewhere, a temporary name
  // from the start.
  const std::filesystem::path folder = path_.has_parent_path() ? path_.parent_path() : ".";
  Descriptor file(::access("/proc/self/fd", F_OK) == 0
                      ? ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600)
                      : -1);
  const bool unnamed = file.get() >= 0;
  std::string temporary;
  if (!unnamed) {
    temporary = create_temporary(path_, file, "cannot write " + path_.string());
  }
  const auto fail = [&](int error) {
    throw InputError("cannot write " + path_.string() + " (" + std::strerror(error) + ")");
  };
  // The permissions a new file of this user gets (mkstemp's are 0600). The umask can only be
  // read by setting it, for the whole process: read once, under the lock of a function-local
  // static, so that reports written on several threads (write_reports) cannot see each other's 0.
  static const mode_t mask = [] {
    const mode_t process_mask = ::umask(0);
    ::umask(process_mask);
    return process_mask;
  }();
  const auto write_all = [&](std::string_view bytes) {
    for (std::size_t done = 0; done < bytes.size();) {
      const ssize_t n = ::write(file.get(), bytes.data() + done, bytes.size() - done);
      if (n < 0) {
        if (errno == EINTR) {
          continue;
        }
        fail(errno);
      }
      done += static_cast<std::size_t>(n);
    }
  };
  try {
    if (::fchmod(file.get(), 0666 & ~mask) != 0) {
      fail(errno);
    }
    constexpr std::size_t buffer_bytes = std::size_t{1} << 20;
    std::string buffer;
    produce([&](std::string_view piece) {
      if (buffer.size() + piece.size() > buffer_bytes) {
        write_all(buffer);
        buffer.clear();
      }
      if (piece.size() > buffer_bytes) {
        write_all(piece);
      } else {
        buffer.append(piece);
      }
    });
    write_all(buffer);
    if (::fsync(file.get()) != 0) {
      fail(errno);
    }
    if (unnamed) { // kept open and nameless until commit(): a process killed first leaves nothing
      unnamed_ = file.get();
      file.release();
      return;
    }
    const int descriptor = file.get();
    file.release();
    if (::close(descriptor) != 0) {
      fail(errno);
    }
  } catch (...) { // a failed write, or `produce`'s own exception: no temporary is left behind
    if (!temporary.empty()) {
      ::unlink(temporary.c_str());
    }
    throw;
  }
  temporary_ = std::move(temporary);
}

StagedFile::StagedFile(StagedFile&& other) noexcept
    : path_(std::move(other.path_)), temporary_(std::move(other.temporary_)),
      unnamed_(other.unnamed_) {
  other.temporary_.clear();
  other.unnamed_ = -1;
}

StagedFile::~StagedFile() {
  if (!temporary_.empty()) {
    ::unlink(temporary_.c_str());
  }
  if (unnamed_ >= 0) {
    ::close(unnamed_);
  }
}

void StagedFile::commit() {
  if (unnamed_ >= 0) { // a name beside the target, then the target's
    temporary_ = link_temporary(path_, unnamed_);
    const int descriptor = unnamed_;
    unnamed_ = -1;
    if (::close(descriptor) != 0) {
      const int error = errno;
      throw InputError("cannot write " + path_.string() + " (" + std::strerror(error) + ")");
    }
  }
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    throw InputError("cannot write " + path_.string() + " (" + std::strerror(error) + ")");
  }
  temporary_.clear();
}

std::string gather_text(const std::function<void(const TextSink&)>& produce) {
  std::string text;
  produce([&text](std::string_view piece) { text.append(piece); });
  return text;
}

std::optional<std::string> unreadable_file(const std::filesystem::path& path) {
  const Descriptor file(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  struct stat status {};
  if (file.get() < 0 || ::fstat(file.get(), &status) != 0) {
    return std::string(std::strerror(errno));
  }
  const mode_t type = status.st_mode & S_IFMT;
  if (type == S_IFREG) {
    return std::nullopt;
  }
  return std::string(type == S_IFIFO    ? "a FIFO (a named pipe)"
                     : type == S_IFDIR  ? "a directory"
                     : type == S_IFCHR  ? "a character device"
                     : type == S_IFBLK  ? "a block device"
                     : type == S_IFSOCK ? "a socket"
                                        : "not a file") +
         ", not a regular file";
}

std::string unchanged_reports(const std::filesystem::path& folder) {
  return "no report file was changed: " + folder.string() + " holds the previous run's, if any";
}

void require_writable_folder(const std::filesystem::path& folder, std::string_view what) {
  std::error_code failed;
  std::filesystem::create_directories(folder, failed);
  if (failed) {
    throw InputError("cannot create the " + std::string(what) + ", " + failed.message() + " (got " +
                     folder.string() + ")");
  }
  Descriptor probe;
  const std::string name = create_temporary(
      folder / "report", probe, "cannot write in the " + std::string(what) + " " + folder.string());
  ::unlink(name.c_str());
}

} // namespace pldamp::harness
