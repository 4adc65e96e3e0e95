#include <action_flow/person_pipeline.h>

#include <cmath>

namespace action_flow
{
FlowTrack::FlowTrack(const FlowParams& params, double max_gap) : estimator_(params), max_gap_(max_gap)
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
      step.result = estimator_.estimate(*previous_, *frame);
    }
    else
    {
      step.status = Status::Reset;
    }
  }
  previous_ = std::move(frame);
  return step;
}

PersonPipeline::PersonPipeline(const RecognitionParams& params)
  : params_(params), track_(params.flow), grid_(params.grid), sequence_(params.frames)
{
}

FlowTrack::Step PersonPipeline::add(const Cloud& cloud, double stamp, const PersonFrame& where)
{
  FlowTrack::Step step = track_.add(cloud, stamp);
  if (step.status == FlowTrack::Status::Reset)
    clear();
  if (step.status == FlowTrack::Status::Flow)
  {
    descriptors_.push_back(grid_.compute(step.result.flow, where));
    stamps_.push_back(stamp);
  }
  return step;
}

Eigen::VectorXf PersonPipeline::sequence(const Pca& pca) const
{
  return sequence_.compute(descriptors_, stamps_, pca);
}

void PersonPipeline::clear()
{
  descriptors_.clear();
  stamps_.clear();
}

}  // namespace action_flow
