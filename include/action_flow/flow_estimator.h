/**
 * @file flow_estimator.h
 * @brief 3D flow between two consecutive colored person clouds (the paper's section
 *        "3D Flow Estimation Pipeline", steps 1-4).
 */
#pragma once

#include <action_flow/param_table.h>
#include <action_flow/types.h>

#include <cstddef>
#include <memory>
#include <vector>

namespace action_flow
{
/** @brief Parameters of the flow estimation; defaults are the paper's. */
struct FlowParams
{
  /** K nearest neighbours in XYZ among which the nearest in HSV is chosen (paper: 50 at 0.02 m voxels). */
  int k = 50;
  /** Keep only reciprocal correspondences (target->source and source->target agree). */
  bool reciprocal = true;
  /** Apply the speed and isolation rules of step 4. */
  bool reject_outliers = true;
  /** Points slower than this (m/s) are dropped. */
  float min_speed = 0.3f;
  /** A moving point is kept only if some neighbour moves faster than this (m/s). */
  float isolation_speed = 0.75f;
  /**
   * Radius (m) within which a moving point looks for a fast neighbour. The paper only says
   * "near". 0.05 m is 2.5 voxels at the paper's 0.02 m voxel size: a moving limb always has
   * several voxel neighbours inside it (a forearm is about 4 voxels across), while a noise
   * point on a static surface, whose neighbours are all still, finds none.
   */
  float neighbour_radius = 0.05f;
  /** Frames of one person further apart than this (s) are not matched: the track's flow restarts
   *  (a dropped stretch of frames, a paused bag). The nodelets and the offline tools share it. */
  double max_gap = 1.0;

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    v("flow/k", p.k, "nearest neighbours in XYZ among which the nearest in HSV is taken", Shapes::Frames);
    v("flow/reciprocal", p.reciprocal, "keep only reciprocal correspondences", Shapes::Frames);
    v("flow/reject_outliers", p.reject_outliers, "apply the speed and isolation rules (step 4)", Shapes::Frames);
    v("flow/min_speed", p.min_speed, "m/s: slower points are dropped", Shapes::Frames);
    v("flow/isolation_speed", p.isolation_speed, "m/s: a moving point needs a neighbour faster than this", Shapes::Frames);
    v("flow/neighbour_radius", p.neighbour_radius, "m: where that neighbour is looked for", Shapes::Frames);
    v("flow/max_gap", p.max_gap, "s: frames further apart restart the track's flow", Shapes::Frames);
  }
};

/** @brief A colour in HSV, each channel in [0,1]; hue wraps around. */
struct Hsv
{
  float h, s, v;
};

/** @brief Converts 8-bit RGB to HSV with all channels in [0,1]. */
Hsv rgbToHsv(std::uint8_t r, std::uint8_t g, std::uint8_t b);

/**
 * @brief Distance in the HSV cone: Euclidean between (c cos 2πh, c sin 2πh, v) with chroma c = s v.
 *
 * Hue is an angle, so its difference wraps around (hue 0.95 is as near 0.05 as 0.45 is to 0.55),
 * and it counts in proportion to chroma: the hue of a grey or dark pixel is noise (two colour
 * levels can swing it by 180 degrees) and must not decide a match.
 */
float hsvDistance(const Hsv& a, const Hsv& b);

/** @brief The cone coordinates of hsvDistance; matching compares these directly. */
Eigen::Vector3f hsvCone(const Hsv& c);

/**
 * @brief One person cloud prepared for matching: its finite points, their HSV colours and a
 *        neighbour index over XYZ (a uniform grid; exact K-nearest and radius search). Built once per frame; the same frame serves as the target of one
 *        pair and as the source of the next.
 */
class FlowFrame
{
public:
  /** @brief Keeps the finite points of @p cloud (NaN/inf dropped) and builds the neighbour index. */
  FlowFrame(const Cloud& cloud, double stamp);
  ~FlowFrame();
  FlowFrame(const FlowFrame&) = delete;
  FlowFrame& operator=(const FlowFrame&) = delete;

  double stamp() const { return stamp_; }
  std::size_t size() const { return xyz_.size(); }
  bool empty() const { return xyz_.empty(); }
  const Eigen::Vector3f& point(std::size_t i) const { return xyz_[i]; }
  /** @brief Colour of point i in HSV-cone coordinates (see hsvCone). */
  const Eigen::Vector3f& colour(std::size_t i) const { return colour_[i]; }

