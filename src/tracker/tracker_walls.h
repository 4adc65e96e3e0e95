/**
 * @file tracker_walls.h
 * @brief Walls among the points above the ground: wide, tall, vertical planes (the people
 *        detector removes them before clustering, so that a person close in front of a wall is not
 *        absorbed into it, and no column of a wall is taken for a person). ROS-free.
 */
#pragma once

#include <action_flow/types.h>

#include <Eigen/Core>

#include <vector>

namespace action_flow
{
/** @brief What makes a wall. Lengths in metres. */
struct WallParams
{
  float inlier_distance = 0.06f;  ///< points this close to a plane support it (the detection voxel)
  float max_angle = 0.25f;        ///< largest angle between the plane and the vertical (rad)
  float min_width = 0.6f;         ///< horizontal extent of its points (2nd to 98th percentile)
  float min_height = 1.2f;        ///< vertical extent of its points (likewise)
  /** Its points reach this high above the ground (98th percentile): higher than (almost) anyone's
   *  head (a row of people side by side, with nothing behind them, is as plane as a wall but not
   *  as tall; a wall seen from 3 m by a camera 1.1 m high pitched down 5 degrees reaches 2.26 m). */
  float min_top = 2.1f;
  /** ... or its plane runs along the image's top edge for at least min_width: the wall goes on above
   *  what the camera sees (a low camera, or one pitched down, sees a wall close behind a person only
   *  up to 1.6-2 m). A row of people has no such edge: their heads are inside the image. */
  /** Its points cover at least this share of width x height (a voxelised surface; a plane strung
   *  through the fronts of scattered furniture is sparse). */
  float min_cover = 0.3f;
  float voxel = 0.06f;            ///< the voxel size of the points (for the cover)
  int max_walls = 3;
};

/**
 * @brief The walls among @p points (voxelised, above the ground plane @p ground, unit normal up): up
 *        to max_walls planes (a, b, c, d), unit normal toward @p camera, found by RANSAC for planes
 *        parallel to up (within max_angle) one after the other, each kept
 *        only if wide, tall, reaching min_top and covered enough and if at most 2 % of the points lie more than
 *        0.15 m behind it (a wall bounds the room; at most max_walls + 2 planes are looked at).
 *        @p image_top: the points along the image's top edge (organized clouds), for walls that go on
 *        above the view (see WallParams::min_top). Deterministic.
 */
std::vector<Eigen::Vector4f> findWalls(const Cloud& points, const Eigen::Vector4f& ground, const Eigen::Vector3f& camera,
                                       const WallParams& params = WallParams(),
                                       const std::vector<Eigen::Vector3f>& image_top = {});

}  // namespace action_flow
