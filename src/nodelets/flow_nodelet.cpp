// Flow stage: per tracked person, the 3D flow between its consecutive clouds (core FlowTrack).
#include <action_flow/person_pipeline.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>

#include <pluginlib/class_list_macros.hpp>

#include <map>

namespace action_flow
{
/**
 * Subscribes `person_clouds` (PeopleClouds), publishes `flow` (PeopleFlow). Parameters (private):
 * the flow/ part of the recognition parameters, `max_gap` (s, frames further apart restart a track).
 */
class FlowNodelet : public LazyNodelet
{
  struct Track
  {
    std::unique_ptr<FlowTrack> flow;
    double last_seen = 0.0;
  };

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
    pnh.param("max_gap", max_gap_, max_gap_);
    diag_.start(getNodeHandle(), pnh, getName(), "flow");
    setSubscribe([this] { return getNodeHandle().subscribe("person_clouds", 10, &FlowNodelet::onClouds, this); });
    pub_ = advertiseLazy<PeopleFlow>("flow", 10);
  }

  void onClouds(const PeopleClouds::ConstPtr& in)
  {
    diag_.received();
    const double stamp = in->header.stamp.toSec();
    auto out = boost::make_shared<PeopleFlow>();
    out->header = in->header;
    out->lost = in->lost;
    out->source = in;
    out->reset = in->reset;
    if (in->reset || stamp < last_stamp_)
    {
      if (!in->reset)
        NODELET_WARN_THROTTLE(5, "time went backwards (%.3f s after %.3f s): dropping the flow state of %zu tracks",
                              stamp, last_stamp_, tracks_.size());
      tracks_.clear();
      out->reset = true;
    }
    last_stamp_ = stamp;
    for (std::uint32_t id : in->lost)
      tracks_.erase(id);
    // A track the tracker never reported lost (e.g. its output was dropped) must not live forever.
    for (auto it = tracks_.begin(); it != tracks_.end();)
      it = stamp - it->second.last_seen > 10.0 * max_gap_ ? tracks_.erase(it) : std::next(it);

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
      Track& track = tracks_[person.info.id];
      if (!track.flow)
        track.flow = std::make_unique<FlowTrack>(params_, max_gap_);
      track.last_seen = stamp;
      try
      {
        FlowTrack::Step step = track.flow->add(*person.cloud, stamp);
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
        track.flow->reset();
        p.status = PeopleFlow::kReset;
      }
      out->people.push_back(std::move(p));
    }
    pub_.publish(out);
    diag_.published(in->header.stamp);
  }

  FlowParams params_;
  double max_gap_ = 1.0;
  double last_stamp_ = -1.0;
  std::map<std::uint32_t, Track> tracks_;
  ros::Publisher pub_;
  StageDiagnostics diag_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::FlowNodelet, nodelet::Nodelet)
