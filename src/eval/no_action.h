/**
 * @file no_action.h
 * @brief Samples an online model can learn from training people's continuous streams.
 *
 * The "no action" class: windows of a training person's
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

/**
 * @brief Which windows of a stream become samples of the action they hold, in context: with the
 *        transitions around it, as the online sliding window sees an action (the segmented
 *        training samples hold the action alone).
 */
struct ActionWindows
{
  double length = 3.0;             ///< s: the window (the sliding window's default)
  double step = 0.5;               ///< s between the starts of two windows
  double min_action_cover = 0.8;   ///< share of the action's span that must lie in the window
  double max_other_share = 0.1;    ///< of the window's length that may lie in other actions
  double min_coverage = 0.8;       ///< share of the window the track's frames must span
  int min_frames = 5;              ///< fewer frame descriptors make no window
  int per_stream = 24;             ///< at most this many windows per stream, spread evenly (0: none)
};

/** @brief A window of a stream and the action it holds. */
struct ActionWindow
{
  std::string label;
  SampleFrames frames;
};

/**
 * @brief The action windows of one stream: per track of @p stream, windows every `step` seconds
 *        that hold at least min_action_cover of one action of @p truth and at most max_other_share
 *        of their length of any other; then at most per_stream, evenly spaced in time order.
 * @throws std::invalid_argument on a non-positive length or step or an out-of-range share
 */
std::vector<ActionWindow> actionWindows(const std::vector<TruthSegment>& truth, const SampleFrames& stream,
                                        const ActionWindows& w);

/** @brief How many of @p labelled, from @p first on, are labelled no_action. */
std::size_t noActionCount(const std::vector<LabelledSample>& labelled, std::size_t first = 0);

}  // namespace action_flow
