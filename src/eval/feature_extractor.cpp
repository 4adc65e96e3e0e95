#include <action_flow/feature_extractor.h>

#include <action_flow/person_pipeline.h>

#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>

namespace action_flow
{
std::vector<SampleFrames> extractSample(FrameSource& source, const TrackerParams& tracker_params,
                                        const std::vector<RecognitionParams>& variants)
{
  for (const auto& v : variants)
    if (std::fabs(v.voxel_size - tracker_params.person_voxel_size) > 1e-6f)
      throw std::invalid_argument("extractSample: the flow's voxel size differs from the tracker's person clouds");
  if (variants.empty())
    return {};
  PeopleTracker tracker(tracker_params);
  // Per track id: one pipeline for all variants (they share the flow's matching), and how many
  // frames the track was seen in.
  struct Track
  {
    std::unique_ptr<PersonPipeline> pipeline;
    int seen = 0;
  };
  std::map<std::uint32_t, Track> tracks;
  Cloud cloud;
  double stamp = 0.0;
  while (source.next(cloud, stamp))
  {
    const TrackerResult result = tracker.update(cloud, stamp);
    if (result.reset)
      tracks.clear();
    for (const auto& person : result.people)
    {
      Track& t = tracks[person.id];
      if (!t.pipeline)
        t.pipeline = std::make_unique<PersonPipeline>(variants);
      ++t.seen;
      t.pipeline->add(*person.cloud, stamp, person.frame);
    }
  }

  std::vector<SampleFrames> out(variants.size());
  const Track* best = nullptr;
  for (const auto& kv : tracks)
    if (!best || kv.second.seen > best->seen)
      best = &kv.second;
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
