#pragma once
// Starting a tool as a child process with its stdout and stderr in files, for the tools
// that drive other tools (valerant_eval runs valerant_explore, valerant_bench graph runs
// valerant_explore and roslaunch). POSIX fork/exec: std has nothing for this, and the
// children must keep running in parallel while the parent waits for any of them.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "valerant/common/error.h"

namespace valerant::tools {

namespace detail {

// The child's side of a start: stdout and stderr into files, `environment` added, then
// `argv` replaces the process (never returns; 126 when a log cannot be opened, 127 when
// the program cannot be executed).
[[noreturn]] inline void execChild(const std::vector<std::string>& argv, const std::string& stdout_path,
                                   const std::string& stderr_path,
                                   const std::map<std::string, std::string>& environment) {
  if (!freopen(stderr_path.c_str(), "w", stderr) || !freopen(stdout_path.c_str(), "w", stdout)) _exit(126);
  for (const auto& [name, value] : environment) setenv(name.c_str(), value.c_str(), 1);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  execvp(args[0], args.data());
  _exit(127);
}

}  // namespace detail

// Starts `argv[0]` (a path, or a name looked up on PATH) with `environment` added to
// this process's environment; returns its pid. The child stays in this process's
// process group (a Ctrl-C in the terminal reaches it too).
inline pid_t startChild(const std::vector<std::string>& argv, const std::string& stdout_path,
                        const std::string& stderr_path, const std::map<std::string, std::string>& environment = {}) {
  if (argv.empty()) throw InputError("startChild", "no command");
  const pid_t pid = fork();
  if (pid < 0) throw InputError(argv[0], "cannot start a process");
  if (pid == 0) detail::execChild(argv, stdout_path, stderr_path, environment);
  return pid;
}

// The path of `tool` built next to the running one (valerant_eval and valerant_bench
// start valerant_explore from their own folder, never from PATH).
inline std::string siblingTool(const std::string& tool) {
  const std::filesystem::path path = std::filesystem::read_symlink("/proc/self/exe").parent_path() / tool;
  if (!std::filesystem::exists(path)) throw InputError(path.string(), tool + " is not built next to this tool");
  return path.string();
}

// Waits for `pid`; true when it exited with status 0.
inline bool waitForChild(pid_t pid) {
  int status = 0;
  if (waitpid(pid, &status, 0) != pid) return false;
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace valerant::tools
