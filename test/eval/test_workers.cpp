// forEachParallel (src/eval/workers.h), on which the tools train and extract at once: every item
// runs exactly once whatever the thread count, and an error reaches the caller only after every
// item has stopped, the lowest index's first.
#include <gtest/gtest.h>

#include "../../src/eval/workers.h"

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

using action_flow::forEachParallel;

TEST(Workers, EveryItemRunsOnceWhateverTheJobs)
{
  for (const int jobs : { 0, 1, 2, 5, 200 })
  {
    std::vector<std::atomic<int>> runs(97);
    forEachParallel(jobs, runs.size(), [&](std::size_t i) { ++runs[i]; });
    for (std::size_t i = 0; i < runs.size(); ++i)
      EXPECT_EQ(runs[i].load(), 1) << "item " << i << " with " << jobs << " jobs";
  }
  bool called = false;
  forEachParallel(2, 0, [&](std::size_t) { called = true; });
  EXPECT_FALSE(called) << "no items, no calls";
}

TEST(Workers, TheLowestFailingItemIsRethrownAfterAllHaveRun)
{
  std::atomic<int> finished{ 0 };
  try
  {
    forEachParallel(3, 40, [&](std::size_t i) {
      ++finished;
      if (i == 31 || i == 7 || i == 12)
        throw std::runtime_error("item " + std::to_string(i));
    });
    FAIL() << "no error reached the caller";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_EQ(std::string(e.what()), "item 7");
  }
  EXPECT_EQ(finished.load(), 40) << "one item's error must not stop the others";
}
