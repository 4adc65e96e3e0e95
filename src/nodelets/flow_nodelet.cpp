// Flow stage: per tracked person, the 3D flow between its consecutive clouds (core FlowTrack).
#include <action_flow/person_pipeline.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>
#include <action_flow/track_table.h>

#include <pluginlib/class_list_macros.hpp>

#include <memory>

namespace action_flow
{
/**
 * Subscribes `person_clouds` (PeopleClouds), publishes `flow` (PeopleFlow). Parameters (private):
 * the flow/ part of the recognition parameters (flow/max_gap: frames further apart restart a track).
 * Per-track state and its lost, reset and time rules: TrackTable.
 */
class FlowNodelet : public LazyNodelet
{
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    try
    {
      params_ = readRecognitionParams(pnh).flow;
      FlowEstimator check(params_);  // throws on a bad value
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("bad flow parameters (%s): using the defaults", e.what());
      params_ = FlowParams();
    }
    tracks_ = TrackTable<std::unique_ptr<FlowTrack>>(params_.max_gap);
    diag_.start(getNodeHandle(), pnh, getName(), "flow");
    setSubscribe([this] { return getNodeHandle().subscribe("person_clouds", 10, &FlowNodelet::onClouds, this); });
    pub_ = advertiseLazy<PeopleFlow>("flow", 10);
  }

  void onClouds(const PeopleClouds::ConstPtr& in)
  {
    diag_.received();
    auto out = boost::make_shared<PeopleFlow>();
    out->header = in->header;
    out->lost = in->lost;
    out->source = in;
    const auto frame = tracks_.begin(in->header.stamp.toSec(), in->reset, in->lost);
    if (frame.time_went_back && !in->reset)
      NODELET_WARN_THROTTLE(5, "time went backwards (%.3f s after %.3f s): dropping the flow state of %zu tracks",
                            in->header.stamp.toSec(), frame.previous_stamp, frame.ended.size());
    out->reset = frame.cleared;

    for (const auto& person : in->people)
    {
      PeopleFlow::Person p;
      p.info = person.info;
      if (!person.cloud)
      {
        NODELET_WARN_THROTTLE(5, "track %u has no cloud: skipped", person.info.id);
        continue;
      }
      p.cloud = person.cloud;
      FlowTrack& track = *tracks_.at(person.info.id, [&] { return std::make_unique<FlowTrack>(params_); });
      try
      {
        FlowTrack::Step step = track.add(*person.cloud, in->header.stamp.toSec());
        p.status = step.status == FlowTrack::Status::Flow    ? PeopleFlow::kFlow
                   : step.status == FlowTrack::Status::Reset ? PeopleFlow::kReset
                                                             : PeopleFlow::kFirst;
        p.dt = step.result.dt;
        if (p.status == PeopleFlow::kFlow)
          p.flow = boost::make_shared<const FlowVectors>(std::move(step.result.flow));
      }
      catch (const std::exception& e)
      {
        NODELET_ERROR_THROTTLE(5, "flow of track %u failed (%s): restarting the track", person.info.id, e.what());
        track.reset();
        p.status = PeopleFlow::kReset;
      }
      out->people.push_back(std::move(p));
    }
    pub_.publish(out);
    diag_.published(in->header.stamp);
  }

  FlowParams params_;
  TrackTable<std::unique_ptr<FlowTrack>> tracks_{ FlowParams().max_gap };
  ros::Publisher pub_;
  StageDiagnostics diag_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::FlowNodelet, nodelet::Nodelet)
