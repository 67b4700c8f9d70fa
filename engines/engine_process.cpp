#include "engines/engine_process.hpp"

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace demcal::engines {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void sleep_s(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

// SIGINT / SIGTERM caught while launches run (see the header). A lock-free
// atomic int is safe to store from a signal handler.
std::atomic<int> g_interrupt{0};
static_assert(std::atomic<int>::is_always_lock_free);

extern "C" void on_interrupt(int signal) { g_interrupt.store(signal); }

constexpr int kCaught[] = {SIGINT, SIGTERM};

class InterruptGuard {
 public:
  static InterruptGuard& instance() {
    static InterruptGuard g;
    return g;
  }

  void enter() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (active_++ > 0) return;
    g_interrupt.store(0);
    for (std::size_t i = 0; i < std::size(kCaught); ++i) {
      installed_[i] = false;
      ::sigaction(kCaught[i], nullptr, &old_[i]);
      // An ignored signal stays ignored (a job started with nohup or in the background).
      if (old_[i].sa_handler == SIG_IGN) continue;
      struct sigaction sa {};
      sa.sa_handler = on_interrupt;
      ::sigemptyset(&sa.sa_mask);
      ::sigaction(kCaught[i], &sa, nullptr);
      installed_[i] = true;
    }
  }

  // After a launch that ran to its end (or was cancelled otherwise).
  // A signal caught after the process ended (or before it started) is not
  // swallowed: the last one out raises it once demcal's disposition is back.
  void leave() {
    int pending = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (--active_ == 0) {
        restore_locked();
        pending = g_interrupt.exchange(0);
      }
    }
    if (pending != 0) ::raise(pending);
  }

  // After a launch ended by `signal`: the last one out restores demcal's own
  // disposition and raises the signal again; the others wait for it, so that
  // no caller records a run of a process about to end.
  void leave_interrupted(int signal) {
    std::unique_lock<std::mutex> lock(mutex_);
    const unsigned long epoch = epoch_;
    if (--active_ == 0) {
      restore_locked();
      lock.unlock();
      ::raise(signal);
      return;
    }
    ended_.wait(lock, [&] { return epoch_ != epoch; });
  }

 private:
  void restore_locked() {
    for (std::size_t i = 0; i < std::size(kCaught); ++i)
      if (installed_[i]) ::sigaction(kCaught[i], &old_[i], nullptr);
    ++epoch_;
    ended_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable ended_;
  int active_ = 0;
  unsigned long epoch_ = 0;
  struct sigaction old_[std::size(kCaught)]{};
  bool installed_[std::size(kCaught)] = {};
};

// Whether a process of group `group` still runs. Its members that ended but
// are not yet reaped by init (zombies) do not count: init may take a while.
bool group_runs(pid_t group) {
  if (::kill(-group, 0) == -1 && errno == ESRCH) return false;
  std::error_code ec;
  std::filesystem::directory_iterator proc("/proc", ec);
  if (ec) return true;  // no /proc: only kill() can tell, and it says some are left
  for (const auto& entry : proc) {
    const std::string name = entry.path().filename().string();
    if (name.empty() || name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "stat");
    std::string line;
    if (!std::getline(in, line)) continue;
    // pid (comm) state ppid pgrp ...: comm may hold spaces and parentheses.
    const std::size_t close = line.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(line.substr(close + 1));
    char state = 0;
    long ppid = 0, pgrp = 0;
    if (rest >> state >> ppid >> pgrp && pgrp == group && state != 'Z' && state != 'X') return true;
  }
  return false;
}

// SIGTERM to the whole group, then SIGKILL after the grace period; the leader reaped.
void end_group(pid_t leader, double grace_period_s, int* status) {
  ::kill(-leader, SIGTERM);
  const Clock::time_point start = Clock::now();
  bool reaped = false;
  while (true) {
    if (!reaped && ::waitpid(leader, status, WNOHANG) == leader) reaped = true;
    // The group is gone once its last process is (the leader reaped first).
    if (reaped && !group_runs(leader)) return;
    if (seconds_since(start) >= grace_period_s) break;
    sleep_s(0.02);
  }
  ::kill(-leader, SIGKILL);
  while (!reaped) {
    const pid_t r = ::waitpid(leader, status, 0);
    reaped = r == leader || (r == -1 && errno != EINTR);
  }
}

std::string format_seconds(double s) {
  std::ostringstream os;
  os << s;
  return os.str();
}

// Owns the spawn attributes and file actions.
struct SpawnSetup {
  posix_spawn_file_actions_t actions;
  posix_spawnattr_t attr;
  SpawnSetup() {
    ::posix_spawn_file_actions_init(&actions);
    ::posix_spawnattr_init(&attr);
  }
  ~SpawnSetup() {
    ::posix_spawn_file_actions_destroy(&actions);
    ::posix_spawnattr_destroy(&attr);
  }
  SpawnSetup(const SpawnSetup&) = delete;
  SpawnSetup& operator=(const SpawnSetup&) = delete;
};

pid_t spawn(const ProcessOptions& o) {
  SpawnSetup s;
  int rc = 0;
  rc |= ::posix_spawn_file_actions_addchdir_np(&s.actions, o.working_directory.c_str());
  // Not the terminal: in a group of its own, a read from it would stop the engine (SIGTTIN).
  rc |= ::posix_spawn_file_actions_addopen(&s.actions, 0, "/dev/null", O_RDONLY, 0);
  rc |= ::posix_spawn_file_actions_addopen(&s.actions, 1, o.output.c_str(),
                                           O_WRONLY | O_CREAT | O_TRUNC, 0644);
  rc |= ::posix_spawn_file_actions_adddup2(&s.actions, 1, 2);
  // Its own group, so that it and everything it starts can be signalled at once.
  rc |= ::posix_spawnattr_setpgroup(&s.attr, 0);
  sigset_t none, defaults;
  ::sigemptyset(&none);
  ::sigemptyset(&defaults);
  ::sigaddset(&defaults, SIGINT);
  ::sigaddset(&defaults, SIGTERM);
  ::sigaddset(&defaults, SIGQUIT);
  rc |= ::posix_spawnattr_setsigmask(&s.attr, &none);
  rc |= ::posix_spawnattr_setsigdefault(&s.attr, &defaults);
  rc |= ::posix_spawnattr_setflags(
      &s.attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  if (rc != 0) throw std::runtime_error("engine launch: cannot prepare the spawn of /bin/sh");
  std::string line = o.command_line;
  char sh[] = "sh";
  char dash_c[] = "-c";
  char* argv[] = {sh, dash_c, line.data(), nullptr};
  pid_t pid = 0;
  const int err = ::posix_spawn(&pid, "/bin/sh", &s.actions, &s.attr, argv, environ);
  if (err != 0)
    throw std::runtime_error("engine launch: cannot start /bin/sh -c \"" + o.command_line +
                             "\" in " + o.working_directory.string() + " (output " +
                             o.output.string() + "): " + std::strerror(err));
  return pid;
}

}  // namespace

std::string signal_name(int signal) {
  switch (signal) {
    case SIGHUP:
      return "SIGHUP";
    case SIGINT:
      return "SIGINT";
    case SIGQUIT:
      return "SIGQUIT";
    case SIGILL:
      return "SIGILL";
    case SIGTRAP:
      return "SIGTRAP";
    case SIGABRT:
      return "SIGABRT";
    case SIGBUS:
      return "SIGBUS";
    case SIGFPE:
      return "SIGFPE";
    case SIGKILL:
      return "SIGKILL";
    case SIGUSR1:
      return "SIGUSR1";
    case SIGSEGV:
      return "SIGSEGV";
    case SIGUSR2:
      return "SIGUSR2";
    case SIGPIPE:
      return "SIGPIPE";
    case SIGALRM:
      return "SIGALRM";
    case SIGTERM:
      return "SIGTERM";
    case SIGXCPU:
      return "SIGXCPU";
    case SIGXFSZ:
      return "SIGXFSZ";
    default:
      return "signal " + std::to_string(signal);
  }
}

std::string ProcessOutcome::describe() const {
  switch (ended) {
    case Ended::exited: {
      std::string s = "exited with status " + std::to_string(exit_code);
      // The shell reports a command killed by signal N as 128 + N.
      if (exit_code > 128 && exit_code < 128 + 65)
        s += " (the shell's code for " + signal_name(exit_code - 128) + ")";
      return s;
    }
    case Ended::signalled:
      return "killed by " + signal_name(signal);
    case Ended::timed_out:
    case Ended::cancelled:
      return reason;
  }
  return reason;
}

ProcessOutcome run_process(const ProcessOptions& o) {
  if (o.timeout_s && !(*o.timeout_s > 0.0))
    throw std::invalid_argument("run_process: timeout_s must be > 0");
  InterruptGuard& guard = InterruptGuard::instance();
  guard.enter();
  pid_t pid = 0;
  try {
    pid = spawn(o);
  } catch (...) {
    guard.leave();
    throw;
  }
  ProcessOutcome out;
  const Clock::time_point start = Clock::now();
  int status = 0;
  int interrupted = 0;
  std::exception_ptr thrown;
  while (true) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r == -1 && errno != EINTR) {
      // Not ours to wait for any more (cannot happen unless someone reaped it).
      status = 0;
      out.reason = std::string("lost track of the process: ") + std::strerror(errno);
      out.ended = ProcessOutcome::Ended::cancelled;
      break;
    }
    if ((interrupted = g_interrupt.load()) != 0) {
      end_group(pid, o.grace_period_s, &status);
      out.ended = ProcessOutcome::Ended::cancelled;
      out.signal = interrupted;
      out.reason = "interrupted by " + signal_name(interrupted);
      break;
    }
    if (o.cancel != nullptr && o.cancel->load()) {
      end_group(pid, o.grace_period_s, &status);
      out.ended = ProcessOutcome::Ended::cancelled;
      out.reason = "cancelled";
      break;
    }
    if (o.timeout_s && seconds_since(start) >= *o.timeout_s) {
      end_group(pid, o.grace_period_s, &status);
      out.ended = ProcessOutcome::Ended::timed_out;
      out.reason = "timed out after " + format_seconds(*o.timeout_s) + " s";
      break;
    }
    if (o.poll) {
      try {
        o.poll();
      } catch (...) {
        thrown = std::current_exception();
        end_group(pid, o.grace_period_s, &status);
        break;
      }
    }
    sleep_s(o.poll_interval_s);
  }
  out.wall_time_s = seconds_since(start);
  if (interrupted != 0) {
    guard.leave_interrupted(interrupted);  // does not return when the signal ends demcal
  } else {
    guard.leave();
  }
  if (thrown) std::rethrow_exception(thrown);
  if (out.ended == ProcessOutcome::Ended::exited) {
    if (WIFSIGNALED(status)) {
      out.ended = ProcessOutcome::Ended::signalled;
      out.signal = WTERMSIG(status);
    } else if (WIFEXITED(status)) {
      out.exit_code = WEXITSTATUS(status);
    }
  }
  return out;
}

}  // namespace demcal::engines
