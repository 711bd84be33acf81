// valerant_eval's runs as children: the time limit per run (SIGTERM to the run's process
// group, SIGKILL after the grace period), stopping every run, and the reasons a run failed.
// Small children (sleep, sh) stand in for valerant_explore; each test takes about 1 s at most.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "child_pool.h"

using namespace valerant;
using tools::ChildExit;
using tools::ChildPool;

namespace {

std::string logDir() {
  const std::string dir = ::testing::TempDir() + "/valerant_child_pool";
  std::filesystem::create_directories(dir);
  return dir;
}

// Starts `argv` as child `id` with its logs in logDir().
void start(ChildPool& pool, size_t id, const std::vector<std::string>& argv) {
  const std::string base = logDir() + "/" + std::to_string(id);
  pool.start(id, argv, base + ".out", base + ".err");
}

// Polls until `count` children ended (at most 10 s), by id.
std::map<size_t, ChildExit> waitFor(ChildPool& pool, size_t count) {
  std::map<size_t, ChildExit> ended;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (ended.size() < count && std::chrono::steady_clock::now() < give_up) {
    for (const auto& e : pool.poll()) ended[e.id] = e;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return ended;
}

// Whether process `pid` has ended (gone, or a zombie nobody reaped yet), within 2 s.
bool ends(pid_t pid) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < give_up) {
    std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
    std::string text;
    if (!stat || !std::getline(stat, text)) return true;
    const size_t paren = text.rfind(')');
    if (paren != std::string::npos && paren + 2 < text.size() && text[paren + 2] == 'Z') return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

pid_t pidIn(const std::string& path) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  pid_t pid = 0;
  while (pid == 0 && std::chrono::steady_clock::now() < give_up) {
    std::ifstream(path) >> pid;
    if (pid == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pid;
}

}  // namespace

TEST(EvalChildPool, ARunPastItsTimeLimitIsTerminatedAndSaysSo) {
  ChildPool pool(2, 0.3, 5);
  start(pool, 7, {"/bin/sleep", "30"});
  start(pool, 8, {"/bin/sh", "-c", "exit 3"});
  EXPECT_TRUE(pool.full());
  const auto ended = waitFor(pool, 2);
  ASSERT_EQ(ended.size(), 2u);
  const ChildExit& slow = ended.at(7);
  EXPECT_TRUE(slow.timed_out);
  EXPECT_FALSE(slow.killed);  // SIGTERM was enough
  EXPECT_TRUE(WIFSIGNALED(slow.status) && WTERMSIG(slow.status) == SIGTERM);
  EXPECT_GE(slow.seconds, 0.3);
  EXPECT_LT(slow.seconds, 3.0);
  EXPECT_FALSE(slow.succeeded());
  EXPECT_EQ(pool.failure(slow), "timed out after 0.3 s");
  EXPECT_FALSE(ended.at(8).timed_out);
  EXPECT_EQ(pool.failure(ended.at(8)), "exited with status 3");
  EXPECT_EQ(pool.running(), 0u);
}

TEST(EvalChildPool, ARunThatIgnoresSigtermGetsSigkillWithItsGroup) {
  // The run and what it started ignore SIGTERM: after the grace period both get SIGKILL.
  const std::string pid_file = logDir() + "/ignoring.pid";
  std::filesystem::remove(pid_file);
  ChildPool pool(1, 0.5, 0.3);
  start(pool, 1, {"/bin/sh", "-c", "trap '' TERM; sleep 30 & echo $! > " + pid_file + "; wait"});
  const pid_t grandchild = pidIn(pid_file);
  ASSERT_GT(grandchild, 0);
  const auto ended = waitFor(pool, 1);
  ASSERT_EQ(ended.size(), 1u);
  const ChildExit& e = ended.at(1);
  EXPECT_TRUE(e.timed_out);
  EXPECT_TRUE(e.killed);
  EXPECT_TRUE(WIFSIGNALED(e.status) && WTERMSIG(e.status) == SIGKILL);
  EXPECT_GE(e.seconds, 0.8);
  EXPECT_EQ(pool.failure(e), "timed out after 0.5 s");
  EXPECT_TRUE(ends(grandchild));
}

TEST(EvalChildPool, WhatARunStartedDiesWithIt) {
  // The run ends on SIGTERM; a process it started ignores SIGTERM and would outlive it.
  const std::string pid_file = logDir() + "/survivor.pid";
  std::filesystem::remove(pid_file);
  ChildPool pool(1, 0.5, 30);
  start(pool, 1, {"/bin/sh", "-c", "(trap '' TERM; exec sleep 30) & echo $! > " + pid_file + "; wait"});
  const pid_t grandchild = pidIn(pid_file);
  ASSERT_GT(grandchild, 0);
  const auto ended = waitFor(pool, 1);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_TRUE(ended.at(1).timed_out);
  EXPECT_FALSE(ended.at(1).killed);
  EXPECT_TRUE(ends(grandchild));  // SIGKILL to the group when the run ended
}

TEST(EvalChildPool, NoTimeLimitTerminateAndKillNow) {
  ChildPool pool(3, 0, 0.1);  // 0: no time limit
  start(pool, 1, {"/bin/sleep", "0.4"});
  start(pool, 2, {"/bin/sleep", "30"});
  start(pool, 3, {"/bin/sh", "-c", "trap '' TERM; sleep 30"});
  EXPECT_THROW(start(pool, 4, {"/bin/true"}), InputError);  // full
  auto ended = waitFor(pool, 1);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_TRUE(ended.at(1).succeeded());
  EXPECT_EQ(pool.failure(ended.at(1)), "");
  // A stop: SIGTERM to each, no SIGKILL after the grace period.
  pool.terminate();
  ended = waitFor(pool, 1);
  ASSERT_EQ(ended.count(2), 1u);
  EXPECT_TRUE(ended.at(2).stopped);
  EXPECT_FALSE(ended.at(2).timed_out);
  EXPECT_TRUE(WIFSIGNALED(ended.at(2).status) && WTERMSIG(ended.at(2).status) == SIGTERM);
  EXPECT_EQ(pool.failure(ended.at(2)), "stopped before it finished");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_TRUE(pool.poll().empty());  // the one ignoring SIGTERM still runs
  EXPECT_EQ(pool.running(), 1u);
  pool.killNow();
  ended = waitFor(pool, 1);
  ASSERT_EQ(ended.count(3), 1u);
  EXPECT_TRUE(WIFSIGNALED(ended.at(3).status) && WTERMSIG(ended.at(3).status) == SIGKILL);
}

TEST(EvalChildPool, AProgramThatCannotStartIsAFailureWithItsReason) {
  ChildPool pool(1, 10, 1);
  start(pool, 5, {"/nonexistent/valerant_explore"});
  const auto ended = waitFor(pool, 1);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_EQ(pool.failure(ended.at(5)), "exited with status 127 (the program could not be executed)");
  EXPECT_EQ(tools::secondsText(3600), "3600");
  EXPECT_EQ(tools::secondsText(0.5), "0.5");
}

TEST(EvalChildPool, AStoppedRunStillHasItsTimeLimit) {
  const std::string ready = logDir() + "/stopped.ready";
  std::filesystem::remove(ready);
  ChildPool pool(1, 0.5, 0.2);
  start(pool, 1, {"/bin/sh", "-c", "trap '' TERM; echo 1 > " + ready + "; sleep 30"});
  ASSERT_GT(pidIn(ready), 0);
  pool.terminate();  // ignored: SIGKILL a grace period after the limit
  const auto ended = waitFor(pool, 1);
  ASSERT_EQ(ended.size(), 1u);
  EXPECT_TRUE(ended.at(1).stopped);
  EXPECT_TRUE(ended.at(1).timed_out);
  EXPECT_TRUE(WIFSIGNALED(ended.at(1).status) && WTERMSIG(ended.at(1).status) == SIGKILL);
  EXPECT_GE(ended.at(1).seconds, 0.7);
}

TEST(EvalChildPool, ARunEndsWhenItsParentDiesWithoutStoppingIt) {
  // A parent that stands in for a valerant_eval killed by SIGKILL: it starts a run and
  // exits without a word to it.
  const std::string pid_file = logDir() + "/orphan.pid";
  std::filesystem::remove(pid_file);
  const pid_t parent = fork();
  ASSERT_GE(parent, 0);
  if (parent == 0) {
    auto* pool = new ChildPool(1, 0, 1);  // never destroyed: no SIGKILL from ~ChildPool
    start(*pool, 1, {"/bin/sh", "-c", "echo $$ > " + pid_file + "; exec sleep 30"});
    while (!std::filesystem::exists(pid_file)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(parent, &status, 0), parent);
  const pid_t run = pidIn(pid_file);
  ASSERT_GT(run, 0);
  EXPECT_TRUE(ends(run));
}
