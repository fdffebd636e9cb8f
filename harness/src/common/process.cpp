#include "common/process.hpp"

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

extern char** environ;

namespace pldamp::harness {
namespace {

// A file descriptor closed when it goes out of scope.
class Descriptor {
public:
  explicit Descriptor(int fd = -1) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() { reset(); }
  int get() const { return fd_; }
  void reset(int fd = -1) {
    if (fd_ >= 0) {
      ::close(fd_);
    }
    fd_ = fd;
  }

private:
  int fd_;
};

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
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in_read.get(), STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out_write.get(), STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  std::vector<char*> args;
  for (const std::string& arg : argv) {
    args.push_back(const_cast<char*>(arg.c_str())); // posix_spawn's signature; not modified
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  in_read.reset();
  out_write.reset();
  if (spawned != 0) {
    return run;
  }
  run.started = true;

  // Feed stdin and drain stdout together, so neither side can block the other on a full pipe.
  ::fcntl(in_write.get(), F_SETFL, O_NONBLOCK);
  if (input.empty()) {
    in_write.reset();
  }
  // A child that exits early closes its stdin: writing must fail with EPIPE, not kill us. SIGPIPE
  // is blocked in this thread while we write, and a pending one consumed before unblocking.
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
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
  if (broken_pipe) {
    const timespec now{};
    sigtimedwait(&pipe_signal, nullptr, &now);
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  if (run.timed_out) {
    ::kill(pid, SIGKILL);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

} // namespace pldamp::harness
