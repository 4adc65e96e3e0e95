/**
 * @file tracking_metrics.h
 * @brief Multi-object tracking scores as the MOT benchmarks compute them: CLEAR MOT (MOTA, MOTP,
 *        id switches, fragmentations; Bernardin & Stiefelhagen 2008) and the identity scores
 *        (IDF1, IDP, IDR; Ristani et al. 2016), matching by distance on the ground plane. ROS-free.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace action_flow
{
/** @brief One object in one frame: who (a truth person or a track id) and where on the ground plane (m). */
struct TrackPoint
{
  std::uint32_t id = 0;
  Eigen::Vector2f position = Eigen::Vector2f::Zero();
  /** Truth only: present but not to be tracked (hidden, out of view). A prediction matched to it
   *  counts neither as a match nor as a false positive; unmatched, it is no miss. */
  bool ignored = false;
};

/** @brief The truth and the tracker's output of one frame. */
struct TrackingFrame
{
  std::vector<TrackPoint> truth;
  std::vector<TrackPoint> predicted;
};

/** @brief The scores of a sequence (or of several: see addTrackingScores). */
struct TrackingScores
{
  std::size_t frames = 0;
  std::size_t truth = 0;            ///< truth objects to track, summed over frames
  std::size_t matches = 0;          ///< true positives
  std::size_t misses = 0;           ///< false negatives
  std::size_t false_positives = 0;
  std::size_t id_switches = 0;      ///< a truth object matched to another track than at its last match
  std::size_t fragmentations = 0;   ///< a truth object's matched run interrupted and taken up again
  double distance_sum = 0.0;        ///< of the matches (m), for MOTP
  std::size_t truth_ids = 0, predicted_ids = 0;  ///< distinct ids that took part (not ignored)
  std::size_t mostly_tracked = 0;   ///< truth ids matched in >= 80 % of their frames
  std::size_t mostly_lost = 0;      ///< ... in < 20 %
  std::size_t idtp = 0, idfp = 0, idfn = 0;  ///< identity true positives, false positives, false negatives
  double person_seconds = 0.0;      ///< truth objects to track x frame duration

  /** 1 - (misses + false positives + id switches) / truth (truth taken as 1 when there is none). */
  double mota() const;
  /** Mean distance of the matches (m); 0 without matches. */
  double motp() const;
  // The ratios below are 1 when their denominator is 0 (nothing to get wrong).
  double precision() const;  ///< matches / (matches + false positives)
  double recall() const;     ///< matches / truth
  double idf1() const;       ///< 2 IDTP / (2 IDTP + IDFP + IDFN)
  double idp() const;        ///< IDTP / (IDTP + IDFP)
  double idr() const;        ///< IDTP / (IDTP + IDFN)
  /** Id switches per minute of a person to be tracked (0 with none tracked). */
  double switchesPerPersonMinute() const;
};

/**
 * @brief Scores a sequence.
 *
 * Per frame, as py-motmetrics and the MOT devkit do: a truth object keeps the track it was last
 * matched to if that track is present within @p gate; the others are assigned by minimum total
 * distance (Hungarian method) among pairs within @p gate, as many pairs as possible. A truth object
 * matched to another track than at its last match is an id switch. Predictions matched to ignored
 * truth are dropped before anything is counted. The identity scores then pair whole truth
 * trajectories with whole tracks one to one, maximising the frames in which a pair is within the
 * gate (IDTP), over the frames that count.
 *
 * @param gate largest ground-plane distance (m) of a match, inclusive
 * @param frame_seconds the duration of one frame (for the rate of id switches)
 * @throws std::invalid_argument on a gate that is not positive, a non-finite position, or an id
 *         used twice in one frame's truth or predictions
 */
TrackingScores scoreTracking(const std::vector<TrackingFrame>& frames, float gate, double frame_seconds);

/**
 * @brief The matches scoreTracking makes, frame by frame: per frame, for each truth object (in the
 *        frame's order) the index of the prediction matched to it, or -1. Ignored truth is matched
 *        too (a track on a hidden person is that person's), but only counted truth carries a match
 *        on to the next frame, as in scoreTracking.
 * @throws std::invalid_argument as scoreTracking
 */
std::vector<std::vector<int>> matchTracking(const std::vector<TrackingFrame>& frames, float gate);

/** @brief Sums the counts of two scored sequences (ids of different sequences count apart). */
TrackingScores addTrackingScores(const TrackingScores& a, const TrackingScores& b);

}  // namespace action_flow
