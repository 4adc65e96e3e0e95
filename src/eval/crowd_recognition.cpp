// Which track shows a person during one of their actions, and its descriptors then (crowd_recognition.h).
#include "crowd_recognition.h"

#include <stdexcept>

namespace action_flow
{
TrackedScene trackScene(const std::vector<TrackingFrame>& frames, const std::vector<double>& stamps, float gate)
{
  if (frames.size() != stamps.size())
    throw std::invalid_argument("trackScene: " + std::to_string(frames.size()) + " frames but " +
                                std::to_string(stamps.size()) + " stamps");
  const std::vector<std::vector<int>> matches = matchTracking(frames, gate);
  TrackedScene out;
  out.stamps = stamps;
  out.track_of.resize(frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (std::size_t i = 0; i < frames[k].truth.size(); ++i)
      if (matches[k][i] >= 0)
        out.track_of[k][frames[k].truth[i].id] = frames[k].predicted[std::size_t(matches[k][i])].id;
  return out;
}

std::uint32_t segmentFrames(const SampleFrames& rows, const TrackedScene& scene, const CrowdSegment& segment,
                            SampleFrames& out)
{
  out = SampleFrames();
  out.descriptors.resize(0, rows.descriptors.cols());
  if (segment.first < 0 || segment.last < segment.first || std::size_t(segment.last) >= scene.stamps.size() ||
      scene.track_of.size() != scene.stamps.size())
    throw std::invalid_argument("segmentFrames: frames " + std::to_string(segment.first) + ".." +
                                std::to_string(segment.last) + " are not within the scene's " +
                                std::to_string(scene.stamps.size()));
  if (rows.descriptors.rows() > 0 && rows.tracks.size() != std::size_t(rows.descriptors.rows()))
    throw std::invalid_argument("segmentFrames: the rows carry no tracks");
  std::map<std::uint32_t, int> frames_of;  // track -> frames it was the person's
  for (int f = segment.first; f <= segment.last; ++f)
  {
    const auto& of = scene.track_of[std::size_t(f)];
    const auto it = of.find(segment.person);
    if (it != of.end())
      ++frames_of[it->second];
  }
  std::uint32_t track = 0;
  int most = 0;
  for (const auto& [id, n] : frames_of)  // ascending ids: the lower wins a tie
    if (n > most)
      track = id, most = n;
  if (track == 0)
    return 0;
  const double from = scene.stamps[std::size_t(segment.first)], to = scene.stamps[std::size_t(segment.last)];
  std::vector<Eigen::Index> kept;
  for (Eigen::Index r = 0; r < rows.descriptors.rows(); ++r)
    if (rows.tracks[std::size_t(r)] == track && rows.stamps[std::size_t(r)] >= from && rows.stamps[std::size_t(r)] <= to)
      kept.push_back(r);
  out.descriptors.resize(Eigen::Index(kept.size()), rows.descriptors.cols());
  for (std::size_t k = 0; k < kept.size(); ++k)
  {
    out.descriptors.row(Eigen::Index(k)) = rows.descriptors.row(kept[k]);
    out.stamps.push_back(rows.stamps[std::size_t(kept[k])]);
  }
  return track;
}

}  // namespace action_flow
