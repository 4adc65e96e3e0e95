// Small helpers for the rostest nodes: collect messages from a topic, wait for a condition.
#pragma once

#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace action_flow
{
namespace test
{
/** Waits (wall time) until @p done holds or @p seconds pass; callbacks run on an AsyncSpinner. */
inline bool waitFor(const std::function<bool()>& done, double seconds)
{
  const auto until = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::WallTime::now() < until && ros::ok())
  {
    if (done())
      return true;
    ros::WallDuration(0.02).sleep();
  }
  return done();
}

/** Subscribes to a topic and keeps every message. */
template <class M>
class Collector
{
public:
  Collector(ros::NodeHandle& nh, const std::string& topic, int queue = 100)
  {
    sub_ = nh.subscribe<M>(topic, queue, boost::function<void(const boost::shared_ptr<const M>&)>(
                                             [this](const boost::shared_ptr<const M>& m) {
                                               std::lock_guard<std::mutex> lock(mutex_);
                                               messages_.push_back(m);
                                             }));
  }
  std::vector<boost::shared_ptr<const M>> messages() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_;
  }
  std::size_t size() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages_.size();
  }
  void clear()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    messages_.clear();
  }
  bool waitForCount(std::size_t n, double seconds)
  {
    return waitFor([&] { return size() >= n; }, seconds);
  }
  void shutdown() { sub_.shutdown(); }

private:
  mutable std::mutex mutex_;
  std::vector<boost::shared_ptr<const M>> messages_;
  ros::Subscriber sub_;
};

/** Nodes subscribed to @p topic (resolved name) according to the master. */
inline std::set<std::string> subscribersOf(const std::string& topic)
{
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  std::set<std::string> nodes;
  if (!ros::master::execute("getSystemState", args, result, payload, false))
    return nodes;
  XmlRpc::XmlRpcValue& subs = payload[1];
  for (int i = 0; i < subs.size(); ++i)
    if (static_cast<std::string>(subs[i][0]) == topic)
      for (int j = 0; j < subs[i][1].size(); ++j)
        nodes.insert(static_cast<std::string>(subs[i][1][j]));
  return nodes;
}

}  // namespace test
}  // namespace action_flow