  /**
   * @brief Indices of the (at most) @p k nearest points to @p q, nearest first; among equal
   *        distances the lower index first (so the set is a function of the data alone).
   */
  void nearest(const Eigen::Vector3f& q, int k, std::vector<std::size_t>& indices,
               std::vector<float>& sq_dists) const;
  /** @brief Indices of all points closer than @p radius to @p q, in no particular order. */
  void within(const Eigen::Vector3f& q, float radius, std::vector<std::size_t>& indices) const;

  struct Index;  // the neighbour index (a uniform grid), defined in src/core/neighbour_grid.h
  /** @brief The neighbour index, for FlowEstimator; its type is opaque outside the core. */
  const Index& index() const { return *index_; }

private:
  double stamp_;
  std::vector<Eigen::Vector3f> xyz_;
  std::vector<Eigen::Vector3f> colour_;
  std::unique_ptr<Index> index_;
};

/** @brief What each rule of the estimation kept or removed, for logging and tests. */
struct FlowStats
{
  std::size_t source_points = 0;        ///< finite points of the source frame
  std::size_t target_points = 0;        ///< finite points of the target frame
  std::size_t matched = 0;              ///< target points with a correspondence (step 1)
  std::size_t removed_reciprocal = 0;   ///< dropped because the match was not reciprocal (step 2)
  std::size_t removed_slow = 0;         ///< dropped as slower than min_speed (step 4)
  std::size_t removed_isolated = 0;     ///< dropped as moving with no fast neighbour (step 4)
  std::size_t kept = 0;                 ///< flow vectors returned
};

/** @brief A correspondence: target point index and the source point index it matches. */
struct Correspondence
{
  std::size_t target;
  std::size_t source;
};

/** @brief The result of one estimation: flow vectors at target points, and statistics. */
struct FlowResult
{
  FlowVectors flow;
  FlowStats stats;
  double dt = 0.0;  ///< target stamp minus source stamp (s)
};

/**
 * @brief Estimates 3D flow between two person clouds (the paper, steps 1-4).
 *
 * Stateless and thread-safe; per-track state lives in FlowTrack. The four steps are public so
 * that the benchmark can time them one by one; estimate() runs them in order.
 */
class FlowEstimator
{
public:
  /** @throws std::invalid_argument if a parameter is out of range. */
  explicit FlowEstimator(const FlowParams& params = FlowParams());

  const FlowParams& params() const { return params_; }

  /**
   * @brief Runs steps 1-4 between @p source (earlier) and @p target (later).
   * @throws std::invalid_argument if target.stamp() - source.stamp() is not a positive finite number.
   */
  FlowResult estimate(const FlowFrame& source, const FlowFrame& target) const;

  /**
   * @brief As estimate(), and also gives step 3's flow before step 4 in @p unfiltered (when step 4
   *        is off, the same as the result's flow): one matching serves the paper's variants with
   *        and without outlier rejection.
   */
  FlowResult estimate(const FlowFrame& source, const FlowFrame& target, FlowVectors& unfiltered) const;

  /** @brief Step 1: for each point of @p from, the index of its match in @p to (K-NN in XYZ, then nearest in HSV). */
  std::vector<std::size_t> match(const FlowFrame& from, const FlowFrame& to) const;

  /**
   * @brief Steps 1-2: target->source matches, kept only where source->target agrees (if reciprocal).
   * Fills stats.matched and stats.removed_reciprocal.
   */
  std::vector<Correspondence> correspond(const FlowFrame& source, const FlowFrame& target,
                                         FlowStats& stats) const;

  /** @brief Step 3: velocity = displacement / dt for each correspondence; velocities per target point. */
  static FlowVectors velocities(const FlowFrame& source, const FlowFrame& target,
                                const std::vector<Correspondence>& matches, double dt);

  /** @brief Step 4: drops slow points, then moving points with no fast neighbour. */
  FlowVectors rejectOutliers(const FlowFrame& target, const std::vector<Correspondence>& matches,
                             const FlowVectors& flow, FlowStats& stats) const;

private:
  FlowParams params_;
};

}  // namespace action_flow
