/**
 * @file stream_scoring.h
 * @brief Scores online recognition on a continuous stream: the labels a recognizer published
 *        against the stream's true action segments (segment-level precision/recall/F1 in the
 *        PKU-MMD style, frame accuracy, false labels while idle, latencies). ROS-free.
 *
 * All times are in seconds on one clock (e.g. the bag's stamps). Spans are closed: [start, end].
 */
#pragma once

#include <string>
#include <vector>

namespace action_flow
{
/** @brief A true action in a stream: label and time span in seconds (start <= end). */
struct TruthSegment
{
  std::string label;
  double start = 0, end = 0;
};

/** @brief A label the recognizer published: its label, the span it claims, and when it was published. */
struct PredictedSegment
{
  std::string label;
  double start = 0, end = 0;
  double published = 0;
};

/**
 * @brief Temporal intersection over union of two spans: the length of their overlap over the
 *        length of their union; 0 when they are disjoint or only touch, and when both are empty.
 *        A containment gives the shorter span's length over the longer's.
 * @throws std::invalid_argument on a span with end < start or a non-finite time
 */
double temporalIou(double a_start, double a_end, double b_start, double b_end);

/** @brief What scoreStream found on one stream (or combineScores on several). */
struct StreamScore
{
  int truths = 0, predictions = 0;
  int matched = 0;            ///< pairs (truth, prediction) with the same label and tIoU >= threshold, one-to-one
  double precision = 0;       ///< matched / predictions (segment level, PKU-MMD style); 0 without predictions
  double recall = 0;          ///< matched / truths; 0 without truths
  double f1 = 0;              ///< 2 P R / (P + R); 0 when P + R is 0
  /**
   * Share of the frames given whose label was right: a frame's truth is the label of the truth
   * segment covering its stamp or "" (none), its prediction likewise the label of the covering
   * predicted segment or ""; "" against "" is right. 0 without frames.
   */
  double frame_accuracy = 0;
  int frames = 0;             ///< frames scored for frame_accuracy
  double idle_seconds = 0;    ///< time within [stream_start, stream_end] not inside any truth segment
  int idle_false = 0;         ///< unmatched predictions published while no truth segment was under way (idle, transitions)
  int false_labels = 0;       ///< predictions not matched to a truth segment
  double stream_seconds = 0;  ///< stream_end - stream_start
  /** @brief idle_false per minute of idle time; 0 when idle_seconds is 0. */
  double idle_false_per_minute() const;
  /** @brief false_labels per minute of the stream; 0 when stream_seconds is 0. */
  double false_per_minute() const;
  /**
   * Per truth segment that got a correct label (in truth order): the publish time of the first
   * published correct prediction (same label, tIoU >= threshold; not necessarily the one matched
   * to it) minus the segment's start, respectively end. End latency is negative when the label
   * came before the action ended.
   */
  std::vector<double> start_latency, end_latency;
  std::vector<int> match_of_truth;       ///< per truth: index of the matched prediction or -1
  std::vector<int> match_of_prediction;  ///< per prediction: index of the matched truth or -1
};

/**
 * @brief Scores one stream.
 *
 * Matching: a truth and a prediction may be matched when they have the same label and
 * tIoU >= @p iou_threshold (with a tolerance of 1e-9 for rounding); each truth and each
 * prediction is matched at most once, greedily by decreasing tIoU (ties: earlier truth first,
 * then earlier prediction). Overlapping predictions are allowed (a recognizer may publish twice);
 * the ones left over are false labels. For frame accuracy, when several predictions cover a
 * frame the latest published wins (ties: the later in @p predicted); when several truths cover
 * it (touching ends) the one starting latest wins. A prediction published at a truth's start or
 * end counts as published while it was under way.
 *
 * @param frame_stamps the stamps of the stream's frames, for frame accuracy
 * @param stream_start,stream_end the stream's time span, for idle time and the rates; truth
 *        segments reaching outside it count only within it for idle_seconds
 * @throws std::invalid_argument on a segment with end < start, a non-finite time (segment,
 *         publish time, frame stamp or stream span), stream_end < stream_start, or
 *         @p iou_threshold not in (0, 1]
 */
StreamScore scoreStream(const std::vector<TruthSegment>& truth, const std::vector<PredictedSegment>& predicted,
                        const std::vector<double>& frame_stamps, double stream_start, double stream_end,
                        double iou_threshold = 0.5);

/**
 * @brief Sums several streams' scores: counts and times add up, precision, recall, F1 and frame
 *        accuracy are recomputed from the sums (so frame accuracy is weighted by frames),
 *        latencies are concatenated in order; the match vectors are left empty.
 */
StreamScore combineScores(const std::vector<StreamScore>& scores);

/** @brief Median of @p values (the mean of the two middle ones for an even count); NaN when empty. */
double median(std::vector<double> values);

}  // namespace action_flow
