// evaluate --protocol detection: the people tracker, with its default parameters, on the virtual
// Kinect's cluttered rooms (synth dataset "clutter"): precision and recall per scene type, camera
// height and pitch, action and visible floor, and where the errors come from.
#pragma once

#include "../eval/detection_scoring.h"
#include <action_flow/people_tracker.h>
#include <action_flow/synth/synth.h>

#include <map>
#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
/** What one scene gave. */
struct SceneOutcome
{
  std::string name, kind, action;
  double camera_height = 0, pitch_up_deg = 0;  ///< the camera's; pitch positive = looking up
  double floor_share = 0;                      ///< share of the first frame's pixels that see the floor
  DetectionCounts counts;
  std::map<std::string, long> false_on;     ///< false detections by what they lie on (synth::objectAt)
  std::map<std::string, long> miss_causes;  ///< misses by cause
  long not_required = 0;                    ///< frames whose person was too little seen to be required
  /** One frame to show (the first with an error, else the middle one): colour and boxes. */
  int example_frame = -1;
  bool example_has_error = false;
  std::vector<std::uint8_t> example_rgb;
  std::string example_boxes;  ///< JSON array of {box: [u0, v0, u1, v1], what: tp|fp|ignored|truth|missed, on}
};

/**
 * Runs the tracker with @p params over @p spec (a clutter scene) and scores every frame after the
 * first (a track is reported from its second detection), matching detections to the person on
 * the floor within @p gate. A person is required in a frame when their head and at least 8 of their
 * 15 joints are inside the image and at least 35 % of their body (rendered alone) is seen.
 */
SceneOutcome runDetectionScene(const synth::SampleSpec& spec, const TrackerParams& params, float gate);

/**
 * Runs the protocol: --scenes N per kind (default 10), --seed, --gate (0.5 m), --jobs; writes
 * OUTPUT/detection.json, and unless --no-plots OUTPUT/detection.png and OUTPUT/detection_examples.png
 * (scripts/plot_detection.py).
 */
int runDetectionProtocol(const class Args& args, const std::string& dir);

/** Adds the detection protocol's options. */
void addDetectionOptions(class Options& o);

}  // namespace tools
}  // namespace action_flow
