#include "common/process.hpp"

#include "common/files.hpp"

#include <cctype>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
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

// The process group a program is started in: pldamp's (a terminal's Ctrl-C reaches it too), or
// one of its own, whose id is its pid (what it forks can then be stopped with it).
enum class ProcessGroup { pldamps, own };

// Starts argv (looked up on PATH) with the given descriptors as its standard input, output and
// error (err < 0: /dev/null). Returns its pid, or -1.
pid_t spawn(const std::vector<std::string>& argv, int in, int out, int err, ProcessGroup group) {
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  if (group == ProcessGroup::own) {
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
  }
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
  const int spawned = posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
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

// Whether a process of process group `group` still runs. A zombie does not: a child a program
// forked and pldamp killed is one until its new parent reaps it, and a container's init may never
// do so. Read from /proc (each /proc/PID/stat: "PID (NAME) STATE PPID PGRP ...", NAME may hold
// spaces and parentheses); without /proc, kill(-group, 0), which counts zombies too.
bool group_runs(pid_t group) {
  DIR* processes = ::opendir("/proc");
  if (processes == nullptr) {
    return ::kill(-group, 0) == 0;
  }
  bool runs = false;
  while (const dirent* entry = ::readdir(processes)) {
    if (std::isdigit(static_cast<unsigned char>(entry->d_name[0])) == 0) {
      continue;
    }
    const std::string path = std::string("/proc/") + entry->d_name + "/stat";
    const Descriptor stat(::open(path.c_str(), O_RDONLY | O_CLOEXEC));
    std::array<char, 1024> buffer{};
    const ssize_t n = stat.get() < 0 ? -1 : ::read(stat.get(), buffer.data(), buffer.size() - 1);
    if (n <= 0) {
      continue; // ended meanwhile
    }
    const std::string_view text(buffer.data(), static_cast<std::size_t>(n));
    const std::size_t name_end = text.rfind(')');
    char state = 0;
    long parent = 0, its_group = 0;
    if (name_end != std::string_view::npos &&
        std::sscanf(buffer.data() + name_end + 1, " %c %ld %ld", &state, &parent, &its_group) ==
            3 &&
        its_group == group && state != 'Z' && state != 'X') {
      runs = true;
      break;
    }
  }
  ::closedir(processes);
  return runs;
}

// How often a wait for a program's line looks whether the program itself has exited: its pipes
// tell only when every process holding them has (a child it forked may hold them for hours).
constexpr std::chrono::milliseconds exit_check_interval{10};

// How long a poll for a program may wait: until the deadline, at most exit_check_interval.
int poll_timeout(std::chrono::steady_clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
      deadline - std::chrono::steady_clock::now());
  return static_cast<int>(
      std::clamp(left, std::chrono::milliseconds(0), exit_check_interval).count());
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
  const pid_t pid = spawn(argv, in_read.get(), out_write.get(), -1, ProcessGroup::pldamps);
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

LineProgram::LineProgram(const std::vector<std::string>& argv, const std::atomic<bool>* stop)
    : stop_(stop) {
  if (argv.empty()) {
    return;
  }
  Descriptor in_read, in_write, out_read, out_write, err_read, err_write;
  if (!make_pipe(in_read, in_write) || !make_pipe(out_read, out_write) ||
      !make_pipe(err_read, err_write)) {
    return;
  }
  const pid_t pid = spawn(argv, in_read.get(), out_write.get(), err_write.get(), ProcessGroup::own);
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

bool LineProgram::stop_requested() const {
  return stop_ != nullptr && stop_->load();
}

bool LineProgram::has_exited() {
  if (!exited_ && pid_ > 0) {
    // WNOWAIT: noticed, not reaped. finish() reaps it, after signalling its group: until then its
    // pid, the group's id, cannot be taken by another process.
    siginfo_t info{};
    exited_ = ::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 &&
              info.si_pid == pid_;
  }
  return exited_;
}

LineProgram::Write LineProgram::write_line(const std::string& line,
                                           std::chrono::milliseconds limit) {
  if (in_ < 0) {
    return Write::closed;
  }
  // A program that does not read (a full pipe: 64 KiB on Linux) blocked a plain write for ever,
  // deaf to the run's limit and to SIGTERM. The write waits in poll, within `limit`, and keeps
  // reading what the program writes meanwhile: one that writes before it reads would otherwise
  // block on its own full output while this waits on its input. A program that has exited no
  // longer reads, though a child it forked may hold its input open.
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
    if (stop_requested()) {
      return Write::stopped;
    }
    if (has_exited()) {
      break;
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      return Write::timeout;
    }
    std::array<pollfd, 3> fds{pollfd{in_, POLLOUT, 0}, pollfd{out_, POLLIN, 0},
                              pollfd{err_, POLLIN, 0}};
    if (::poll(fds.data(), fds.size(), poll_timeout(deadline)) < 0 && errno != EINTR) {
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

bool LineProgram::read_output() {
  std::array<char, 65536> buffer{};
  const ssize_t n = ::read(out_, buffer.data(), buffer.size());
  if (n > 0) {
    pending_.append(buffer.data(), static_cast<std::size_t>(n));
    return true;
  }
  if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
    ::close(out_);
    out_ = -1;
  }
  return false;
}

LineProgram::Read LineProgram::read_line(std::string& line, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
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
    if (stop_requested()) {
      line.clear();
      return Read::stopped;
    }
    if (has_exited()) {
      // All it wrote is in the pipe: read it, and its output has ended, whatever a child it
      // forked still holds (the pipe's end of file waited for that child, an hour for a sleeper).
      while (out_ >= 0 && pending_.size() <= max_line_bytes && read_output()) {
      }
      if (out_ >= 0) {
        ::close(out_);
        out_ = -1;
      }
      continue;
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      line.clear();
      return Read::timeout;
    }
    std::array<pollfd, 2> fds{pollfd{out_, POLLIN, 0}, pollfd{err_, POLLIN, 0}};
    if (::poll(fds.data(), err_ >= 0 ? 2 : 1, poll_timeout(deadline)) < 0 && errno != EINTR) {
      line.clear();
      return Read::end;
    }
    drain_error();
    if ((fds[0].revents & (POLLIN | POLLHUP | POLLERR)) != 0) {
      read_output();
    }
  }
}

void LineProgram::finish(std::chrono::milliseconds limit) {
  if (in_ >= 0) {
    ::close(in_);
    in_ = -1;
  }
  if (pid_ > 0) {
    // It may exit on its own once its input is closed, within the limit. Then its process group
    // is stopped, whatever the program did: what it forked and left running goes with it, asked
    // with SIGTERM, then, past the same limit, killed.
    const auto wait_until = [&](const std::function<bool()>& done) {
      const auto deadline = std::chrono::steady_clock::now() + limit;
      while (std::chrono::steady_clock::now() < deadline && !done()) {
        drain_error();
        const timespec pause{0, 2000000};
        nanosleep(&pause, nullptr);
      }
    };
    wait_until([&] { return has_exited(); });
    const bool exited_itself = has_exited();
    ::kill(-pid_, SIGTERM);
    wait_until([&] { return !group_runs(pid_); });
    ::kill(-pid_, SIGKILL);
    const std::string ended = reap(pid_); // last: its pid named the group until now
    // pldamp stopped it: said so, not as a signal of its own.
    status_ = exited_itself ? ended : "stopped answering but did not exit (pldamp stopped it)";
    pid_ = -1;
    exited_ = false;
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
