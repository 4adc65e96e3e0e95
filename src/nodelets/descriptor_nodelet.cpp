// Descriptor stage: each person's flow summed (or averaged) in a grid around them (core GridDescriptor).
#include <action_flow/grid_descriptor.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>

#include <pluginlib/class_list_macros.hpp>

namespace action_flow
{
/**
 * Subscribes `flow` (PeopleFlow), publishes `descriptors` (FrameDescriptors). Parameters (private):
 * the grid/ part and `descriptor` (sumflow|meanflow) of the recognition parameters. Stateless.
 */
class DescriptorNodelet : public LazyNodelet
{
  void onInit() override
  {
    try
    {
      grid_ = std::make_unique<GridDescriptor>(readRecognitionParams(getPrivateNodeHandle()).grid);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("bad grid parameters (%s): using the defaults", e.what());
      grid_ = std::make_unique<GridDescriptor>();
    }
    setSubscribe([this] { return getNodeHandle().subscribe("flow", 10, &DescriptorNodelet::onFlow, this); });
    pub_ = advertiseLazy<FrameDescriptors>("descriptors", 10);
  }

  void onFlow(const PeopleFlow::ConstPtr& in)
  {
    auto out = boost::make_shared<FrameDescriptors>();
    out->header = in->header;
    out->lost = in->lost;
    out->reset = in->reset;
    out->source = in;
    for (const auto& person : in->people)
    {
      FrameDescriptor d;
      d.track_id = person.info.id;
      d.status = person.status;
      const Eigen::Vector3f head = person.info.head();
      d.head.x = head.x();
      d.head.y = head.y();
      d.head.z = head.z();
      if (person.status == PeopleFlow::kFlow && person.flow)
      {
        const Eigen::VectorXf v = grid_->compute(*person.flow, person.info.frame);
        d.values.assign(v.data(), v.data() + v.size());
      }
      out->descriptors.push_back(std::move(d));
    }
    pub_.publish(out);
  }

  std::unique_ptr<GridDescriptor> grid_;
  ros::Publisher pub_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::DescriptorNodelet, nodelet::Nodelet)
