/**
 * @file stage_diagnostics.h
 * @brief What each stage reports on /diagnostics (diagnostic_updater): its input and output
 *        rates, the latency of its outputs (now minus the input frame's stamp), values of its own
 *        (tracked people, the model) and what is wrong, if anything. Published once a second, also
 *        while the stage is idle (nobody listening).
 */
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace action_flow
{
class StageDiagnostics
{
public:
  /**
   * @brief Starts reporting as "<node name>: <stage>" (diagnostic_updater's name), every @p period s.
   * @param nh, pnh the nodelet's handles; @p node_name its name (nodelet::Nodelet::getName())
   */
  void start(ros::NodeHandle& nh, ros::NodeHandle& pnh, const std::string& node_name, const std::string& stage,
             double period = 1.0);
  /** @brief One input message arrived. */
  void received();
  /** @brief One output was published for the input frame stamped @p stamp. */
  void published(const ros::Time& stamp);
  /** @brief A value of the stage's own, shown until set again ("tracked people" = "2"). */
  void set(const std::string& key, const std::string& value);
  /** @brief What is wrong (level ERROR with this message); "" = nothing. */
  void setProblem(const std::string& problem);

private:
  void report(diagnostic_updater::DiagnosticStatusWrapper& status);

  std::mutex mutex_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer timer_;
  ros::WallTime since_;
  std::size_t in_ = 0, out_ = 0;
  double latency_sum_ = 0.0, latency_max_ = 0.0;
  std::map<std::string, std::string> values_;
  std::string problem_;
};

}  // namespace action_flow
