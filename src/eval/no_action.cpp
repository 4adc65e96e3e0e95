#include "no_action.h"

#include <algorithm>
#include <map>
#include <optional>
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
/** Frames of the track's @p rows of @p stream in [from, to], if they are enough. */
std::optional<SampleFrames> windowFrames(const SampleFrames& stream, const std::vector<Eigen::Index>& rows, double from,
                                         double to, double min_coverage, int min_frames)
{
  std::vector<Eigen::Index> in;
  for (Eigen::Index r : rows)
  {
    const double s = stream.stamps[static_cast<std::size_t>(r)];
    if (s >= from && s <= to)
      in.push_back(r);
  }
  if (in.empty() || static_cast<int>(in.size()) < min_frames ||
      stream.stamps[static_cast<std::size_t>(in.back())] - stream.stamps[static_cast<std::size_t>(in.front())] <
          min_coverage * (to - from))
    return std::nullopt;
  SampleFrames f;
  f.descriptors.resize(static_cast<Eigen::Index>(in.size()), stream.descriptors.cols());
  for (std::size_t i = 0; i < in.size(); ++i)
  {
    f.descriptors.row(static_cast<Eigen::Index>(i)) = stream.descriptors.row(in[i]);
    f.stamps.push_back(stream.stamps[static_cast<std::size_t>(in[i])]);
  }
  return f;
}

/**
 * Per track of @p stream, windows of @p length every @p step seconds that @p label_of(from, to)
 * gives a label (std::nullopt: none) and that have enough frames.
 */
template <class LabelOf>
void cutWindows(const SampleFrames& stream, double length, double step, double min_coverage, int min_frames,
                LabelOf label_of, std::vector<ActionWindow>& found)
{
  if (stream.stamps.size() != static_cast<std::size_t>(stream.descriptors.rows()))
    throw std::invalid_argument("stream windows: a stamp per descriptor row required");
  std::map<std::uint32_t, std::vector<Eigen::Index>> rows_of_track;
  for (Eigen::Index r = 0; r < stream.descriptors.rows(); ++r)
    rows_of_track[stream.tracks.empty() ? 0u : stream.tracks[static_cast<std::size_t>(r)]].push_back(r);
  for (const auto& kv : rows_of_track)
  {
    const std::vector<Eigen::Index>& rows = kv.second;
    const double first = stream.stamps[static_cast<std::size_t>(rows.front())];
    const double last = stream.stamps[static_cast<std::size_t>(rows.back())];
    for (double from = first; from + length <= last + 1e-9; from += step)
    {
      const std::optional<std::string> label = label_of(from, from + length);
      if (!label)
        continue;
      if (auto f = windowFrames(stream, rows, from, from + length, min_coverage, min_frames))
        found.push_back({ *label, std::move(*f) });
    }
  }
}

/** At most @p keep of @p found, evenly spread over them. */
std::vector<ActionWindow> spread(std::vector<ActionWindow>& found, int keep_at_most)
{
  const std::size_t keep = std::min(found.size(), static_cast<std::size_t>(keep_at_most));
  std::vector<ActionWindow> out;
  for (std::size_t k = 0; k < keep; ++k)
    out.push_back(std::move(found[(2 * k + 1) * found.size() / (2 * keep)]));
  return out;
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
  std::vector<ActionWindow> found;
  for (double length : w.lengths)
    cutWindows(stream, length, w.step, w.min_coverage, w.min_frames,
               [&](double from, double to) -> std::optional<std::string> {
                 if (actionTime(truth, from, to) > w.max_action_share * length)
                   return std::nullopt;
                 return std::string(kNoActionLabel);
               },
               found);
  std::vector<SampleFrames> out;
  for (ActionWindow& a : spread(found, w.per_stream))
    out.push_back(std::move(a.frames));
  return out;
}

std::vector<ActionWindow> actionWindows(const std::vector<TruthSegment>& truth, const SampleFrames& stream,
                                        const ActionWindows& w)
{
  if (!(w.length > 0.0) || w.step <= 0.0 || w.min_action_cover < 0.0 || w.min_action_cover > 1.0 ||
      w.max_other_share < 0.0 || w.max_other_share > 1.0 || w.min_coverage < 0.0 || w.min_coverage > 1.0 ||
      w.per_stream < 0)
    throw std::invalid_argument("actionWindows: length, step > 0, shares in [0,1] and per_stream >= 0 required");
  std::vector<ActionWindow> found;
  cutWindows(stream, w.length, w.step, w.min_coverage, w.min_frames,
             [&](double from, double to) -> std::optional<std::string> {
               const TruthSegment* held = nullptr;
               double other = 0.0;
               for (const TruthSegment& t : truth)
               {
                 const double in = std::max(0.0, std::min(to, t.end) - std::max(from, t.start));
                 if (!held && t.end > t.start && in >= w.min_action_cover * (t.end - t.start))
                   held = &t;
                 else
                   other += in;
               }
               if (!held || other > w.max_other_share * (to - from))
                 return std::nullopt;
               return held->label;
             },
             found);
  return spread(found, w.per_stream);
}

std::size_t noActionCount(const std::vector<LabelledSample>& labelled, std::size_t first)
{
  std::size_t n = 0;
  for (std::size_t i = first; i < labelled.size(); ++i)
    n += labelled[i].action == kNoActionLabel;
  return n;
}

}  // namespace action_flow
