// evaluate --protocol online: the classifier's policy on continuous streams of people who are not
// in training (synthetic actors, or MSR Action3D subjects' real motion), with its thresholds chosen
// on streams of training people only.
#pragma once

#include "sample_sources.h"

#include "../eval/evaluation.h"
#include <action_flow/recognition_policy.h>
#include "../eval/stream_scoring.h"

#include <nlohmann/json.hpp>

#include <deque>
#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
/** One stream with its truth and its frame descriptors. */
struct StreamCase
{
  std::string name;
  std::vector<TruthSegment> truth;
  std::vector<double> frame_stamps;  // every rendered frame
  double start = 0.0, end = 0.0;
  const SampleFrames* frames = nullptr;
};

/** The labels the policy publishes over one stream's frame descriptors (one track), as segments. */
std::vector<PredictedSegment> runPolicy(const std::shared_ptr<const ActionModel>& model, const PolicyParams& params,
                                        const SampleFrames& frames);

/**
 * The policy settings the online protocol chooses from: for posture_flow the motion cut's
 * thresholds, rest time, confidence and early or late labels, and sliding windows; for the
 * paper's recognizer sliding windows only.
 */
std::vector<PolicyParams> policyCandidates(Recognizer recognizer);

/**
 * The candidate with the best segment F1 over @p streams (ties: fewer false labels a minute, then
 * the earlier candidate); fills @p score with its combined score.
 */
PolicyParams choosePolicy(const std::shared_ptr<const ActionModel>& model, const std::vector<StreamCase>& streams,
                          const std::vector<PolicyParams>& candidates, StreamScore* score);

/** The settings that matter in a report. */
nlohmann::json policyJson(const PolicyParams& p);

/**
 * Runs the online protocol and writes OUTPUT/online.json, OUTPUT/timeline.csv and (unless
 * --no-plots) OUTPUT/timeline_<variant>_<stream>.png. @p samples are the segmented samples.
 * --synth ias: all of them train; the streams are of new actors after the training people.
 * --synth msr: those of --train-persons train; the streams are MSR streams (msr_stream) of the
 * other subjects. Either way the thresholds are chosen on streams of some training people
 * (--tuning-people) with a model trained on the others.
 */
int runOnlineProtocol(const class Args& args, const std::vector<SampleRef>& samples, const std::string& dir);

/** How many windows of each training stream a model learns: as no_action, and as the action they hold. */
struct StreamWindowCounts
{
  int no_action = 0;
  int action = 0;
};

/**
 * train --no-action-windows N --action-windows M: renders --training-streams streams (default 1) of every person of @p samples
 * (--synth ias: synthetic actors; --synth msr: MSR subjects, of the actions they train on), extracts
 * it with @p params and appends up to @p counts of its no-action and action windows (no_action.h)
 * to @p labelled, their indices to @p rows; @p store keeps their frames. Returns how many were added.
 */
std::size_t appendStreamWindows(const class Args& args, const std::vector<SampleRef>& samples,
                                const StreamWindowCounts& counts, const RecognitionParams& params,
                                std::vector<LabelledSample>& labelled, std::vector<std::size_t>& rows,
                                std::deque<SampleFrames>& store);

/** Adds the online protocol's options. */
void addOnlineOptions(class Options& o);

}  // namespace tools
}  // namespace action_flow
