/**
 * @file moving_person.h
 * @brief A self-contained virtual Kinect view of a person waving an arm, for the benchmark.
 *
 * The benchmark needs person clouds with the structure of real ones: only the surface the sensor
 * sees (one side of each limb, with self-occlusion), depth noise growing with distance, a texture
 * that moves with the body (the matching uses colour), and a limb moving at a realistic speed over
 * a still body. The project's full virtual Kinect lives in include/action_flow/synth when that part
 * is merged; this generator keeps the benchmark working without it and is small enough to audit.
 *
 * The body is made of capsules (a head, torso, two legs, two two-segment arms); each surface is
 * sampled densely in its own (axial, angular) coordinates, coloured from those coordinates (so the
 * texture moves with the limb), projected through a 640x480 pinhole camera (f = 525) and z-buffered.
 */
#pragma once

#include <action_flow/types.h>

#include <cstdint>
#include <vector>

namespace action_flow
{
namespace bench
{
/** @brief What to render; defaults: a 1.75 m person 2.5 m in front of a Kinect v1, waving at 1.2 Hz. */
struct MovingPersonParams
{
  float distance = 2.5f;       ///< from the camera to the body axis (m)
  float height = 1.75f;        ///< the person's height (m)
  float camera_height = 1.1f;  ///< optical centre above the floor (m)
  float wave_hz = 1.2f;        ///< arm wave frequency
  float fps = 30.0f;
  float depth_noise = 1.425e-3f;  ///< depth standard deviation = depth_noise * z^2 (Kinect v1); 0 = none
  int colour_noise = 3;        ///< uniform colour noise, +- levels
  std::uint32_t seed = 1;      ///< texture and noise
};

/**
 * @brief Renders frame @p i of the waving person as an organized 640x480 cloud (camera optical
 *        frame: x right, y down, z forward; NaN where nothing is seen) with a floor and a back wall,
 *        and the mask of the pixels showing the person.
 */
class MovingPerson
{
public:
  explicit MovingPerson(const MovingPersonParams& params = MovingPersonParams());

  /** @brief Time of frame i (s). */
  double stamp(int i) const { return i / static_cast<double>(params_.fps); }

  /**
   * @param with_room also render the floor and the back wall (full sensor frame); otherwise only
   *        the person's pixels have points
   * @param mask if given, resized to 640*480: 1 where the person is seen, else 0
   */
  void render(int i, Cloud& organized, std::vector<std::uint8_t>* mask = nullptr, bool with_room = true) const;

  /** @brief The person's points of frame i (the mask applied), voxelised to @p voxel (m) as the tracker does. */
  Cloud personCloud(int i, float voxel) const;

  const MovingPersonParams& params() const { return params_; }

private:
  MovingPersonParams params_;
};

/** @brief Voxel-grid filter (PCL's VoxelGrid: one centroid per occupied voxel, colours averaged). */
Cloud voxelise(const Cloud& in, float voxel);

}  // namespace bench
}  // namespace action_flow
