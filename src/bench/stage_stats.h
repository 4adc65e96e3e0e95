/**
 * @file stage_stats.h
 * @brief Collects per-frame timings of one benchmark stage and summarises them (median, p95).
 */
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace action_flow
{
namespace bench
{
/** @brief Timings (seconds) of one stage, one sample per frame or per call. */
class StageSamples
{
public:
  void add(double seconds) { samples_.push_back(seconds); }
  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  const std::vector<double>& samples() const { return samples_; }

  /**
   * @brief The nearest-rank percentile: the smallest sample with at least @p q of all samples at or
   *        below it (q in (0,1]); the median is q = 0.5 (lower median for an even count).
   * @throws std::logic_error when empty, std::invalid_argument for q outside (0,1]
   */
  double percentile(double q) const
  {
    if (samples_.empty())
      throw std::logic_error("StageSamples: no samples");
    if (!(q > 0.0 && q <= 1.0))
      throw std::invalid_argument("StageSamples: percentile must be in (0,1]");
    std::vector<double> s = samples_;
    const std::size_t rank = static_cast<std::size_t>(std::ceil(q * s.size()));  // 1-based
    std::nth_element(s.begin(), s.begin() + (rank - 1), s.end());
    return s[rank - 1];
  }
  double median() const { return percentile(0.5); }
  double p95() const { return percentile(0.95); }

private:
  std::vector<double> samples_;
};

/** @brief Which clock a Stopwatch reads. */
enum class Clock
{
  Wall,      ///< the monotonic wall clock: includes time the thread waited for a core
  ThreadCpu  ///< CPU time of the calling thread: what the work cost on one core, on a shared machine
};

/** @brief Seconds elapsed since construction (or the last lap). */
class Stopwatch
{
public:
  explicit Stopwatch(Clock clock = Clock::Wall) : clock_(clock), start_(now()) {}
  double seconds() const { return now() - start_; }
  /** @brief Returns the seconds elapsed and starts again. */
  double lap()
  {
    const double t = now();
    const double s = t - start_;
    start_ = t;
    return s;
  }

private:
  double now() const
  {
    if (clock_ == Clock::ThreadCpu)
    {
      timespec ts;
      clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
      return ts.tv_sec + 1e-9 * ts.tv_nsec;
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  }
  Clock clock_;
  double start_;
};

}  // namespace bench
}  // namespace action_flow
