/**
 * @file no_action.h
 * @brief The "no action" class an online model can learn: windows of a training person's
 *        continuous stream that lie (almost) outside every action of its truth, i.e. transitions,
 *        walks between places and idle periods. The classifier then has an answer for what the
 *        motion cut opens on between actions, and the policy never publishes it (it is one of
 *        PolicyParams::idle_labels). Without it the classifier can only choose among the actions,
 *        and a calibrated probability does not help: it is calibrated on samples of actions.
 */
#pragma once

#include "evaluation.h"
#include "stream_scoring.h"

#include <action_flow/recognition_policy.h>  // kNoActionLabel

#include <string>
#include <vector>

namespace action_flow
{
/** @brief Which windows of a stream become no-action samples. */
struct NoActionWindows
{
  std::vector<double> lengths = { 1.5, 3.0 };  ///< s: window lengths (the motion cut's segments are 1-4 s)
  double step = 0.5;                           ///< s between the starts of two windows of one length
  double max_action_share = 0.25;              ///< of a window's span that may lie inside actions
  double min_coverage = 0.8;                   ///< share of the window the track's frames must span
  int min_frames = 5;                          ///< fewer frame descriptors make no window
  int per_stream = 6;                          ///< at most this many windows per stream, spread evenly (0: none)
};

/**
 * @brief The no-action windows of one stream: for each track of @p stream (its rows; one track when
 *        it has no track ids) and each length, windows every `step` seconds whose time inside the
 *        actions of @p truth is at most max_action_share of their length; then at most per_stream
 *        of them, evenly spaced in the order found (lengths first, then time).
 * @throws std::invalid_argument on a non-positive length, step or out-of-range share
 */
std::vector<SampleFrames> noActionWindows(const std::vector<TruthSegment>& truth, const SampleFrames& stream,
                                          const NoActionWindows& w);

}  // namespace action_flow
