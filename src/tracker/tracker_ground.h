/**
 * @file tracker_ground.h
 * @brief Finds the ground plane in a voxelised cloud by itself and keeps it up to date
 *        (part of the people tracker, ROS-free).
 */
#pragma once

#include <action_flow/types.h>

#include <Eigen/Core>

namespace action_flow
{
/** @brief @p d laid on the ground plane of normal @p up (unit, or zero: @p d as it is). */
inline Eigen::Vector3f onGround(const Eigen::Vector3f& d, const Eigen::Vector3f& up)
{
  return d - d.dot(up) * up;
}

/** @brief Settings of the ground search. Lengths in metres, angles in radians. */
struct GroundParams
{
  /** Points this close to a candidate plane support it. */
  float inlier_distance = 0.06f;
  /** Least number of supporting points (voxels) of a ground plane. */
  int min_inliers = 140;
  /** Largest angle between the plane's normal and the up hint. */
  float max_angle = 0.8f;
  /** The camera must be this high above the ground, at least / at most. */
  float min_camera_height = 0.2f, max_camera_height = 3.5f;
  /** How many horizontal planes the full search looks at (floor, table tops, ...). */
  int max_candidates = 4;
  /** A refined plane may move this much per update before a full search is done instead. */
  float max_step_angle = 0.15f, max_step_offset = 0.15f;
  /** A plane's points per occupied cell of a 2 inlier_distance grid on it (a voxelised surface
   *  gives about 4; scattered points about 1). */
  float min_density = 2.0f;
  /** When no floor plane is visible, assume one below the lowest points (see GroundEstimator). */
  bool assume_below_points = true;
  /** ... if at least this many points lie within 2 inlier_distance of that level ... */
  int min_support = 30;
  /** ... spread at least this far apart horizontally. */
  float min_support_spread = 1.0f;
  /** A floor found by the search replaces a measured or given ground it disagrees with (by more
   *  than max_step_angle / max_step_offset) only with this many times min_inliers: a small patch
   *  (a table top, a step) does not overturn a good ground, a wide floor does. */
  float strong_support = 2.0f;
};

/**
 * @brief The ground plane of a (possibly moving) camera.
 *
 * Full search: RANSAC for planes roughly perpendicular to the up hint (pcl's
 * SACMODEL_PERPENDICULAR_PLANE), repeated on the remaining points; the ground is the LOWEST such
 * plane with enough support (a table top or a bed has floor below it, the floor has nothing).
 * Update: least-squares refinement on the points near the current plane (as pcl::people does
 * every frame), falling back to a full search when too few points support it or it jumps.
 * Assumed ground: dark or shiny floors often give no depth at all (the tue_hsr_person
 * recordings). Then, if assume_below_points, the ground is taken perpendicular to the last
 * normal (else the up hint) through the lowest points, provided enough of them lie at that level
 * (feet, chair legs, furniture bases) over a wide enough area; assumed() tells this case.
 * While the ground is assumed, the plane search is retried every 10th update only.
 *
 * Which ground wins (source()): a ground that was measured, or given (setPrior(): from the
 * camera's mounting or tf), is KEPT while the floor is hidden (it is never replaced by an assumed
 * one), refined by the measured floor where that agrees, and replaced by a searched floor that
 * disagrees only if that floor is strongly supported (strong_support). An assumed ground is
 * replaced by any floor the search finds (a wrong assumption is corrected once floor is seen).
 */
class GroundEstimator
{
public:
  /** @brief Where the current plane comes from. */
  enum class Source
  {
    None,      ///< no plane yet
    Measured,  ///< a floor seen in the cloud (searched or refined)
    Assumed,   ///< below the lowest points (no floor seen, no prior)
    Prior      ///< given by setPrior() and not (yet) refined by a measured floor
  };

  /** @throws std::invalid_argument on non-positive or inconsistent settings. */
  explicit GroundEstimator(const GroundParams& params = GroundParams());

  /**
   * @brief Looks for the ground in @p cloud (finite points, typically at the detection voxel size).
   * @param camera the camera's position (the ground lies below it)
   * @param up_hint roughly up (need not be unit)
   * @return true when this cloud gave (or confirmed) a ground plane; false leaves the previous one, if any
   */
  bool update(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up_hint);

  /** @brief Whether a ground plane has been found. */
  bool valid() const { return valid_; }
  /** @brief The plane (a,b,c,d): unit normal pointing up (toward the camera), a x + b y + c z + d = 0. */
  const Eigen::Vector4f& plane() const { return plane_; }
  /** @brief Whether the current plane is assumed below the lowest points (no floor was visible). */
  bool assumed() const { return source() == Source::Assumed; }
  /** @brief Where the plane comes from. */
  Source source() const { return valid_ ? source_ : Source::None; }
  /** @brief Forgets the plane (back to the prior, if one is set). */
  void reset();
  /**
   * @brief Gives the ground as known from outside (the camera's mounting, tf): used at once if no
   *        floor has been measured, kept while the floor is hidden, and after reset().
   * @param plane (a,b,c,d); normalised and oriented toward @p camera here
   * @return false (nothing changed) for a degenerate plane
   */
  bool setPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera = Eigen::Vector3f::Zero());
  /** @brief Whether a prior is set. */
  bool hasPrior() const { return has_prior_; }
  /** @brief How many full searches were run (the rest were refinements). */
  int searches() const { return searches_; }

  const GroundParams& params() const { return params_; }

private:
  bool search(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up, Eigen::Vector4f& found,
              std::size_t& support);
  bool close(const Eigen::Vector4f& a, const Eigen::Vector4f& b, const Eigen::Vector3f& camera) const;
  bool refine(const Cloud& cloud, const Eigen::Vector3f& camera);
  bool dense(const Cloud& cloud, const pcl::Indices& inliers, const Eigen::Vector4f& plane) const;
  bool assumeBelow(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up);

  GroundParams params_;
  Eigen::Vector4f plane_ = Eigen::Vector4f::Zero();
  bool valid_ = false;
  Source source_ = Source::None;
  Eigen::Vector4f prior_ = Eigen::Vector4f::Zero();
  bool has_prior_ = false;
  int searches_ = 0;
  int since_search_ = 0;  // updates since the plane was last confirmed (refined or searched)
};

/** @brief Signed height of @p p above @p plane (unit normal). */
inline float heightAbove(const Eigen::Vector4f& plane, const Eigen::Vector3f& p)
{
  return plane.head<3>().dot(p) + plane[3];
}

}  // namespace action_flow
