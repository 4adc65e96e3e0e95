// A hand-built scene for the rostests: a person-like figure of boxes standing on a floor 2.5 m in
// front of a camera 1.2 m above it, waving the right forearm, seen as a Kinect-like organized
// cloud (ray cast per pixel, so the person hides the floor behind it). Each surface point's
// colour is a texture fixed to its box, so the flow's colour matching can follow it.
#pragma once

#include <action_flow/types.h>

#include <Eigen/Geometry>
#include <vector>

namespace action_flow
{
namespace test
{
struct SceneOptions
{
  int width = 320, height = 240;
  float focal = 262.5f;        // Kinect v1 at 320x240
  float camera_height = 1.2f;  // above the floor (camera y points down, so the floor is y = +1.2)
  float distance = 2.5f;       // person's distance along z
  float person_x = 0.0f;       // person's lateral offset
  bool floor = true;
  bool person = true;
};

/** Renders the scene with the forearm at @p angle (rad); y down, z forward (optical frame). */
Cloud renderScene(const SceneOptions& o, float angle);

/** The person's points only (no floor), for publishing person clouds directly. */
Cloud renderPerson(const SceneOptions& o, float angle);

/** The person's height in the scene (top of the head above the floor). */
constexpr float kPersonHeight = 1.75f;

}  // namespace test
}  // namespace action_flow
