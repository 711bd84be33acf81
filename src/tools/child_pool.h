#pragma once
// Children that run in parallel, each in a process group of its own, with a time limit
// per child: valerant_eval's runs of valerant_explore. A child that runs past the limit
// gets SIGTERM to its whole group, and SIGKILL a grace period later if it still runs;
// terminate() sends SIGTERM to every child (for a Ctrl-C of the parent), killNow()
// SIGKILL, from a signal handler too. A child gets SIGTERM when the parent dies. The parent polls (poll(), then a short sleep): no
// SIGCHLD handler, and it reaps only its own children.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "child_process.h"

namespace valerant::tools {

struct ChildExit {
  size_t id = 0;           // what start() was given
  int status = 0;          // waitpid's status
  bool timed_out = false;  // ran past the time limit: its group got SIGTERM (and SIGKILL after the grace period)
  bool stopped = false;    // terminate() ended it
  bool killed = false;     // its group got SIGKILL
  double seconds = 0;      // from start to exit
  bool succeeded() const { return !timed_out && !stopped && WIFEXITED(status) && WEXITSTATUS(status) == 0; }
};

// "1", "0.5", "3600": seconds as written in a reason.
inline std::string secondsText(double seconds) {
  std::ostringstream out;
  if (seconds == std::floor(seconds) && std::fabs(seconds) < 1e15) {
    out << static_cast<long long>(seconds);
  } else {
    out << seconds;
  }
  return out.str();
}

class ChildPool {
 public:
  using Clock = std::chrono::steady_clock;

  // At most `capacity` children at a time. A child running longer than `timeout_s`
  // (0: no limit) gets SIGTERM to its process group, and SIGKILL `grace_s` later.
  ChildPool(size_t capacity, double timeout_s, double grace_s)
      : capacity_(capacity), timeout_s_(timeout_s), grace_s_(grace_s), groups_(new std::atomic<pid_t>[capacity]) {
    if (capacity < 1) throw InputError("ChildPool", "needs room for a child");
    for (size_t i = 0; i < capacity_; ++i) groups_[i] = 0;
  }
  ~ChildPool() { killNow(); reapAll(); }
  ChildPool(const ChildPool&) = delete;
  ChildPool& operator=(const ChildPool&) = delete;

  size_t running() const { return children_.size(); }
  bool full() const { return children_.size() >= capacity_; }
  double timeoutSeconds() const { return timeout_s_; }

  // Starts `argv` (stdout and stderr into files, `environment` added) in a new process
  // group whose id is its pid; `id` comes back in its ChildExit.
  void start(size_t id, const std::vector<std::string>& argv, const std::string& stdout_path,
             const std::string& stderr_path, const std::map<std::string, std::string>& environment = {}) {
    if (argv.empty()) throw InputError("ChildPool", "no command");
    if (full()) throw InputError(argv[0], "no room for another child");
    size_t slot = 0;
    while (groups_[slot].load() != 0) ++slot;
    // SIGINT and SIGTERM wait until the child is in groups_, so a handler that calls
    // killNow() never misses it; the child gets the caller's mask back before exec.
    sigset_t stop_signals, previous;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    sigprocmask(SIG_BLOCK, &stop_signals, &previous);
    const pid_t parent = getpid();
    const pid_t pid = fork();
    if (pid == 0) {
      setpgid(0, 0);
      // A parent that dies without stopping it (SIGKILL, a crash) still stops it.
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent) _exit(125);
      sigprocmask(SIG_SETMASK, &previous, nullptr);
      detail::execChild(argv, stdout_path, stderr_path, environment);
    }
    if (pid > 0) {
      setpgid(pid, pid);  // also here: a signal to the group may come before the child runs
      groups_[slot] = pid;
      Child child;
      child.pid = pid;
      child.id = id;
      child.slot = slot;
      child.started = Clock::now();
      children_.push_back(child);
    }
    sigprocmask(SIG_SETMASK, &previous, nullptr);
    if (pid < 0) throw InputError(argv[0], std::string("cannot start a process: ") + std::strerror(errno));
  }

