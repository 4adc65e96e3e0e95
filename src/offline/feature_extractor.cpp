#include "feature_extractor.h"

#include <action_flow/person_pipeline.h>
#include <action_flow/track_table.h>

#include <cmath>
#include <utility>
#include <memory>
#include <stdexcept>

namespace action_flow
{
std::vector<SampleFrames> extractSample(FrameSource& source, const TrackerParams& tracker_params,
                                        const std::vector<RecognitionParams>& variants, bool all_tracks)
{
  for (const auto& v : variants)
    if (v.flow.max_gap != variants.front().flow.max_gap)
      throw std::invalid_argument("extractSample: the variants' flow/max_gap differ (their tracks end together)");
  if (variants.empty())
    return {};
  PeopleTracker tracker(tracker_params);
  // Per track id: one pipeline for all variants (they share the flow's matching), and how many
  // frames the track was seen in. Tracks end by the nodelets' rules (TrackTable); the ended ones
  // are kept for choosing the sample's person, but for those a reset drops. A person re-identified
  // after their track ended comes back under its id as a new track (TrackerParams::reid_after).
  struct Track
  {
    std::unique_ptr<PersonPipeline> pipeline;
    int seen = 0;
  };
  TrackTable<Track> live(variants.front().flow.max_gap);
  std::vector<std::pair<std::uint32_t, Track>> tracks;
  // all_tracks: every descriptor as it comes, per variant (a reset does not take them back).
  std::vector<std::vector<Eigen::VectorXf>> rows(variants.size());
  std::vector<std::vector<double>> row_stamps(variants.size());
  std::vector<std::vector<std::uint32_t>> row_tracks(variants.size());
  Cloud cloud;
  double stamp = 0.0;
  while (source.next(cloud, stamp))
  {
    const TrackerResult result = tracker.update(cloud, stamp);
    auto frame = live.begin(stamp, result.reset, result.lost);
    if (frame.cleared)
      tracks.clear();
    else
      for (auto& ended : frame.ended)
        tracks.push_back(std::move(ended));
    for (const auto& person : result.people)
    {
      Track& t = live.at(person.id, [&] { return Track{ std::make_unique<PersonPipeline>(variants), 0 }; });
      ++t.seen;
      t.pipeline->add(*person.cloud, stamp, person.frame);
      for (std::size_t v = 0; all_tracks && v < variants.size(); ++v)
        if (!t.pipeline->stamps(v).empty() && t.pipeline->stamps(v).back() == stamp)  // a descriptor for this frame
        {
          rows[v].push_back(t.pipeline->descriptors(v).back());
          row_stamps[v].push_back(stamp);
          row_tracks[v].push_back(person.id);
        }
    }
  }

  for (auto& ended : live.endAll())
    tracks.push_back(std::move(ended));

  std::vector<SampleFrames> out(variants.size());
  if (all_tracks)
  {
    for (std::size_t v = 0; v < variants.size(); ++v)
    {
      out[v].stamps = row_stamps[v];
      out[v].tracks = row_tracks[v];
      out[v].descriptors.resize(static_cast<Eigen::Index>(rows[v].size()), frameDescriptorLength(variants[v]));
      for (std::size_t r = 0; r < rows[v].size(); ++r)
        out[v].descriptors.row(static_cast<Eigen::Index>(r)) = rows[v][r].transpose();
    }
    return out;
  }

  const Track* best = nullptr;  // the longest; of equal ones the lowest id, the first to end
  std::uint32_t best_id = 0;
  for (const auto& [id, t] : tracks)
    if (!best || t.seen > best->seen || (t.seen == best->seen && id < best_id))
      best = &t, best_id = id;
  if (!best)
    return out;
  for (std::size_t v = 0; v < variants.size(); ++v)
  {
    const PersonPipeline& p = *best->pipeline;
    out[v].stamps = p.stamps(v);
    out[v].descriptors.resize(static_cast<Eigen::Index>(p.descriptors(v).size()), frameDescriptorLength(variants[v]));
    for (std::size_t r = 0; r < p.descriptors(v).size(); ++r)
      out[v].descriptors.row(static_cast<Eigen::Index>(r)) = p.descriptors(v)[r].transpose();
  }
  return out;
}

}  // namespace action_flow
