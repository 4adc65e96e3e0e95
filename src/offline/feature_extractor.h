/**
 * @file feature_extractor.h
 * @brief Turns one recorded or rendered sample into frame descriptors the way the live pipeline
 *        does: people tracker, then per track flow and grid descriptor (PersonPipeline). ROS-free;
 *        the tools give it frames from bags or from the virtual Kinect.
 */
#pragma once

#include <action_flow/action_model.h>
#include "../eval/evaluation.h"
#include <action_flow/people_tracker.h>

#include <functional>
#include <vector>

namespace action_flow
{
/** @brief The frames of one sample, in time order. */
class FrameSource
{
public:
  virtual ~FrameSource() = default;
  /** @brief The next frame; false at the end. */
  virtual bool next(Cloud& cloud, double& stamp) = 0;
};

/**
 * @brief Runs the tracker once over @p source and, for each variant, the person pipeline of every
 *        track; returns, per variant, the frame descriptors of the sample's performer: the track
 *        seen in the most frames (a dataset sample shows one person). With @p all_tracks, every
 *        track's descriptors instead, in time order, with SampleFrames::tracks (a stream: the
 *        tracker may lose the performer and find them again under a new id, as it would live).
 * @param variants parameter sets to extract at once (e.g. SUMFLOW and MEANFLOW), on the person
 *        clouds of @p tracker (at its person_voxel_size)
 * @param observe if given, called with every frame's stamp and the tracker's output for it (the
 *        people where they were: the crowd protocol matches tracks to people with it)
 * @throws std::invalid_argument if the variants' flow/max_gap differ
 */
std::vector<SampleFrames> extractSample(FrameSource& source, const TrackerParams& tracker,
                                        const std::vector<RecognitionParams>& variants, bool all_tracks = false,
                                        const std::function<void(double, const TrackerResult&)>& observe = {});

}  // namespace action_flow
