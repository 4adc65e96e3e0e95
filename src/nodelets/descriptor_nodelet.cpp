// Descriptor stage: each person's frame descriptor in a grid around them: posture and flow
// (core PostureFlowDescriptor, the default) or the paper's SUMFLOW / MEANFLOW (core GridDescriptor).
#include <action_flow/action_model.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>

#include <pluginlib/class_list_macros.hpp>

namespace action_flow
{
/**
 * Subscribes `flow` (PeopleFlow), publishes `descriptors` (FrameDescriptors). Parameters (private):
 * `recognizer` (posture_flow|paper), the grid/ part and, for the paper's, `descriptor`
 * (sumflow|meanflow) of the recognition parameters. Stateless.
 */
class DescriptorNodelet : public LazyNodelet
{
  void onInit() override
  {
    try
    {
      params_ = readRecognitionParams(getPrivateNodeHandle());
      frameDescriptorLength(params_);  // checks the grid
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("bad descriptor parameters (%s): using the defaults", e.what());
      params_ = defaultRecognitionParams();
    }
    diag_.start(getNodeHandle(), getPrivateNodeHandle(), getName(), "descriptor");
    setSubscribe([this] { return getNodeHandle().subscribe("flow", 10, &DescriptorNodelet::onFlow, this); });
    pub_ = advertiseLazy<FrameDescriptors>("descriptors", 10);
  }

  void onFlow(const PeopleFlow::ConstPtr& in)
  {
    diag_.received();
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
      const bool needs_cloud = params_.recognizer == Recognizer::PostureFlow;
      if (person.status == PeopleFlow::kFlow && person.flow && needs_cloud && (!person.cloud || person.cloud->empty()))
        NODELET_WARN_THROTTLE(5, "track %u: flow without the person's cloud, which posture_flow needs: no descriptor",
                              person.info.id);
      else if (person.status == PeopleFlow::kFlow && person.flow)
      {
        const Eigen::VectorXf v =
            frameDescriptor(params_, person.cloud ? *person.cloud : Cloud(), *person.flow, person.info.frame);
        d.values.assign(v.data(), v.data() + v.size());
      }
      out->descriptors.push_back(std::move(d));
    }
    pub_.publish(out);
    diag_.published(in->header.stamp);
  }

  RecognitionParams params_;
  StageDiagnostics diag_;
  ros::Publisher pub_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::DescriptorNodelet, nodelet::Nodelet)
