// rosbag::Bag loads its encryption plugin through pluginlib when it is built and opened, and
// unloads it when destroyed; pluginlib's class loader is not safe to use from two threads at once
// ("no factory exists for rosbag::NoEncryptor" when tools open bags in parallel). GuardedBag
// serializes exactly those steps; reading and writing run in parallel as before.
#pragma once

#include <rosbag/bag.h>

#include <memory>
#include <mutex>
#include <string>

namespace action_flow
{
namespace tools
{
inline std::mutex& bagLifecycleMutex()
{
  static std::mutex m;
  return m;
}

class GuardedBag
{
public:
  GuardedBag(const std::string& path, std::uint32_t mode)
  {
    std::lock_guard<std::mutex> lock(bagLifecycleMutex());
    bag_ = std::make_unique<rosbag::Bag>();
    bag_->open(path, mode);
  }
  ~GuardedBag()
  {
    std::lock_guard<std::mutex> lock(bagLifecycleMutex());
    bag_.reset();
  }
  GuardedBag(const GuardedBag&) = delete;
  GuardedBag& operator=(const GuardedBag&) = delete;
  rosbag::Bag& operator*() { return *bag_; }
  rosbag::Bag* operator->() { return bag_.get(); }

private:
  std::unique_ptr<rosbag::Bag> bag_;
};

}  // namespace tools
}  // namespace action_flow
