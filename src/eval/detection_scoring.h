/**
 * @file detection_scoring.h
 * @brief Scoring people detections against true people, frame by frame, on the floor plane:
 *        one-to-one matching within a gate, precision and recall, and tallies per scene type or
 *        bin. ROS-free; used by evaluate --protocol detection.
 */
#pragma once

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief A true person in one frame: where they stand (floor plane, m) and whether they must be found. */
struct TruthPerson
{
  Eigen::Vector2f position = Eigen::Vector2f::Zero();
  /** false: too little of them is seen to demand a detection (a detection matched to them counts
   *  neither as right nor as false). */
  bool required = true;
};

/** @brief Counts of one frame or many. */
struct DetectionCounts
{
  long true_positives = 0;   ///< detections matched to a required person
  long false_positives = 0;  ///< detections matched to no person
  long misses = 0;           ///< required people matched to no detection
  long ignored = 0;          ///< detections matched to a person who is not required
  long frames = 0;

  /** @brief tp / (tp + fp); NaN with no (non-ignored) detection. */
  double precision() const;
  /** @brief tp / (tp + misses); NaN with no required person. */
  double recall() const;
  DetectionCounts& operator+=(const DetectionCounts& other);
};

/** @brief The outcome of one frame. */
struct FrameScore
{
  DetectionCounts counts;
  std::vector<int> truth_of_detection;  ///< per detection: the matched person's index, -1 if none
  std::vector<int> false_detections;    ///< indices of the false detections
  std::vector<int> missed;              ///< indices of the required people not found
};

/**
 * @brief Matches @p detections to @p truth one to one, nearest pairs first, a pair only when closer
 *        than @p gate (horizontal distance, m), and counts the outcome (frames = 1).
 * @throws std::invalid_argument if gate is not positive and finite
 */
FrameScore scoreFrame(const std::vector<Eigen::Vector2f>& detections, const std::vector<TruthPerson>& truth, float gate);

/**
 * @brief The bin of @p value among @p edges (ascending): "lo..hi" with the edges printed by
 *        @p format (printf, e.g. "%.1f"), "<first" below the first edge, ">=last" from the last on.
 * @throws std::invalid_argument with fewer than 2 edges or edges not ascending
 */
std::string binLabel(double value, const std::vector<double>& edges, const char* format = "%.1f");

/** @brief Counts under named keys (scene type, bin), summed. */
using DetectionTally = std::map<std::string, DetectionCounts>;

}  // namespace action_flow
