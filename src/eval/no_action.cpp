#include "no_action.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace action_flow
{
namespace
{
double actionTime(const std::vector<TruthSegment>& truth, double from, double to)
{
  double sum = 0.0;
  for (const TruthSegment& t : truth)
    sum += std::max(0.0, std::min(to, t.end) - std::max(from, t.start));
  return sum;
}
}  // namespace

std::vector<SampleFrames> noActionWindows(const std::vector<TruthSegment>& truth, const SampleFrames& stream,
                                          const NoActionWindows& w)
{
  if (w.step <= 0.0 || w.max_action_share < 0.0 || w.max_action_share > 1.0 || w.min_coverage < 0.0 ||
      w.min_coverage > 1.0 || w.per_stream < 0)
    throw std::invalid_argument("noActionWindows: step > 0, shares in [0,1] and per_stream >= 0 required");
  for (double l : w.lengths)
    if (!(l > 0.0))
      throw std::invalid_argument("noActionWindows: window lengths must be > 0");
  if (stream.stamps.size() != static_cast<std::size_t>(stream.descriptors.rows()))
    throw std::invalid_argument("noActionWindows: a stamp per descriptor row required");
  std::map<std::uint32_t, std::vector<Eigen::Index>> rows_of_track;
  for (Eigen::Index r = 0; r < stream.descriptors.rows(); ++r)
    rows_of_track[stream.tracks.empty() ? 0u : stream.tracks[static_cast<std::size_t>(r)]].push_back(r);

  std::vector<SampleFrames> found;
  for (double length : w.lengths)
    for (const auto& kv : rows_of_track)
    {
      const std::vector<Eigen::Index>& rows = kv.second;
      const double first = stream.stamps[static_cast<std::size_t>(rows.front())];
      const double last = stream.stamps[static_cast<std::size_t>(rows.back())];
      for (double from = first; from + length <= last + 1e-9; from += w.step)
      {
        const double to = from + length;
        if (actionTime(truth, from, to) > w.max_action_share * length)
          continue;
        std::vector<Eigen::Index> in;
        for (Eigen::Index r : rows)
        {
          const double s = stream.stamps[static_cast<std::size_t>(r)];
          if (s >= from && s <= to)
            in.push_back(r);
        }
        if (static_cast<int>(in.size()) < w.min_frames ||
            stream.stamps[static_cast<std::size_t>(in.back())] - stream.stamps[static_cast<std::size_t>(in.front())] <
                w.min_coverage * length)
          continue;
        SampleFrames f;
        f.descriptors.resize(static_cast<Eigen::Index>(in.size()), stream.descriptors.cols());
        for (std::size_t i = 0; i < in.size(); ++i)
        {
          f.descriptors.row(static_cast<Eigen::Index>(i)) = stream.descriptors.row(in[i]);
          f.stamps.push_back(stream.stamps[static_cast<std::size_t>(in[i])]);
        }
        found.push_back(std::move(f));
      }
    }
  const std::size_t keep = std::min(found.size(), static_cast<std::size_t>(w.per_stream));
  std::vector<SampleFrames> out;
  for (std::size_t k = 0; k < keep; ++k)  // evenly spread over what was found
    out.push_back(std::move(found[(2 * k + 1) * found.size() / (2 * keep)]));
  return out;
}

}  // namespace action_flow
