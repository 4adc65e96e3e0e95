/**
 * @file clutter.h
 * @brief Cluttered rooms for the virtual Kinect (dataset "clutter"): a synthetic actor standing close
 *        to a wall, beside or behind chairs, tables, shelves and doors, or partly out of the image,
 *        and rooms with furniture and nobody; cameras 0.5-1.8 m high, pitched from 10 degrees up to
 *        20 degrees down. For measuring people detection (evaluate --protocol detection). ROS-free.
 *
 * The scenes are rendered by SampleRenderer like the other datasets (SampleSpec::dataset "clutter");
 * clutterLayout() is the scene itself (camera, room, labelled furniture, the actor's motion), a pure
 * function of the spec, so an evaluation can ask what stands where.
 */
#pragma once

#include <action_flow/synth/scene.h>
#include <action_flow/synth/synth.h>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/**
 * @brief The clutter scene types, in order: "wall" (a wall 0.2-1 m behind or beside the person),
 *        "chair", "table", "shelf", "door" (the object beside the person or between the camera and
 *        them), "border" (the person partly out of the image: a side or the legs), "furniture"
 *        (furniture only, nobody).
 */
const std::vector<std::string>& clutterKinds();

/**
 * @brief The clutter set: @p per_kind scenes of each kind, ordered kind then number. A scene's spec:
 *        dataset "clutter", scene = the kind, repetition = its number, person = the actor ("p01"..
 *        "p12" in turn; "none" for furniture), action = what the actor performs (pick_up in about a
 *        third of the scenes, else one of the IAS-Lab actions done on the spot; "none" for furniture).
 * @throws std::invalid_argument if per_kind is not in 1..999
 */
std::vector<SampleSpec> clutterSamples(int per_kind = 10, std::uint64_t seed = 1);

/** @brief A piece of furniture (or the walls' door) and the boxes it is made of (also in the room). */
struct ClutterObject
{
  std::string kind;  ///< "chair", "table", "shelf", "door", "cabinet"
  std::vector<Box> boxes;
};

/** @brief One clutter scene: what the camera sees and where everything stands (world frame, scene.h). */
struct ClutterLayout
{
  std::string kind;             ///< clutterKinds() entry
  CameraModel camera;           ///< with the scene's height_above_floor and tilt
  Room room;                    ///< walls, floor and every object's boxes
  std::vector<ClutterObject> objects;
  bool person = false;          ///< an actor is there (every kind but "furniture")
  Actor actor;                  ///< valid if person
  std::vector<Skeleton> joints; ///< per frame, world (empty without a person)
  std::vector<Eigen::Vector3f> forward;  ///< per frame, body facing, world
  int frames = 0;               ///< frames of the scene
};

/**
 * @brief The scene of @p spec (dataset "clutter") seen by @p camera (its intrinsics and noise; the
 *        height and tilt are drawn per scene). Deterministic in the spec.
 * @throws std::invalid_argument on a spec that is not a clutter scene (unknown kind, action or person)
 */
ClutterLayout clutterLayout(const SampleSpec& spec, const CameraModel& camera = CameraModel());

/**
 * @brief What the world point @p p lies on: "person" (within 0.25 m of the actor's skeleton in
 *        @p frame), an object's kind (inside one of its boxes grown by @p tolerance), "wall",
 *        "floor", or "other".
 */
std::string objectAt(const ClutterLayout& layout, int frame, const Eigen::Vector3f& p, float tolerance = 0.05f);

/** @brief How much of a body the camera's image holds. */
struct JointsInView
{
  int inside = 0;            ///< joints (of kJointCount) projecting inside the image by the margin
  bool head_inside = false;  ///< the head joint and the top of the head (0.12 m above it) are inside
};

/** @brief The joints of @p world (world frame) inside @p camera's image, @p margin pixels in from its edges. */
JointsInView jointsInView(const CameraModel& camera, const Skeleton& world, float margin = 4.0f);

/** @brief Horizontal distance (m) from the world point @p p to the nearest wall of the room (+inf without walls). */
float distanceToWall(const Room& room, const Eigen::Vector3f& p);

}  // namespace synth
}  // namespace action_flow
