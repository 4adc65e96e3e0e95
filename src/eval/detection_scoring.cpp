#include "detection_scoring.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <tuple>

namespace action_flow
{
double DetectionCounts::precision() const
{
  const long n = true_positives + false_positives;
  return n == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(true_positives) / n;
}

double DetectionCounts::recall() const
{
  const long n = true_positives + misses;
  return n == 0 ? std::numeric_limits<double>::quiet_NaN() : static_cast<double>(true_positives) / n;
}

DetectionCounts& DetectionCounts::operator+=(const DetectionCounts& o)
{
  true_positives += o.true_positives;
  false_positives += o.false_positives;
  misses += o.misses;
  ignored += o.ignored;
  frames += o.frames;
  return *this;
}

FrameScore scoreFrame(const std::vector<Eigen::Vector2f>& detections, const std::vector<TruthPerson>& truth, float gate)
{
  if (!(gate > 0.0f) || !std::isfinite(gate))
    throw std::invalid_argument("scoreFrame: the gate must be positive and finite");
  // Every pair within the gate, nearest first (ties: lower indices first, so the result is deterministic).
  std::vector<std::tuple<float, int, int>> pairs;
  for (std::size_t d = 0; d < detections.size(); ++d)
    for (std::size_t t = 0; t < truth.size(); ++t)
    {
      const float dist = (detections[d] - truth[t].position).norm();
      if (dist < gate)
        pairs.emplace_back(dist, static_cast<int>(d), static_cast<int>(t));
    }
  std::sort(pairs.begin(), pairs.end());
  FrameScore out;
  out.counts.frames = 1;
  out.truth_of_detection.assign(detections.size(), -1);
  std::vector<int> detection_of_truth(truth.size(), -1);
  for (const auto& [dist, d, t] : pairs)
    if (out.truth_of_detection[d] < 0 && detection_of_truth[t] < 0)
    {
      out.truth_of_detection[d] = t;
      detection_of_truth[t] = d;
    }
  for (std::size_t d = 0; d < detections.size(); ++d)
  {
    const int t = out.truth_of_detection[d];
    if (t < 0)
    {
      ++out.counts.false_positives;
      out.false_detections.push_back(static_cast<int>(d));
    }
    else if (truth[t].required)
      ++out.counts.true_positives;
    else
      ++out.counts.ignored;
  }
  for (std::size_t t = 0; t < truth.size(); ++t)
    if (truth[t].required && detection_of_truth[t] < 0)
    {
      ++out.counts.misses;
      out.missed.push_back(static_cast<int>(t));
    }
  return out;
}

std::string binLabel(double value, const std::vector<double>& edges, const char* format)
{
  if (edges.size() < 2 || !std::is_sorted(edges.begin(), edges.end()) ||
      std::adjacent_find(edges.begin(), edges.end()) != edges.end())
    throw std::invalid_argument("binLabel: need at least 2 ascending edges");
  const auto print = [&](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, format, v);
    return std::string(buf);
  };
  if (value < edges.front())
    return "<" + print(edges.front());
  if (value >= edges.back())
    return ">=" + print(edges.back());
  const auto hi = std::upper_bound(edges.begin(), edges.end(), value);
  return print(*(hi - 1)) + ".." + print(*hi);
}

}  // namespace action_flow
