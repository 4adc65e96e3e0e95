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
    /** Step 3's flow before step 4; filled only by a track made with keep_unfiltered. */
    FlowVectors unfiltered;
  };

  /** Frames further apart than params.max_gap are not matched: the track restarts. */
  explicit FlowTrack(const FlowParams& params = FlowParams(), bool keep_unfiltered = false);

  /** @brief Adds the next cloud of this person; non-finite points are ignored. */
  Step add(const Cloud& cloud, double stamp);
  /** @brief Forgets the previous frame. */
  void reset() { previous_.reset(); }
  const FlowEstimator& estimator() const { return estimator_; }

private:
  FlowEstimator estimator_;
  double max_gap_;
  bool keep_unfiltered_;
  std::unique_ptr<FlowFrame> previous_;
};

/**
 * @brief One person from clouds to frame descriptors to a sequence descriptor, as the offline
 *        tools use it (the nodelets run the same classes, one stage each), for one parameter set
 *        or several at once. Sets whose flow differs at most in step 4 (outlier rejection on or
 *        off) share one matching, the costly part: the paper's SUMFLOW, MEANFLOW and SUMFLOW
 *        without rejection cost one flow estimation per frame, not three.
 */
class PersonPipeline
{
public:
  explicit PersonPipeline(const RecognitionParams& params = RecognitionParams());
  /** @throws std::invalid_argument if @p variants is empty */
  explicit PersonPipeline(const std::vector<RecognitionParams>& variants);

  /**
   * @brief Adds the person's next cloud (voxelised to the tracker's person_voxel_size) at @p stamp, standing at
   *        @p where. When the flow could be estimated, each variant's frame descriptor is appended
   *        to its descriptors(); a time reset clears the collected descriptors first.
   */
  void add(const Cloud& cloud, double stamp, const PersonFrame& where);

  std::size_t variants() const { return variants_.size(); }
  /** @brief Frame descriptors collected so far for variant @p v, and their stamps. */
  const std::vector<Eigen::VectorXf>& descriptors(std::size_t v = 0) const { return variants_.at(v).descriptors; }
  const std::vector<double>& stamps(std::size_t v = 0) const { return variants_.at(v).stamps; }

  /** @brief The sequence descriptor of what was collected; @throws std::invalid_argument if nothing was. */
  Eigen::VectorXf sequence(const Pca& pca = Pca(), std::size_t v = 0) const;

  void clear();

private:
  struct Variant
  {
    std::size_t flow;   ///< index into flows_
    bool unfiltered;    ///< uses the flow before step 4
    RecognitionParams params;
    SequenceDescriptor sequence;
    std::vector<Eigen::VectorXf> descriptors;
    std::vector<double> stamps;
  };
  std::vector<FlowTrack> flows_;
  std::vector<Variant> variants_;
};

}  // namespace action_flow
