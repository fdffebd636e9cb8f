#include "common/process.hpp"

#include "common/files.hpp"

#include <cerrno>
#include <csignal>
#include <ctime>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <utility>

extern char** environ;

namespace pldamp::harness {
namespace {

// Both ends of a pipe, close-on-exec so the child keeps only what posix_spawn gives it.
bool make_pipe(Descriptor& read_end, Descriptor& write_end) {
  std::array<int, 2> fds{};
  if (::pipe2(fds.data(), O_CLOEXEC) != 0) {
    return false;
  }
  read_end.reset(fds[0]);
  write_end.reset(fds[1]);
  return true;
}

// A child that exits early closes its stdin: writing must fail with EPIPE, not kill us. SIGPIPE
// is blocked in this thread while this lives, and a pending one consumed before unblocking.
class PipeSignalBlocked {
public:
  PipeSignalBlocked() {
    sigemptyset(&pipe_signal_);
    sigaddset(&pipe_signal_, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_signal_, &previous_);
  }
  PipeSignalBlocked(const PipeSignalBlocked&) = delete;
  PipeSignalBlocked& operator=(const PipeSignalBlocked&) = delete;
  ~PipeSignalBlocked() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  void consume_if(bool broken_pipe) {
    if (broken_pipe) {
      const timespec now{};
      sigtimedwait(&pipe_signal_, nullptr, &now);
    }
  }

private:
  sigset_t pipe_signal_{}, previous_{};
};

// Starts argv (looked up on PATH) with the given descriptors as its standard input, output and
// error (err < 0: /dev/null). Returns its pid, or -1.
pid_t spawn(const std::vector<std::string>& argv, int in, int out, int err) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in, STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out, STDOUT_FILENO);
  if (err >= 0) {
    posix_spawn_file_actions_adddup2(&actions, err, STDERR_FILENO);
  } else {
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  }
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str())); // posix_spawn's signature; not modified
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return spawned == 0 ? pid : -1;
}

// How a child ended, from waitpid's status.
std::string describe(int status) {
  return WIFEXITED(status) ? "exited with status " + std::to_string(WEXITSTATUS(status))
                           : "killed by signal " + std::to_string(WTERMSIG(status));
}

// Waits for `pid` (retrying on EINTR) and says how it ended.
std::string reap(pid_t pid, int* exit_code = nullptr) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (exit_code != nullptr) {
    *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return describe(status);
}

} // namespace

ProgramRun run_program(const std::vector<std::string>& argv, const std::string& input,
                       std::chrono::milliseconds limit) {
  ProgramRun run;
  if (argv.empty()) {
    return run;
  }
  Descriptor in_read, in_write, out_read, out_write;
  if (!make_pipe(in_read, in_write) || !make_pipe(out_read, out_write)) {
    return run;
  }
  const pid_t pid = spawn(argv, in_read.get(), out_write.get(), -1);
  in_read.reset();
  out_write.reset();
  if (pid <= 0) {
    return run;
  }
  run.started = true;

  // Feed stdin and drain stdout together, so neither side can block the other on a full pipe.
  ::fcntl(in_write.get(), F_SETFL, O_NONBLOCK);
  if (input.empty()) {
    in_write.reset();
  }
  PipeSignalBlocked blocked;
  bool broken_pipe = false;
  const auto deadline = std::chrono::steady_clock::now() + limit;
  std::size_t written = 0;
  std::array<char, 65536> buffer{};
  while (out_read.get() >= 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      run.timed_out = true;
      break;
    }
    std::array<pollfd, 2> fds{pollfd{out_read.get(), POLLIN, 0},
                              pollfd{in_write.get(), POLLOUT, 0}};
    const nfds_t count = in_write.get() >= 0 ? 2 : 1;
    if (::poll(fds.data(), count, static_cast<int>(left.count())) < 0 && errno != EINTR) {
      break;
    }
    if (count == 2 && (fds[1].revents & (POLLOUT | POLLERR | POLLHUP)) != 0) {
      const ssize_t n = ::write(in_write.get(), input.data() + written, input.size() - written);
      if (n > 0) {
        written += static_cast<std::size_t>(n);
      }
      broken_pipe = broken_pipe || (n < 0 && errno == EPIPE);
      if (written == input.size() || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        in_write.reset(); // all written, or the child stopped reading
      }
    }
    if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      const ssize_t n = ::read(out_read.get(), buffer.data(), buffer.size());
      if (n > 0) {
        run.out.append(buffer.data(), static_cast<std::size_t>(n));
      } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        out_read.reset(); // end of output
      }
    }
  }
  in_write.reset();
  out_read.reset();
  blocked.consume_if(broken_pipe);
  if (run.timed_out) {
    ::kill(pid, SIGKILL);
  }
  reap(pid, &run.exit_code);
  return run;
}

LineProgram::LineProgram(const std::vector<std::string>& argv) {
  if (argv.empty()) {
    return;
  }
  Descriptor in_read, in_write, out_read, out_write, err_read, err_write;
  if (!make_pipe(in_read, in_write) || !make_pipe(out_read, out_write) ||
      !make_pipe(err_read, err_write)) {
    return;
  }
  const pid_t pid = spawn(argv, in_read.get(), out_write.get(), err_write.get());
  if (pid <= 0) {
    return;
  }
  pid_ = pid;
  // Ours are kept; the child's ends close with their Descriptors.
  in_ = in_write.get();
  out_ = out_read.get();
  err_ = err_read.get();
  in_write.release();
  out_read.release();
  err_read.release();
  ::fcntl(in_, F_SETFL, O_NONBLOCK); // write_line waits in poll, within its limit
  ::fcntl(out_, F_SETFL, O_NONBLOCK);
  ::fcntl(err_, F_SETFL, O_NONBLOCK);
}