  // The children that ended since the last call (reaped); sends the time limit's
  // signals to the ones still running. Never blocks.
  std::vector<ChildExit> poll() {
    std::vector<ChildExit> ended;
    const auto now = Clock::now();
    for (size_t i = 0; i < children_.size();) {
      Child& c = children_[i];
      siginfo_t info{};
      // WNOWAIT: the ended child stays a zombie, so its group id cannot be reused while
      // the rest of its group (anything it started) gets SIGKILL below.
      const int waited = waitid(P_PID, static_cast<id_t>(c.pid), &info, WEXITED | WNOHANG | WNOWAIT);
      if (waited < 0 && errno == EINTR) {
        ++i;
        continue;
      }
      if (waited < 0 || info.si_pid == c.pid) {
        if (c.signalled && waited == 0) killpg(c.pid, SIGKILL);
        groups_[c.slot] = 0;
        ChildExit e;
        e.id = c.id;
        e.timed_out = c.timed_out;
        e.stopped = c.stopped;
        e.killed = c.killed;
        e.seconds = std::chrono::duration<double>(now - c.started).count();
        if (waited < 0 || waitpid(c.pid, &e.status, 0) != c.pid) e.status = 255 << 8;  // lost: a failure
        ended.push_back(e);
        children_.erase(children_.begin() + static_cast<std::ptrdiff_t>(i));
        continue;
      }
      // The time limit holds for a stopped child too: it gets SIGKILL a grace period
      // after its limit.
      if (timeout_s_ > 0 && !c.timed_out && now - c.started >= seconds(timeout_s_)) {
        c.timed_out = c.signalled = true;
        killpg(c.pid, SIGTERM);
        c.kill_at = now + seconds(grace_s_);
      }
      if (c.kill_at && now >= *c.kill_at && !c.killed) {
        c.killed = true;
        killpg(c.pid, SIGKILL);
      }
      ++i;
    }
    return ended;
  }

  // SIGTERM to every running child's group (the ones not signalled yet); they are then
  // waited for: no SIGKILL follows before their time limit, or killNow().
  void terminate() {
    for (auto& c : children_) {
      if (c.signalled) continue;
      c.stopped = c.signalled = true;
      killpg(c.pid, SIGTERM);
    }
  }

  // SIGKILL to every running child's group. Async-signal-safe (a signal handler may
  // call it); the children stay to be reaped by poll() or the destructor.
  void killNow() noexcept {
    for (size_t i = 0; i < capacity_; ++i)
      if (const pid_t pid = groups_[i].load(); pid > 0) kill(-pid, SIGKILL);
  }

  // Why a child that did not succeed failed: "timed out after 5 s", "exited with status 1",
  // "killed by signal 9 (Killed)", "stopped"; "" when it succeeded.
  std::string failure(const ChildExit& e) const {
    if (e.timed_out) return "timed out after " + secondsText(timeout_s_) + " s";
    if (e.stopped) return "stopped before it finished";
    if (WIFEXITED(e.status)) {
      const int code = WEXITSTATUS(e.status);
      if (code == 0) return "";
      if (code == 126) return "exited with status 126 (its log files could not be opened)";
      if (code == 127) return "exited with status 127 (the program could not be executed)";
      return "exited with status " + std::to_string(code);
    }
    if (WIFSIGNALED(e.status))
      return "killed by signal " + std::to_string(WTERMSIG(e.status)) + " (" + strsignal(WTERMSIG(e.status)) + ")";
    return "ended with wait status " + std::to_string(e.status);
  }

 private:
  struct Child {
    pid_t pid = 0;
    size_t id = 0;
    size_t slot = 0;  // in groups_
    Clock::time_point started;
    bool signalled = false, timed_out = false, stopped = false, killed = false;
    std::optional<Clock::time_point> kill_at;
  };

  static Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  void reapAll() {
    for (const auto& c : children_) waitpid(c.pid, nullptr, 0);
    children_.clear();
  }

  size_t capacity_;
  double timeout_s_, grace_s_;
  std::vector<Child> children_;
  std::unique_ptr<std::atomic<pid_t>[]> groups_;  // running children's group ids (0: free), for killNow()
};

}  // namespace valerant::tools
