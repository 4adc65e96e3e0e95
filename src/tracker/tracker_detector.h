/**
 * @file tracker_detector.h
 * @brief One frame of people detection on a colored cloud (the people tracker's first half,
 *        ROS-free): voxel grid, ground plane, ground removal, Euclidean clusters, pcl::people's
 *        head-based sub-clustering, size limits, optional HOG confirmation.
 */
#pragma once

#include <action_flow/people_tracker.h>
#include "tracker_ground.h"

#include <boost/make_shared.hpp>
#include <boost/shared_ptr.hpp>
#include <Eigen/Core>

#include <limits>
#include <memory>
#include <vector>

namespace action_flow
{
/** @brief One person found in one frame. */
struct PersonDetection
{
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();  ///< mean of the person's detection voxels (input frame)
  float height = 0.0f;                                 ///< top of the head above the ground
  float width = 0.0f;                                  ///< largest horizontal extent
  int voxels = 0;                                      ///< detection voxels in the person
  double hog_confidence = std::numeric_limits<double>::quiet_NaN();  ///< SVM score; NaN when not evaluated
  pcl::Indices indices;                                ///< the person's points in the input cloud (above the ground)
  /** Passed only the tracked_* limits (or failed HOG): may continue a confirmed track, never start one. */
  bool weak = false;
  /** Share of the head's image rows free on both sides (see TrackerParams::min_free_fraction); NaN if not computed. */
  float free_fraction = std::numeric_limits<float>::quiet_NaN();
  /** Organized clouds: the image row of the detection's highest pixel (0 = the top edge); -1 if not computed. */
  int top_row = -1;
  /** Width of the top 0.15 m over that of the 0.3-0.6 m below the top (see TrackerParams::max_head_ratio);
   *  NaN if not computed. */
  float head_ratio = std::numeric_limits<float>::quiet_NaN();
};

/**
 * @brief Makes @p part one body with @p into: its points join, the centroid is the voxel-weighted
 *        mean, the height the higher; @p apart (their distance on the ground) widens the width.
 */
void joinDetection(PersonDetection& into, const PersonDetection& part, float apart);

/** @brief What one frame gave. */
struct DetectionResult
{
  std::vector<PersonDetection> people;
  Eigen::Vector4f ground = Eigen::Vector4f::Zero();  ///< unit normal up
  bool ground_valid = false;
  bool ground_assumed = false;  ///< see GroundEstimator::assumed()
  bool hog_applied = false;
};

/**
 * @brief Finds the people standing on the ground in one cloud. Keeps the ground estimate from
 *        frame to frame (GroundEstimator); otherwise stateless.
 */
class PeopleDetector
{
public:
  /** @throws std::invalid_argument on bad parameters or an unreadable classifier file. */
  explicit PeopleDetector(const TrackerParams& params);
  ~PeopleDetector();

  /** @brief Detects people; a cloud whose width*height does not match its size gives nothing. */
  DetectionResult detect(const Cloud& cloud, const Eigen::Vector3f& camera_origin);

  /**
   * @brief The points of @p person (indices into @p cloud) at person_voxel_size, as a fresh cloud
   *        carrying @p cloud's header.
   */
  boost::shared_ptr<Cloud> personCloud(const Cloud& cloud, const PersonDetection& person) const;

  /** @brief Forgets the ground estimate (back to the prior, if any). */
  void reset();

  /** @brief See PeopleTracker::setGroundPrior. */
  bool setGroundPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera);

private:
  struct Impl;
  TrackerParams params_;
  std::unique_ptr<Impl> impl_;
};

/** @brief The ground of a camera @p height above the floor pitched down by @p pitch, in its optical frame. */
Eigen::Vector4f groundFromCamera(float height, float pitch);

/** @brief Checks tracker parameters; @throws std::invalid_argument naming the first bad one. */
void validateTrackerParams(const TrackerParams& params);

/**
 * @brief Fits the 3x4 projection of an organized cloud (point in the cloud's frame -> pixel
 *        column, row) by direct linear transformation on a subsample of its finite points.
 * @return false for unorganized clouds, too few points, or a poor fit (median error above 2 px)
 */
bool fitProjection(const Cloud& organized, Eigen::Matrix<float, 3, 4>& projection);

}  // namespace action_flow
