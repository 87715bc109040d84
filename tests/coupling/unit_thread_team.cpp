// ThreadTeam (src/coupling/thread_team.h): the caller and one worker share
// the interface's loops. Each check can fail: a part that did not run, a
// barrier that let a part through early, an exception lost, a nested or
// concurrent task that deadlocked (the test would not finish).
#include "../../src/coupling/thread_team.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <atomic>
#include <array>
#include <stdexcept>
#include <thread>
#include <vector>

using fretsim::coupling::TeamPart;
using fretsim::coupling::ThreadTeam;

TEST(ThreadTeam, EveryPartRunsOnceAndTheBarrierOrdersThem)
{
  omp_set_num_threads(2); // the team follows the caller's OpenMP threads
  ThreadTeam team(2);
  ASSERT_EQ(team.size(), 2);
  for (int round = 0; round < 2000; ++round)
    {
      std::array<int, 2>     written{-1, -1}, seen{-1, -1};
      std::atomic<int>       calls{0};
      std::array<int, 2>     parts{0, 0};
      team.run([&](const TeamPart &part) {
        ++calls;
        parts[part.part] = part.parts;
        written[part.part] = round + part.part;
        part.wait(); // both written
        seen[part.part] = written[1 - part.part];
        part.wait();
        written[part.part] = -2; // not before the other has read it
      });
      ASSERT_EQ(calls.load(), 2);
      ASSERT_EQ(parts, (std::array<int, 2>{2, 2}));
      ASSERT_EQ(seen[0], round + 1);
      ASSERT_EQ(seen[1], round);
      // Every few rounds the worker has time to go to sleep: it must wake.
      if (round % 500 == 0)
        std::this_thread::sleep_for(std::chrono::duration<double>(5 * ThreadTeam::spin_seconds));
    }
}

TEST(ThreadTeam, ATeamOfOneAndATaskWithinATaskRunOnTheirCaller)
{
  ThreadTeam alone(1);
  EXPECT_EQ(alone.size(), 1);
  int parts = 0;
  alone.run([&](const TeamPart &part) {
    parts = part.parts;
    part.wait(); // nothing to wait for
  });
  EXPECT_EQ(parts, 1);

  omp_set_num_threads(2);
  ThreadTeam         team(2);
  std::array<int, 2> inner{0, 0};
  team.run([&](const TeamPart &part) {
    team.run([&](const TeamPart &nested) { inner[part.part] = nested.parts; });
  });
  EXPECT_EQ(inner, (std::array<int, 2>{1, 1}));
  // `fretsim map`'s threads allow their OpenMP one thread: their loops run alone.
  omp_set_num_threads(1);
  team.run([&](const TeamPart &part) { parts = part.parts; });
  EXPECT_EQ(parts, 1);
  omp_set_num_threads(2);
  team.run([&](const TeamPart &part) { inner[part.part] = part.parts; });
  EXPECT_EQ(inner, (std::array<int, 2>{2, 2}));
}

TEST(ThreadTeam, AnExceptionOfEitherPartReachesTheCaller)
{
  omp_set_num_threads(2);
  ThreadTeam team(2);
  for (int thrower = 0; thrower < 2; ++thrower)
    EXPECT_THROW(team.run([&](const TeamPart &part) {
                   if (part.part == thrower)
                     throw std::runtime_error("part failed");
                 }),
                 std::runtime_error);
  int sum = 0; // and the team still works
  std::array<int, 2> values{0, 0};
  team.run([&](const TeamPart &part) { values[part.part] = part.part + 1; });
  sum = values[0] + values[1];
  EXPECT_EQ(sum, 3);
}

TEST(ThreadTeam, TwoCallersAtOnceBothGetTheirSums)
{
  // The second caller finds the team busy and runs alone: every task's
  // parts together still cover its work exactly once.
  ThreadTeam        team(2);
  std::atomic<long> wrong{0};
  const auto        caller = [&](int offset) {
    omp_set_num_threads(2);
    for (int round = 0; round < 3000; ++round)
      {
        std::vector<long> done(100, 0);
        team.run([&](const TeamPart &part) {
          const auto [begin, end] = part.share(done.size());
          for (std::size_t k = begin; k < end; ++k)
            done[k] += offset + static_cast<long>(k);
        });
        for (std::size_t k = 0; k < done.size(); ++k)
          wrong += done[k] != offset + static_cast<long>(k);
      }
  };
  std::thread first(caller, 1), second(caller, 1000);
  first.join();
  second.join();
  EXPECT_EQ(wrong.load(), 0);
}

TEST(ThreadTeam, ItsSizeFollowsOpenMPsThreadsAndWaitPolicy)
{
  EXPECT_EQ(ThreadTeam::threads_for(nullptr, 2), 2);
  EXPECT_EQ(ThreadTeam::threads_for("PASSIVE", 8), 2);
  EXPECT_EQ(ThreadTeam::threads_for(nullptr, 1), 1);
  // OpenMP's threads spinning for ever would keep the worker off the cores.
  EXPECT_EQ(ThreadTeam::threads_for("ACTIVE", 2), 1);
  EXPECT_EQ(ThreadTeam::threads_for("active", 4), 1);
}
