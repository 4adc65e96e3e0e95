#include <action_flow/ros/stage_diagnostics.h>

#include <algorithm>
#include <cstdio>

namespace action_flow
{
namespace
{
std::string fixed(double v, int digits)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}
}  // namespace

void StageDiagnostics::start(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& node_name,
                             const std::string& stage, double period)
{
  updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, node_name);
  updater_->setHardwareID("none");
  updater_->add(stage, this, &StageDiagnostics::report);
  since_ = ros::WallTime::now();
  timer_ = nh.createWallTimer(ros::WallDuration(period), [this](const ros::WallTimerEvent&) { updater_->force_update(); });
}

void StageDiagnostics::received()
{
  std::lock_guard<std::mutex> lock(mutex_);
  ++in_;
}

void StageDiagnostics::published(const ros::Time& stamp)
{
  const double latency = std::max(0.0, (ros::Time::now() - stamp).toSec());
  std::lock_guard<std::mutex> lock(mutex_);
  ++out_;
  latency_sum_ += latency;
  latency_max_ = std::max(latency_max_, latency);
}

void StageDiagnostics::set(const std::string& key, const std::string& value)
{
  std::lock_guard<std::mutex> lock(mutex_);
  values_[key] = value;
}

void StageDiagnostics::setProblem(const std::string& problem)
{
  std::lock_guard<std::mutex> lock(mutex_);
  problem_ = problem;
}

// The rates and latencies of the messages since the last report.
void StageDiagnostics::report(diagnostic_updater::DiagnosticStatusWrapper& status)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const ros::WallTime now = ros::WallTime::now();
  const double span = std::max(1e-3, (now - since_).toSec());
  status.add("input rate (Hz)", fixed(in_ / span, 1));
  status.add("output rate (Hz)", fixed(out_ / span, 1));
  status.add("latency mean (ms)", fixed(out_ ? 1e3 * latency_sum_ / out_ : 0.0, 1));
  status.add("latency max (ms)", fixed(1e3 * latency_max_, 1));
  for (const auto& [key, value] : values_)
    status.add(key, value);
  if (!problem_.empty())
    status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, problem_);
  else if (in_ == 0 && out_ == 0)
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "idle");
  else
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "running");
  since_ = now;
  in_ = out_ = 0;
  latency_sum_ = latency_max_ = 0.0;
}

}  // namespace action_flow
