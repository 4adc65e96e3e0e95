// Motion of the synthetic actors: a pose per frame from an action, an actor and a repetition.
#pragma once

#include <action_flow/synth/synth.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/** One performance in the actor's own frame (origin on the floor where it starts, x forward, z up). */
struct Performance
{
  std::vector<Skeleton> joints;               // per frame, root frame
  std::vector<Eigen::Vector3f> forward;       // per frame, body facing in the root frame
  bool uses_chair = false;                    // sit_down / get_up: a chair stands behind the start
  Eigen::Vector3f chair = Eigen::Vector3f::Zero();  // seat centre (x, y) and seat height (z), root frame
  bool walks = false;                         // walk: the root faces along the path, not the camera
  // The action itself, between the idle lead-in and lead-out: frames core_first..core_last (inclusive).
  int core_first = 0, core_last = 0;
};

/** @brief Generates the frames of @p action performed by @p actor at @p fps; rep_seed varies the repetition. */
Performance perform(const Actor& actor, const std::string& action, std::uint64_t rep_seed, double fps);

/** @brief The walk of perform(), @p length metres along +x (the IAS-Lab walk draws 1.6-2.2 m).
 *  @throws std::invalid_argument if length is not positive */
Performance performWalk(const Actor& actor, std::uint64_t rep_seed, double fps, float length);

/** @brief @p frames frames of the plain idle body (breathing, sway), no action; core = all frames. */
Performance performIdle(const Actor& actor, std::uint64_t rep_seed, double fps, int frames);

/** A stream of actions in the world frame (floor origin below the camera, x away from it, z up). */
struct StreamMotion
{
  std::vector<Skeleton> joints;               // per frame, world
  std::vector<Eigen::Vector3f> forward;       // per frame, body facing, world
  std::vector<StreamSegment> segments;        // the cores of the performed actions, in order
  std::vector<Eigen::Vector4f> chairs;        // seat centre (x, y), seat height, facing yaw (world)
};

/**
 * @brief Composes @p actor performing @p actions in a row at @p fps (see docs/synth.md, "Streams"):
 *        idle lead-in and lead-out of 1-2 s, between two actions a transition of 0.4-0.8 s into an
 *        idle period of 0.5-3 s (seated between sit_down and get_up) and another transition into
 *        the next action. Deterministic in @p stream_seed.
 */
StreamMotion composeStream(const Actor& actor, const std::vector<std::string>& actions, std::uint64_t stream_seed,
                           double fps);

/** @brief Appends frames [first, first + count) of a piece placed by @p root; returns the index of its frame 0. */
int appendPlaced(StreamMotion& out, const std::vector<Skeleton>& joints, const std::vector<Eigen::Vector3f>& forward,
                 const Eigen::Isometry3f& root, int first, int count);

/**
 * @brief Appends @p n frames from the last pose of @p out to the pose @p to: the joints relative to
 *        the pelvis and the heading are interpolated, the pelvis moves and the heading turns between them.
 */
void blendInto(StreamMotion& out, const Skeleton& to, const Eigen::Vector3f& to_forward, int n);

/** One MSR Action3D recording in the world frame, where it was recorded, at the camera's rate. */
struct MsrMotion
{
  std::vector<Skeleton> joints;           // per frame, world (x away from the camera, z up, feet on the floor)
  std::vector<Eigen::Vector3f> forward;   // per frame, body facing, world
  float height = 1.75f;                   // the body's height estimated from the skeleton (m)
};

/**
 * @brief Converts @p file (docs/synth.md, "MSR Action3D"): untracked frames interpolated, the
 *        recording camera's pitch removed, x un-mirrored, feet on the floor, the height estimated,
 *        15 fps resampled linearly to @p fps.
 * @throws std::runtime_error if the file has no tracked frame
 */
MsrMotion msrMotion(const MsrSkeletonFile& file, double fps);

/**
 * @brief Composes MSR recordings in a row at @p fps (see docs/synth.md, "MSR streams"): each
 *        re-centred to where the first one starts (the subject stays on the spot), a segment of
 *        ground truth for the whole of each, labelled @p actions; 1-2 s of held first pose before and
 *        of held last pose after (breathing), and between two a held pose then a transition into
 *        the next one's first pose, together 0.5-3 s. Deterministic in @p stream_seed.
 */
StreamMotion composeMsrStream(const std::vector<MsrMotion>& sequences, const std::vector<std::string>& actions,
                              std::uint64_t stream_seed, double fps);

}  // namespace synth
}  // namespace action_flow
