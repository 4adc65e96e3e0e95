// Test aid, loaded into the pipeline's manager: for every inter-stage topic, checks that the
// object a stage built its output from (its `source`) is the very object the previous stage
// published, as this probe, an in-process subscriber, received it. A copy or a serialization
// anywhere between two stages makes the pointers differ.
#include <action_flow/ros/input_checks.h>
#include <action_flow/ros/stage_types.h>

#include <nodelet/nodelet.h>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include <deque>
#include <sstream>

namespace action_flow
{
/** Publishes `~report` (std_msgs/String, latched): "link same other; ..." per link, after every check. */
class ZeroCopyProbe : public nodelet::Nodelet
{
  // Keeping the pointers alive (not just their addresses) means no address can be reused by a
  // later allocation and match by accident.
  template <class T>
  struct Seen
  {
    std::deque<boost::shared_ptr<const T>> recent;
    void add(const boost::shared_ptr<const T>& p)
    {
      recent.push_back(p);
      if (recent.size() > 100)
        recent.pop_front();
    }
    bool has(const void* p) const
    {
      for (const auto& r : recent)
        if (r.get() == p)
          return true;
      return false;
    }
  };
  struct Link
  {
    int same = 0, other = 0;
  };

  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    report_ = getPrivateNodeHandle().advertise<std_msgs::String>("report", 1, true);
    subs_.push_back(nh.subscribe<InputCloud>("cloud", 100, [this](const InputCloud::ConstPtr& m) { clouds_.add(m->cloud); }));
    subs_.push_back(nh.subscribe<PeopleClouds>("person_clouds", 100, [this](const PeopleClouds::ConstPtr& m) {
      // Without an in-process cloud publisher (person clouds published directly) there is no link to check.
      if (!clouds_.recent.empty())
        check(cloud_link_, clouds_.has(m->source.get()));
      people_.add(m);
    }));
    subs_.push_back(nh.subscribe<PeopleFlow>("flow", 100, [this](const PeopleFlow::ConstPtr& m) {
      check(flow_link_, people_.has(m->source.get()));
      flow_.add(m);
    }));
    subs_.push_back(nh.subscribe<FrameDescriptors>("descriptors", 100, [this](const FrameDescriptors::ConstPtr& m) {
      check(descriptor_link_, flow_.has(m->source.get()));
      descriptors_.add(m);
    }));
    subs_.push_back(nh.subscribe<ActionStates>("states", 100, [this](const ActionStates::ConstPtr& m) {
      check(classifier_link_, descriptors_.has(m->source.get()));
    }));
  }

  void check(Link& link, bool same)
  {
    ++(same ? link.same : link.other);
    std_msgs::String r;
    std::ostringstream s;
    s << "cloud>person_clouds " << cloud_link_.same << " " << cloud_link_.other << "; person_clouds>flow "
      << flow_link_.same << " " << flow_link_.other << "; flow>descriptors " << descriptor_link_.same << " "
      << descriptor_link_.other << "; descriptors>states " << classifier_link_.same << " " << classifier_link_.other;
    r.data = s.str();
    report_.publish(r);
  }

  Seen<Cloud> clouds_;
  Seen<PeopleClouds> people_;
  Seen<PeopleFlow> flow_;
  Seen<FrameDescriptors> descriptors_;
  Link cloud_link_, flow_link_, descriptor_link_, classifier_link_;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher report_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::ZeroCopyProbe, nodelet::Nodelet)
