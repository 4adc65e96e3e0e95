/**
 * @file person_pipeline.h
 * @brief Per-person state: the flow of one track over time (FlowTrack) and the whole
 *        per-person chain from person cloud to frame descriptors (PersonPipeline). The nodelets
 *        and the offline tools both go through these, so each step has one implementation.
 */
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/flow_estimator.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/sequence_descriptor.h>

#include <memory>
#include <vector>

namespace action_flow
{
/**
 * @brief The flow of one tracked person: keeps the previous frame (and its neighbour grid, built once)
 *        and estimates the flow to each new one.
 */
class FlowTrack
{
public:
  enum class Status
  {
    First,  ///< no previous frame: nothing estimated yet
    Flow,   ///< flow estimated from the previous frame
    Reset   ///< time went backwards, stood still or jumped beyond max_gap: restarted from this frame
  };
  struct Step
  {
    Status status = Status::First;
    FlowResult result;
  };

  /**
   * @param max_gap frames further apart than this (s) are not matched: the track restarts
   *        (a dropped stretch of frames, a paused bag)
   */
  explicit FlowTrack(const FlowParams& params = FlowParams(), double max_gap = 1.0);

  /** @brief Adds the next cloud of this person; non-finite points are ignored. */
  Step add(const Cloud& cloud, double stamp);
  /** @brief Forgets the previous frame. */
  void reset() { previous_.reset(); }
  const FlowEstimator& estimator() const { return estimator_; }

private:
  FlowEstimator estimator_;
  double max_gap_;
  std::unique_ptr<FlowFrame> previous_;
};

/**
 * @brief One person from clouds to frame descriptors to a sequence descriptor, as the offline
 *        tools use it (the nodelets run the same classes, one stage each).
 */
class PersonPipeline
{
public:
  explicit PersonPipeline(const RecognitionParams& params = RecognitionParams());

  /**
   * @brief Adds the person's next cloud (voxelised to params.voxel_size) at @p stamp, standing at @p where.
   * @return the flow step; when it produced flow, its frame descriptor is appended to descriptors()
   *         (a time reset clears the collected descriptors first)
   */
  FlowTrack::Step add(const Cloud& cloud, double stamp, const PersonFrame& where);

  /** @brief Frame descriptors collected so far and their stamps. */
  const std::vector<Eigen::VectorXf>& descriptors() const { return descriptors_; }
  const std::vector<double>& stamps() const { return stamps_; }

  /** @brief The sequence descriptor of what was collected; @throws std::invalid_argument if nothing was. */
  Eigen::VectorXf sequence(const Pca& pca = Pca()) const;

  void clear();

private:
  RecognitionParams params_;
  FlowTrack track_;
  GridDescriptor grid_;
  SequenceDescriptor sequence_;
  std::vector<Eigen::VectorXf> descriptors_;
  std::vector<double> stamps_;
};

}  // namespace action_flow
