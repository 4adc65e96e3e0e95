/**
 * @file octree_flow_baseline.h
 * @brief The paper's flow step written the way the paper did it (PCL octree K-nearest search), as
 *        the benchmark's baseline. Same method, same parameters, same HSV distance as
 *        action_flow::FlowEstimator; only the search structure and the loop differ, so the
 *        benchmark can compare speed on identical input and check that both find the same flow.
 */
#pragma once

#include <action_flow/flow_estimator.h>
#include <action_flow/types.h>

#include <pcl/octree/octree_search.h>

#include <memory>
#include <vector>

namespace action_flow
{
namespace bench
{
/**
 * @brief Octree-based flow (the paper, section "3D Flow Estimation Pipeline", as published in
 *        Table 2's "octree initialization" and "point clouds matching").
 */
class OctreeFlowBaseline
{
public:
  /** @brief One frame: finite points, HSV-cone colours and its octree (built once per frame). */
  struct Frame
  {
    Cloud::Ptr cloud;
    std::vector<Eigen::Vector3f> colour;
    std::unique_ptr<pcl::octree::OctreePointCloudSearch<PointT>> octree;
    double stamp = 0.0;
  };

  /**
   * @param params the method's parameters (K, reciprocal, thresholds)
   * @param resolution octree leaf size (m)
   * @throws std::invalid_argument if resolution is not positive
   */
  OctreeFlowBaseline(const FlowParams& params, double resolution);

  /** @brief "Octree initialization": keeps the finite points, converts colours, builds the octree. */
  std::unique_ptr<Frame> prepare(const Cloud& cloud, double stamp) const;

  /** @brief For each point of @p from, its match in @p to: nearestKSearch (K), then nearest in HSV. */
  std::vector<int> match(const Frame& from, const Frame& to) const;

  /** @brief "Point clouds matching": target->source and source->target, reciprocal ones kept. */
  std::vector<Correspondence> correspond(const Frame& source, const Frame& target, FlowStats& stats) const;

  /** @brief "Flow vectors computation". */
  FlowVectors velocities(const Frame& source, const Frame& target, const std::vector<Correspondence>& matches) const;

  /** @brief "Outlier removal": speed threshold, then octree radius search for a fast neighbour. */
  FlowVectors rejectOutliers(const Frame& target, const std::vector<Correspondence>& matches,
                             const FlowVectors& flow, FlowStats& stats) const;

private:
  FlowParams params_;
  double resolution_;
};

}  // namespace bench
}  // namespace action_flow
