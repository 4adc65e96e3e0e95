/**
 * @file lazy_nodelet.h
 * @brief The lazy-subscription pattern shared by the pipeline's stages (as in depth_image_proc):
 *        a stage subscribes to its input only while one of its outputs has a subscriber, so a
 *        pipeline nobody listens to does no work.
 */
#pragma once

#include <nodelet/nodelet.h>
#include <ros/ros.h>

#include <functional>
#include <mutex>
#include <vector>

namespace action_flow
{
/** @brief A nodelet whose input subscription follows the subscriber count of its outputs. */
class LazyNodelet : public nodelet::Nodelet
{
protected:
  /** @brief Advertises @p topic on the public handle with the connect callback that (un)subscribes. */
  template <class M>
  ros::Publisher advertiseLazy(const std::string& topic, int queue, bool latch = false)
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const auto cb = [this](const ros::SingleSubscriberPublisher&) { updateSubscription(); };
    ros::Publisher pub = getNodeHandle().advertise<M>(topic, queue, cb, cb, ros::VoidConstPtr(), latch);
    outputs_.push_back(pub);
    return pub;
  }

  /** @brief Sets how to subscribe to the input; call before the first advertiseLazy. */
  void setSubscribe(std::function<ros::Subscriber()> subscribe) { subscribe_ = std::move(subscribe); }

  /** @brief True while someone listens to any output. */
  bool anyoneListening() const
  {
    for (const auto& p : outputs_)
      if (p.getNumSubscribers() > 0)
        return true;
    return false;
  }

private:
  void updateSubscription()
  {
    std::lock_guard<std::mutex> lock(connect_mutex_);
    const bool wanted = anyoneListening();
    if (wanted && !input_)
    {
      input_ = subscribe_();
      NODELET_DEBUG("a subscriber appeared: subscribing to %s", input_.getTopic().c_str());
    }
    else if (!wanted && input_)
    {
      NODELET_DEBUG("no subscribers left: unsubscribing from %s", input_.getTopic().c_str());
      input_.shutdown();
      input_ = ros::Subscriber();
    }
  }

  std::mutex connect_mutex_;
  std::function<ros::Subscriber()> subscribe_;
  std::vector<ros::Publisher> outputs_;
  ros::Subscriber input_;
};

}  // namespace action_flow