LineProgram::~LineProgram() {
  finish(std::chrono::milliseconds(0));
}

LineProgram::Write LineProgram::write_line(const std::string& line,
                                           std::chrono::milliseconds limit) {
  if (in_ < 0) {
    return Write::closed;
  }
  // A program that does not read (a full pipe: 64 KiB on Linux) blocked a plain write for ever,
  // deaf to the run's limit and to SIGTERM. The write waits in poll, within `limit`, and keeps
  // reading what the program writes meanwhile: one that writes before it reads would otherwise
  // block on its own full output while this waits on its input.
  const auto deadline = std::chrono::steady_clock::now() + limit;
  const std::string text = line + "\n";
  PipeSignalBlocked blocked;
  std::size_t written = 0;
  bool broken_pipe = false;
  std::array<char, 65536> buffer{};
  while (written < text.size()) {
    const ssize_t n = ::write(in_, text.data() + written, text.size() - written);
    if (n > 0) {
      written += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) {
      continue;
    }
    if (n < 0 && errno != EAGAIN) {
      broken_pipe = errno == EPIPE;
      break;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      return Write::timeout;
    }
    std::array<pollfd, 3> fds{pollfd{in_, POLLOUT, 0}, pollfd{out_, POLLIN, 0},
                              pollfd{err_, POLLIN, 0}};
    if (::poll(fds.data(), fds.size(), static_cast<int>(left.count())) < 0 && errno != EINTR) {
      break;
    }
    drain_error();
    if (out_ >= 0 && (fds[1].revents & POLLIN) != 0 && pending_.size() <= 2 * max_line_bytes) {
      if (const ssize_t got = ::read(out_, buffer.data(), buffer.size()); got > 0) {
        pending_.append(buffer.data(), static_cast<std::size_t>(got));
      }
    }
  }
  blocked.consume_if(broken_pipe);
  return written == text.size() ? Write::done : Write::closed;
}

void LineProgram::drain_error() {
  std::array<char, 4096> buffer{};
  while (err_ >= 0) {
    const ssize_t n = ::read(err_, buffer.data(), buffer.size());
    if (n > 0) {
      error_.append(buffer.data(), static_cast<std::size_t>(n));
      if (error_.size() > 8192) {
        error_.erase(0, error_.size() - 4096);
      }
    } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
      ::close(err_);
      err_ = -1;
    } else if (errno == EAGAIN) {
      return;
    }
  }
}

LineProgram::Read LineProgram::read_line(std::string& line, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  std::array<char, 65536> buffer{};
  for (;;) {
    if (const std::size_t newline = pending_.find('\n'); newline != std::string::npos) {
      line = pending_.substr(0, newline);
      pending_.erase(0, newline + 1);
      return line.size() > max_line_bytes ? Read::too_long : Read::line;
    }
    if (pending_.size() > max_line_bytes) {
      line.clear();
      return Read::too_long;
    }
    if (out_ < 0) {
      line = std::exchange(pending_, {}); // a partial last line, if any
      return Read::end;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      line.clear();
      return Read::timeout;
    }
    std::array<pollfd, 2> fds{pollfd{out_, POLLIN, 0}, pollfd{err_, POLLIN, 0}};
    if (::poll(fds.data(), err_ >= 0 ? 2 : 1, static_cast<int>(left.count())) < 0 &&
        errno != EINTR) {
      line.clear();
      return Read::end;
    }
    drain_error();
    if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      const ssize_t n = ::read(out_, buffer.data(), buffer.size());
      if (n > 0) {
        pending_.append(buffer.data(), static_cast<std::size_t>(n));
      } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        ::close(out_);
        out_ = -1;
      }
    }
  }
}

void LineProgram::finish(std::chrono::milliseconds limit) {
  if (in_ >= 0) {
    ::close(in_);
    in_ = -1;
  }
  if (pid_ > 0) {
    // It may exit on its own once its input is closed; past the limit it is killed.
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int status = 0;
    pid_t done = 0;
    while ((done = ::waitpid(pid_, &status, WNOHANG)) == 0 &&
           std::chrono::steady_clock::now() < deadline) {
      drain_error();
      const timespec pause{0, 1000000};
      nanosleep(&pause, nullptr);
    }
    if (done == 0) { // pldamp stops it: said so, not as a signal of its own
      ::kill(pid_, SIGKILL);
      (void)reap(pid_);
      status_ = "stopped answering but did not exit (pldamp stopped it)";
    } else if (done == pid_) {
      status_ = describe(status);
    }
    pid_ = -1;
  }
  drain_error();
  for (int* fd : {&out_, &err_}) {
    if (*fd >= 0) {
      ::close(*fd);
      *fd = -1;
    }
  }
}

std::string LineProgram::last_error_line() const {
  const std::size_t end = error_.find_last_not_of(" \t\r\n");
  if (end == std::string::npos) {
    return "";
  }
  const std::size_t newline = error_.rfind('\n', end);
  const std::size_t begin = newline == std::string::npos ? 0 : newline + 1;
  const std::string line = error_.substr(begin, end + 1 - begin);
  return line.size() > 300 ? line.substr(0, 297) + "..." : line;
}

} // namespace pldamp::harness
