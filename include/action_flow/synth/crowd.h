/**
 * @file crowd.h
 * @brief Scenes of several people at once (dataset "crowd"): 2-5 synthetic actors of the IAS set,
 *        each performing their own actions, entering, leaving, walking across the view and
 *        occluding one another, facing any way at 1-5 m; with the ground truth a multi-person
 *        tracker is measured against (person id per pixel, each person's position and actions).
 *        ROS-free. See docs/synth.md, "Several people".
 */
#pragma once

#include <action_flow/synth/synth.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/**
 * @brief @p scenes scenes ("crowd" samples) of @p people people each lasting @p seconds, numbered
 *        1..scenes (SampleSpec::repetition); person = the actors' ids joined by "+", action "crowd".
 * @throws std::invalid_argument if people is not in 2..5, scenes not in 1..999 or seconds not in 2..3600
 */
std::vector<SampleSpec> crowdSamples(int people, int scenes, double seconds = 60.0, std::uint64_t seed = 1);

/** @brief The actor ids of a scene: person k (0-based) of scene s is p(1 + ((s - 1) * people + k) mod 99). */
std::vector<std::string> crowdActors(int people, int scene);

/** @brief The camera of crowd scenes: the IAS camera, with depth returned up to 6 m (people stand at up to 5 m). */
CameraModel crowdCamera();

/** @brief One person of a crowd scene. */
struct CrowdPerson
{
  std::string actor;                    ///< "p04"
  std::uint8_t mask_id = 1;             ///< their id in FrameImages::mask (1..people)
  int first_frame = 0, last_frame = 0;  ///< in the scene (inclusive); outside they are not there at all
  bool enters = false, leaves = false;  ///< walks in from outside the view / out of it
  std::vector<StreamSegment> segments;  ///< their actions (scene frames, inclusive, ordered)
};

/**
 * @brief What the camera shows of one person in one frame (the evaluation's truth).
 *
 * A person counts (must be tracked) when their head is seen (the top of the head at least 2 rows
 * inside the image, as the tracker requires, and their mask id within 3 pixels of the head joint's
 * image point, which lies inside the image and the depth range) and at least
 * kCrowdMinVisibleArea square metres of them return depth (visible pixels scaled by depth^2/f^2):
 * a head over a wall of other people is not enough, nor a body whose head is out of the image.
 */
struct CrowdTruth
{
  std::uint8_t mask_id = 0;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  ///< world (floor below the camera, x away, z up): mean of the 15 joints
  float yaw = 0.0f;             ///< facing in the world (rad, atan2 of the forward vector)
  int visible_pixels = 0;       ///< mask pixels of this person with depth
  float visible_area = 0.0f;    ///< those pixels' area at the body's depth (m^2)
  bool head_visible = false;
  bool counted = false;
};

/** @brief The least visible area (m^2) of a counted person (about a quarter of a frontal adult). */
constexpr float kCrowdMinVisibleArea = 0.12f;

/**
 * @brief Renders a crowd scene: composes every person's motion, the camera pose and the room at
 *        construction (a few hundred milliseconds), then any frame on demand. const methods are
 *        thread-safe; output depends only on the spec.
 */
class CrowdRenderer
{
public:
  /** @throws std::invalid_argument on a spec that is not a valid crowd scene (dataset, people,
   *          scene number, length) */
  explicit CrowdRenderer(const SampleSpec& spec, const CameraModel& camera = crowdCamera());
  ~CrowdRenderer();

  const SampleSpec& spec() const;
  int frames() const;
  /** @brief Stamp of frame @p i in seconds (the same clock as SampleRenderer::stamp). */
  double stamp(int i) const;
  const std::vector<CrowdPerson>& people() const;
  /** @brief Whether person @p k (index into people()) is in the scene at frame @p i. */
  bool present(std::size_t k, int i) const;
  /** @brief Person @p k's joints at frame @p i, world frame. @throws std::out_of_range if not present */
  const Skeleton& worldSkeleton(std::size_t k, int i) const;
  /** @brief The same in the camera's optical frame. */
  Skeleton skeleton(std::size_t k, int i) const;
  /** @brief The bodies present at frame @p i, for SceneRenderer (mask id = CrowdPerson::mask_id). */
  std::vector<PosedBody> bodies(int i) const;

  /**
   * @brief Frame @p i as images; FrameImages::mask holds each pixel's person (mask id, 0 = none).
   *        With @p only a mask id, that person alone is rendered (the same scene without the others:
   *        what recognition would see of them alone).
   * @throws std::out_of_range outside the frames, std::invalid_argument if @p only is nobody's id
   */
  void renderImages(int i, FrameImages& out, std::uint8_t only = 0) const;
  /** @brief Frame @p i as an organized cloud (as SampleRenderer::render) and, if asked, the mask. */
  void render(int i, Cloud& out, std::vector<std::uint8_t>* mask = nullptr) const;
  /** @brief The truth of every person present at frame @p i, from that frame's @p images. */
  std::vector<CrowdTruth> truth(int i, const FrameImages& images) const;
  /** @brief The least ground-plane distance between two people present at the same frame (m; how
   *         well the composition kept them apart; +inf with fewer than two at once). */
  float leastClearance() const;

  const CameraModel& camera() const;
  const SceneRenderer& scene() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace synth
}  // namespace action_flow
