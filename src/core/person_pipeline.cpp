#include <action_flow/person_pipeline.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace action_flow
{
FlowTrack::FlowTrack(const FlowParams& params, bool keep_unfiltered)
  : estimator_(params), max_gap_(params.max_gap), keep_unfiltered_(keep_unfiltered)
{
}

FlowTrack::Step FlowTrack::add(const Cloud& cloud, double stamp)
{
  auto frame = std::make_unique<FlowFrame>(cloud, stamp);
  Step step;
  if (previous_)
  {
    const double dt = stamp - previous_->stamp();
    if (std::isfinite(dt) && dt > 0.0 && dt <= max_gap_)
    {
      step.status = Status::Flow;
      step.result = keep_unfiltered_ ? estimator_.estimate(*previous_, *frame, step.unfiltered)
                                     : estimator_.estimate(*previous_, *frame);
    }
    else
    {
      step.status = Status::Reset;
    }
  }
  previous_ = std::move(frame);
  return step;
}

PersonPipeline::PersonPipeline(const RecognitionParams& params) : PersonPipeline(std::vector<RecognitionParams>{ params })
{
}

PersonPipeline::PersonPipeline(const std::vector<RecognitionParams>& variants)
{
  if (variants.empty())
    throw std::invalid_argument("PersonPipeline: no parameter set given");
  // Flow parameters up to step 4, per shared flow track.
  std::vector<FlowParams> shared;
  std::vector<bool> needs_unfiltered;
  const auto same_matching = [](FlowParams a, FlowParams b) {
    a.reject_outliers = b.reject_outliers = true;
    const auto ea = paramEntries(a), eb = paramEntries(b);
    return std::equal(ea.begin(), ea.end(), eb.begin(), [](const ParamEntry& x, const ParamEntry& y) {
      return x.value == y.value;
    });
  };
  for (const auto& v : variants)
  {
    std::size_t f = 0;
    while (f < shared.size() && !same_matching(shared[f], v.flow))
      ++f;
    if (f == shared.size())
    {
      shared.push_back(v.flow);
      needs_unfiltered.push_back(false);
    }
    // The track rejects outliers when any of its variants wants that; the others read the flow
    // before step 4.
    if (v.flow.reject_outliers && !shared[f].reject_outliers)
    {
      shared[f].reject_outliers = true;
      needs_unfiltered[f] = true;
    }
    else if (!v.flow.reject_outliers && shared[f].reject_outliers)
      needs_unfiltered[f] = true;
    variants_.push_back({ f, !v.flow.reject_outliers, v, SequenceDescriptor(v.frames), {}, {} });
  }
  for (std::size_t f = 0; f < shared.size(); ++f)
    flows_.emplace_back(shared[f], needs_unfiltered[f]);
}

void PersonPipeline::add(const Cloud& cloud, double stamp, const PersonFrame& where)
{
  std::vector<FlowTrack::Step> steps;
  steps.reserve(flows_.size());
  for (auto& f : flows_)
    steps.push_back(f.add(cloud, stamp));
  for (auto& v : variants_)
  {
    const FlowTrack::Step& step = steps[v.flow];
    if (step.status == FlowTrack::Status::Reset)
    {
      v.descriptors.clear();
      v.stamps.clear();
    }
    if (step.status == FlowTrack::Status::Flow)
    {
      // A track that does not reject outliers has its flow in result (unfiltered stays empty).
      const bool from_unfiltered = v.unfiltered && flows_[v.flow].estimator().params().reject_outliers;
      v.descriptors.push_back(frameDescriptor(v.params, cloud, from_unfiltered ? step.unfiltered : step.result.flow, where));
      v.stamps.push_back(stamp);
    }
  }
}

Eigen::VectorXf PersonPipeline::sequence(const Pca& pca, std::size_t v) const
{
  const Variant& variant = variants_.at(v);
  return variant.sequence.compute(variant.descriptors, variant.stamps, pca);
}

void PersonPipeline::clear()
{
  for (auto& v : variants_)
  {
    v.descriptors.clear();
    v.stamps.clear();
  }
}

}  // namespace action_flow
