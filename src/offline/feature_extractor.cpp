#include "feature_extractor.h"

#include <action_flow/person_pipeline.h>
#include <action_flow/track_table.h>

#include <cmath>
#include <utility>
#include <memory>
#include <stdexcept>

namespace action_flow
{
namespace
{
// Per track id: one pipeline for all variants (they share the flow's matching), and how many
// frames the track was seen in.
struct ExtractedTrack
{
  std::unique_ptr<PersonPipeline> pipeline;
  int seen = 0;
};

/** Frame descriptors @p rows, with their @p stamps, as one matrix of @p length columns. */
SampleFrames framesOf(const std::vector<Eigen::VectorXf>& rows, std::vector<double> stamps, Eigen::Index length)
{
  SampleFrames f;
  f.stamps = std::move(stamps);
  f.descriptors.resize(static_cast<Eigen::Index>(rows.size()), length);
  for (std::size_t r = 0; r < rows.size(); ++r)
    f.descriptors.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  return f;
}

/** The sample's performer: the longest track; of equal ones the lowest id, the first to end. */
const ExtractedTrack* performer(const std::vector<std::pair<std::uint32_t, ExtractedTrack>>& tracks)
{
  const ExtractedTrack* best = nullptr;
  std::uint32_t best_id = 0;
  for (const auto& [id, t] : tracks)
    if (!best || t.seen > best->seen || (t.seen == best->seen && id < best_id))
      best = &t, best_id = id;
  return best;
}
}  // namespace

std::vector<SampleFrames> extractSample(FrameSource& source, const TrackerParams& tracker_params,
                                        const std::vector<RecognitionParams>& variants, bool all_tracks,
                                        const std::function<void(double, const TrackerResult&)>& observe)
{
  for (const auto& v : variants)
    if (v.flow.max_gap != variants.front().flow.max_gap)
      throw std::invalid_argument("extractSample: the variants' flow/max_gap differ (their tracks end together)");
  if (variants.empty())
    return {};
  PeopleTracker tracker(tracker_params);
  // Tracks end by the nodelets' rules (TrackTable); the ended ones are kept for choosing the
  // sample's person, but for those a reset drops. A person re-identified after their track ended
  // comes back under its id as a new track (TrackerParams::reid_after).
  TrackTable<ExtractedTrack> live(variants.front().flow.max_gap);
  std::vector<std::pair<std::uint32_t, ExtractedTrack>> tracks;
  // all_tracks: every descriptor as it comes, per variant (a reset does not take them back).
  std::vector<std::vector<Eigen::VectorXf>> rows(variants.size());
  std::vector<std::vector<double>> row_stamps(variants.size());
  std::vector<std::vector<std::uint32_t>> row_tracks(variants.size());
  Cloud cloud;
  double stamp = 0.0;
  while (source.next(cloud, stamp))
  {
    const TrackerResult result = tracker.update(cloud, stamp);
    if (observe)
      observe(stamp, result);
    auto frame = live.begin(stamp, result.reset, result.lost);
    if (frame.cleared)
      tracks.clear();
    else
      for (auto& ended : frame.ended)
        tracks.push_back(std::move(ended));
    for (const auto& person : result.people)
    {
      ExtractedTrack& t =
          live.at(person.id, [&] { return ExtractedTrack{ std::make_unique<PersonPipeline>(variants), 0 }; });
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
  const ExtractedTrack* best = all_tracks ? nullptr : performer(tracks);
  for (std::size_t v = 0; v < variants.size(); ++v)
    if (all_tracks)
    {
      out[v] = framesOf(rows[v], row_stamps[v], frameDescriptorLength(variants[v]));
      out[v].tracks = row_tracks[v];
    }
    else if (best)
      out[v] = framesOf(best->pipeline->descriptors(v), best->pipeline->stamps(v), frameDescriptorLength(variants[v]));
  return out;
}

}  // namespace action_flow
