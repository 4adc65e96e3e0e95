/**
 * @file crowd_recognition.h
 * @brief What recognition sees of one person among several: which of a scene's tracks shows a
 *        person during one of their actions, and that track's frame descriptors over the action
 *        (evaluate --protocol crowd). ROS-free.
 */
#pragma once

#include "evaluation.h"
#include "tracking_metrics.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief One action of one person of a scene: frames first..last (inclusive). */
struct CrowdSegment
{
  std::uint32_t person = 0;  ///< the person's truth id (TrackPoint::id)
  std::string action;
  int first = 0, last = 0;
};

/** @brief A tracked scene: each frame's stamp, and per frame the track each person was matched to. */
struct TrackedScene
{
  std::vector<double> stamps;
  std::vector<std::map<std::uint32_t, std::uint32_t>> track_of;  ///< per frame: truth id -> track id
};

/**
 * @brief Matches the tracks to the people frame by frame as the MOT scores do (matchTracking,
 *        within @p gate on the ground plane; hidden people are matched too).
 * @throws std::invalid_argument if @p stamps and @p frames differ in length, or as matchTracking
 */
TrackedScene trackScene(const std::vector<TrackingFrame>& frames, const std::vector<double>& stamps, float gate);

/**
 * @brief The frame descriptors that show @p segment's person doing it: of @p rows (every track's
 *        rows, SampleFrames::tracks set), those of the track matched to the person in the most of
 *        the segment's frames (ties: the lower id) with stamps inside the segment's first and last
 *        frame. Returns that track's id, or 0 (and empty @p out) when no track was matched to the
 *        person during the segment.
 * @throws std::invalid_argument if the segment's frames are not within the scene, or @p rows has
 *         no tracks while it has rows
 */
std::uint32_t segmentFrames(const SampleFrames& rows, const TrackedScene& scene, const CrowdSegment& segment,
                            SampleFrames& out);

}  // namespace action_flow
