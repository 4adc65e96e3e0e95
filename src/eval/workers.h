/**
 * @file workers.h
 * @brief Work shared among threads, for the offline tools and the evaluation (ROS-free): a pool of
 *        workers taking items from a shared counter, and every item of a range done once.
 */
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace action_flow
{
/** Runs @p worker on max(1, @p jobs) threads at once and waits for all of them (the workers take
 *  their items from a shared counter and keep their own error; nothing may escape a worker). */
inline void runWorkers(int jobs, const std::function<void()>& worker)
{
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j)
    pool.emplace_back(worker);
  for (auto& t : pool)
    t.join();
}

/** Calls @p item(i) for every i < @p n on up to @p jobs threads, in no set order; when items throw,
 *  the error of the lowest index is rethrown once all have stopped. */
inline void forEachParallel(int jobs, std::size_t n, const std::function<void(std::size_t)>& item)
{
  std::atomic<std::size_t> next{ 0 };
  std::vector<std::exception_ptr> errors(n);
  runWorkers(static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, jobs)), n)), [&] {
    for (std::size_t i = next++; i < n; i = next++)
      try
      {
        item(i);
      }
      catch (...)
      {
        errors[i] = std::current_exception();
      }
  });
  for (const auto& e : errors)
    if (e)
      std::rethrow_exception(e);
}

}  // namespace action_flow
