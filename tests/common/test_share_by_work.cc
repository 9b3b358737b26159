// Requirement: units of work shared out over processes by their expected work (largest first,
// each to the least busy process) keep the busiest process within the longest-processing-time
// bounds, and every process computes the same shares from the same inputs.
#include "common/errors.h"
#include "common/processes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

using namespace hertzgear;

namespace
{
  std::vector<double> loads_of(const std::vector<double> &work, const std::vector<std::size_t> &owner,
                               const std::size_t count)
  {
    std::vector<double> load(count, 0.0);
    for (std::size_t k = 0; k < work.size(); ++k)
      load.at(owner.at(k)) += work[k];
    return load;
  }
} // namespace

// The rule worked by hand: {3, 3, 2, 2, 2} on two processes. Largest first: the 3s go to ranks
// 0 and 1, the first 2 to rank 0 (the tie goes to the lower rank), the second to rank 1, the
// third to rank 0: 7 and 5. This is the textbook case where the rule misses the best shares
// ({3, 3} and {2, 2, 2}: 6) by Graham's bound 4/3 - 1/(3 m) = 7/6 exactly.
TEST(ShareByWork, LargestFirstToTheLeastBusyProcess)
{
  const std::vector<double> work = {2, 3, 2, 3, 2};
  const auto                owner = processes::share_by_work(work, 2);
  EXPECT_EQ(owner, (std::vector<std::size_t>{0, 0, 1, 1, 0}));
  const auto load = loads_of(work, owner, 2);
  EXPECT_EQ(load[0], 7.0);
  EXPECT_EQ(load[1], 5.0);
  EXPECT_DOUBLE_EQ(*std::max_element(load.begin(), load.end()) / 6.0, 4.0 / 3.0 - 1.0 / 6.0);
}

// A mesh cycle of 16 positions, 9 with two tooth pairs in contact (768 grid cells) and 7 with one
// (384), in the order of the cycle: positions by count (k mod 2) give one process 5 two-pair
// positions and 3 one-pair, the other 4 and 4: 5 * 4 + 3 = 23 against 20 (in units of a one-pair
// position's 384^2). By work the busiest has 22, within the one-pair unit of the mean 21.5.
TEST(ShareByWork, AMeshCycleIsSharedWithinOneSmallPositionOfTheMean)
{
  std::vector<double> work;
  for (int k = 0; k < 16; ++k)
    work.push_back(k < 9 ? 4.0 : 1.0);
  std::vector<std::size_t> by_count;
  for (std::size_t k = 0; k < work.size(); ++k)
    by_count.push_back(k % 2);
  const auto count_load = loads_of(work, by_count, 2);
  EXPECT_EQ(std::max(count_load[0], count_load[1]), 23.0);
  const auto load = loads_of(work, processes::share_by_work(work, 2), 2);
  EXPECT_EQ(load[0] + load[1], 43.0);
  EXPECT_EQ(std::max(load[0], load[1]), 22.0);
}

// On random units (seeded: the same in every run) the busiest process ends at most the largest
// unit above the mean, the bound of any rule that gives each unit to the least busy process, and
// no process is left without work while units are as many as processes.
TEST(ShareByWork, TheBusiestEndsWithinTheLargestUnitOfTheMean)
{
  std::mt19937                           random(20261130);
  std::uniform_real_distribution<double> unit(0.05, 1.0);
  for (const std::size_t count : {2u, 3u, 4u, 8u})
    for (const std::size_t n : {count, 2 * count + 1, std::size_t{64}, std::size_t{1024}})
      {
        std::vector<double> work(n);
        for (auto &w : work)
          w = unit(random);
        const auto owner = processes::share_by_work(work, count);
        EXPECT_EQ(owner, processes::share_by_work(work, count)) << "the same shares from the same inputs";
        const auto   load    = loads_of(work, owner, count);
        const double mean    = std::accumulate(work.begin(), work.end(), 0.0) / count;
        const double largest = *std::max_element(work.begin(), work.end());
        // Sums of n <= 1024 numbers below 1: round-off below 1e-12.
        EXPECT_LE(*std::max_element(load.begin(), load.end()), mean + largest + 1e-12) << count << " processes, " << n << " units";
        EXPECT_GT(*std::min_element(load.begin(), load.end()), 0.0) << count << " processes, " << n << " units";
      }
}

// Ties go to the process that has worked least before: the 16 positions above on four processes
// of which process 3 has done the most work before and process 2 the least. Nine units of 4:
// processes 2, 0, 1, 3 get one each, then one each again, and the ninth goes to process 2; the
// seven units of 1 then fill processes 0, 1, 3 (8 each) in that order: 9, 9, 9, 10, 10, 10, 11.
// The process that worked most ends with no more new work than any other.
TEST(ShareByWork, ATieGoesToTheProcessThatWorkedLeastBefore)
{
  std::vector<double> work;
  for (int k = 0; k < 16; ++k)
    work.push_back(k < 9 ? 4.0 : 1.0);
  const std::vector<double> earlier = {30.5, 31.0, 30.0, 33.3};
  const auto                load    = loads_of(work, processes::share_by_work(work, 4, earlier), 4);
  EXPECT_EQ(load, (std::vector<double>{11.0, 10.0, 12.0, 10.0}));
  // Without it the lowest rank takes the ties: process 0 the ninth unit of 4.
  EXPECT_EQ(loads_of(work, processes::share_by_work(work, 4), 4), (std::vector<double>{12.0, 11.0, 10.0, 10.0}));
  EXPECT_THROW(processes::share_by_work(work, 4, {1.0, 2.0}), InputError);
}

TEST(ShareByWork, RefusesNoProcessAndNegativeWork)
{
  EXPECT_THROW(processes::share_by_work({1.0}, 0), InputError);
  EXPECT_THROW(processes::share_by_work({1.0, -1.0}, 2), InputError);
  EXPECT_TRUE(processes::share_by_work({}, 3).empty());
}
