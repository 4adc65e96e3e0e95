// Motion of the synthetic actors: a pose per frame from an action, an actor and a repetition.
#pragma once

#include <action_flow/synth/synth.h>

#include <Eigen/Core>

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
};

/** @brief Generates the frames of @p action performed by @p actor at @p fps; rep_seed varies the repetition. */
Performance perform(const Actor& actor, const std::string& action, std::uint64_t rep_seed, double fps);

}  // namespace synth
}  // namespace action_flow
