// Scoring online recognition on continuous streams: known answers worked out by hand.
#include "../../src/eval/stream_scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

using namespace action_flow;

namespace
{
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// Scores with frames that do not matter and a stream spanning 0..100 s.
StreamScore score(const std::vector<TruthSegment>& truth, const std::vector<PredictedSegment>& predicted,
                  double iou_threshold = 0.5)
{
  return scoreStream(truth, predicted, {}, 0.0, 100.0, iou_threshold);
}
}  // namespace

TEST(TemporalIou, KnownSpans)
{
  EXPECT_DOUBLE_EQ(temporalIou(0, 4, 2, 6), 2.0 / 6.0);   // overlap 2 of union 6
  EXPECT_DOUBLE_EQ(temporalIou(2, 6, 0, 4), 2.0 / 6.0);   // symmetric
  EXPECT_DOUBLE_EQ(temporalIou(0, 10, 2, 5), 0.3);        // containment: 3 of 10
  EXPECT_DOUBLE_EQ(temporalIou(2, 5, 0, 10), 0.3);
  EXPECT_DOUBLE_EQ(temporalIou(1, 3, 1, 3), 1.0);         // identical
  EXPECT_EQ(temporalIou(0, 1, 2, 3), 0.0);                // disjoint
  EXPECT_EQ(temporalIou(0, 1, 1, 2), 0.0);                // touching
  EXPECT_EQ(temporalIou(1, 1, 1, 1), 0.0);                // both empty
  EXPECT_EQ(temporalIou(0, 2, 1, 1), 0.0);                // an empty span inside a full one
}

TEST(TemporalIou, RejectsBadSpans)
{
  EXPECT_THROW(temporalIou(2, 1, 0, 3), std::invalid_argument);
  EXPECT_THROW(temporalIou(0, 3, 2, 1), std::invalid_argument);
  EXPECT_THROW(temporalIou(kNaN, 1, 0, 3), std::invalid_argument);
  EXPECT_THROW(temporalIou(0, kInf, 0, 3), std::invalid_argument);
}

// walk and wave found (tIoU 1 and 0.75), kick missed: a wrong label over it, and a kick with tIoU 0.2.
TEST(ScoreStream, ThreeTruthsFourPredictions)
{
  const std::vector<TruthSegment> truth = { { "walk", 0, 4 }, { "wave", 5, 9 }, { "kick", 10, 14 } };
  const std::vector<PredictedSegment> predicted = {
    { "walk", 0, 4, 4.2 }, { "wave", 6, 9, 9.1 }, { "walk", 10, 14, 14.1 }, { "kick", 12, 20, 20.0 }
  };
  const auto s = score(truth, predicted);
  EXPECT_EQ(s.truths, 3);
  EXPECT_EQ(s.predictions, 4);
  EXPECT_EQ(s.matched, 2);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.f1, 4.0 / 7.0);
  EXPECT_EQ(s.false_labels, 2);
  EXPECT_EQ(s.match_of_truth, (std::vector<int>{ 0, 1, -1 }));
  EXPECT_EQ(s.match_of_prediction, (std::vector<int>{ 0, 1, -1, -1 }));
}

TEST(ScoreStream, ThresholdDecidesAMatch)
{
  const std::vector<TruthSegment> truth = { { "a", 0, 10 } };
  const std::vector<PredictedSegment> predicted = { { "a", 6, 10, 10 } };  // tIoU 4/10
  EXPECT_EQ(score(truth, predicted, 0.5).matched, 0);
  EXPECT_EQ(score(truth, predicted, 0.5).false_labels, 1);
  EXPECT_EQ(score(truth, predicted, 0.3).matched, 1);
  EXPECT_EQ(score(truth, predicted, 0.4).matched, 1);  // tIoU equal to the threshold matches
  EXPECT_EQ(score(truth, predicted, 0.3).false_labels, 0);
}

TEST(ScoreStream, WrongLabelWithPerfectOverlapIsNotMatched)
{
  const auto s = score({ { "a", 0, 5 } }, { { "b", 0, 5, 5 } });
  EXPECT_EQ(s.matched, 0);
  EXPECT_EQ(s.false_labels, 1);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_EQ(s.recall, 0.0);
  EXPECT_EQ(s.f1, 0.0);
  EXPECT_TRUE(s.start_latency.empty());
}

TEST(ScoreStream, OneTruthMatchesOnlyOneOfTwoCorrectPredictions)
{
  const auto s = score({ { "a", 0, 10 } }, { { "a", 0, 8, 8 }, { "a", 0, 10, 10.5 } });
  EXPECT_EQ(s.matched, 1);
  EXPECT_EQ(s.false_labels, 1);
  EXPECT_EQ(s.match_of_truth, (std::vector<int>{ 1 }));  // the higher tIoU (1 against 0.8)
  EXPECT_EQ(s.match_of_prediction, (std::vector<int>{ -1, 0 }));
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 1.0);
  EXPECT_DOUBLE_EQ(s.f1, 2.0 / 3.0);
  // The latency is the first correct label's (published at 8), not the matched one's.
  ASSERT_EQ(s.start_latency.size(), 1u);
  EXPECT_DOUBLE_EQ(s.start_latency[0], 8.0);
  EXPECT_DOUBLE_EQ(s.end_latency[0], -2.0);
}

// tIoUs: P0-T0 0.9, P1-T1 9/11, P1-T0 6/14, P0-T1 4/15; matching truths in order with the first
// fitting prediction would pair T0-P1 and T1-P0 instead.
TEST(ScoreStream, MatchesGreedilyByDecreasingIou)
{
  const auto s = score({ { "a", 0, 10 }, { "a", 5, 15 } }, { { "a", 0, 9, 9 }, { "a", 4, 14, 14 } }, 0.25);
  EXPECT_EQ(s.matched, 2);
  EXPECT_EQ(s.match_of_truth, (std::vector<int>{ 0, 1 }));
  // Swapping the predictions' order changes nothing but the indices.
  const auto swapped = score({ { "a", 0, 10 }, { "a", 5, 15 } }, { { "a", 4, 14, 14 }, { "a", 0, 9, 9 } }, 0.25);
  EXPECT_EQ(swapped.match_of_truth, (std::vector<int>{ 1, 0 }));
}

TEST(ScoreStream, IouTieGoesToTheEarlierTruth)
{
  // The prediction has tIoU 8/12 with both truths.
  const auto s = score({ { "a", 0, 10 }, { "a", 4, 14 } }, { { "a", 2, 12, 12 } });
  EXPECT_EQ(s.match_of_truth, (std::vector<int>{ 0, -1 }));
  EXPECT_EQ(s.match_of_prediction, (std::vector<int>{ 0 }));
}

// Stream 0..60 s, truths during 10..20 and 30..40: 40 s idle. Six unknown labels published at
// 5, 10, 15, 20, 25 and 45 (three while idle; 10 and 20 are a truth's ends), and a correct x
// published at 21, after its action ended (matched: not a false label).
TEST(ScoreStream, IdleFalseCountsLabelsPublishedOutsideTruthsAndRates)
{
  const std::vector<TruthSegment> truth = { { "x", 10, 20 }, { "y", 30, 40 } };
  std::vector<PredictedSegment> predicted;
  for (const double t : { 5.0, 10.0, 15.0, 20.0, 25.0, 45.0 })
    predicted.push_back({ "z", t - 1, t, t });
  predicted.push_back({ "x", 10, 20, 21 });
  const auto s = scoreStream(truth, predicted, {}, 0.0, 60.0);
  EXPECT_DOUBLE_EQ(s.stream_seconds, 60.0);
  EXPECT_DOUBLE_EQ(s.idle_seconds, 40.0);
  EXPECT_EQ(s.matched, 1);
  EXPECT_EQ(s.false_labels, 6);
  EXPECT_EQ(s.idle_false, 3);  // at 5, 25 and 45, not the late but right x at 21
  EXPECT_DOUBLE_EQ(s.idle_false_per_minute(), 3 / (40.0 / 60.0));
  EXPECT_DOUBLE_EQ(s.false_per_minute(), 6.0);
}

TEST(ScoreStream, IdleTimeIsTheStreamOutsideTheUnionOfTruths)
{
  // Covered within 0..100: 0..15 (two overlapping truths, one from before the stream) and 90..100.
  const auto s = scoreStream({ { "a", -10, 10 }, { "b", 5, 15 }, { "c", 90, 120 } }, {}, {}, 0.0, 100.0);
  EXPECT_DOUBLE_EQ(s.idle_seconds, 75.0);
  EXPECT_DOUBLE_EQ(s.stream_seconds, 100.0);
  // No time, no rates.
  const auto empty = scoreStream({}, { { "a", 5, 5, 5 } }, {}, 5.0, 5.0);
  EXPECT_EQ(empty.idle_seconds, 0.0);
  EXPECT_EQ(empty.idle_false, 1);
  EXPECT_EQ(empty.idle_false_per_minute(), 0.0);
  EXPECT_EQ(empty.false_per_minute(), 0.0);
}

TEST(ScoreStream, LatenciesFromStartAndEnd)
{
  const std::vector<TruthSegment> truth = { { "a", 10, 20 }, { "b", 30, 40 }, { "c", 50, 60 } };
  const std::vector<PredictedSegment> predicted = {
    { "a", 10, 20, 21 },    // correct, published after the next one
    { "a", 10, 19, 18 },    // correct, the first published: latencies 8 and -2
    { "b", 30, 40, 41.5 },  // latencies 11.5 and 1.5
    { "c", 55, 70, 70 },    // tIoU 5/20: not a correct label, so c gets no latency
  };
  const auto s = score(truth, predicted);
  ASSERT_EQ(s.start_latency.size(), 2u);
  ASSERT_EQ(s.end_latency.size(), 2u);
  EXPECT_DOUBLE_EQ(s.start_latency[0], 8.0);
  EXPECT_DOUBLE_EQ(s.end_latency[0], -2.0);
  EXPECT_DOUBLE_EQ(s.start_latency[1], 11.5);
  EXPECT_DOUBLE_EQ(s.end_latency[1], 1.5);
}

// Truths a 0..2 and b 3..5. Predictions listed against their publish order, so "latest published"
// and "last in the list" differ.
TEST(ScoreStream, FrameAccuracy)
{
  const std::vector<TruthSegment> truth = { { "a", 0, 2 }, { "b", 3, 5 } };
  const std::vector<PredictedSegment> predicted = { { "a", 3.5, 6, 6.5 }, { "b", 1, 4, 4.5 }, { "a", 0, 1.5, 1.6 } };
  // 0.5: a/a right; 1.2: a/b (b published later) wrong; 2.5: ""/b wrong; 3.2: b/b right;
  // 3.8: b/a (a published later) wrong; 5.5: ""/a wrong; 7: ""/"" right.
  const auto s = scoreStream(truth, predicted, { 0.5, 1.2, 2.5, 3.2, 3.8, 5.5, 7.0 }, 0.0, 8.0);
  EXPECT_EQ(s.frames, 7);
  EXPECT_DOUBLE_EQ(s.frame_accuracy, 3.0 / 7.0);
}

TEST(ScoreStream, FrameOnTouchingTruthsBelongsToTheOneStarting)
{
  // At 2 s a ends and b starts: the frame's truth is b.
  const std::vector<TruthSegment> truth = { { "a", 0, 2 }, { "b", 2, 4 } };
  EXPECT_DOUBLE_EQ(scoreStream(truth, { { "b", 1, 3, 3 } }, { 2.0 }, 0, 4).frame_accuracy, 1.0);
  EXPECT_DOUBLE_EQ(scoreStream(truth, { { "a", 1, 3, 3 } }, { 2.0 }, 0, 4).frame_accuracy, 0.0);
}

TEST(ScoreStream, EmptyStream)
{
  const auto s = scoreStream({}, {}, { 1.0, 2.0 }, 0.0, 30.0);
  EXPECT_EQ(s.matched, 0);
  EXPECT_EQ(s.precision, 0.0);
  EXPECT_EQ(s.recall, 0.0);
  EXPECT_EQ(s.f1, 0.0);
  EXPECT_DOUBLE_EQ(s.frame_accuracy, 1.0);  // nothing happened and nothing was said
  EXPECT_DOUBLE_EQ(s.idle_seconds, 30.0);
  EXPECT_EQ(scoreStream({}, {}, {}, 0.0, 30.0).frame_accuracy, 0.0);
}

TEST(ScoreStream, RejectsInvalidInput)
{
  const std::vector<TruthSegment> good_truth = { { "a", 0, 1 } };
  const std::vector<PredictedSegment> good_pred = { { "a", 0, 1, 1 } };
  EXPECT_NO_THROW(scoreStream(good_truth, good_pred, { 0.5 }, 0, 2, 1.0));
  EXPECT_THROW(scoreStream({ { "a", 2, 1 } }, good_pred, {}, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, { { "a", 2, 1, 2 } }, {}, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream({ { "a", kNaN, 1 } }, good_pred, {}, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, { { "a", 0, kInf, 1 } }, {}, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, { { "a", 0, 1, kInf } }, {}, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, good_pred, { kNaN }, 0, 2), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, good_pred, {}, 2, 0), std::invalid_argument);
  EXPECT_THROW(scoreStream(good_truth, good_pred, {}, 0, kInf), std::invalid_argument);
  for (const double t : { 0.0, -0.1, 1.0001, kNaN })
    EXPECT_THROW(scoreStream(good_truth, good_pred, {}, 0, 2, t), std::invalid_argument) << t;
}

TEST(CombineScores, SumsCountsAndRecomputesFigures)
{
  StreamScore a;
  a.truths = 3;
  a.predictions = 4;
  a.matched = 2;
  a.frames = 10;
  a.frame_accuracy = 0.7;
  a.idle_seconds = 20;
  a.idle_false = 1;
  a.false_labels = 2;
  a.stream_seconds = 60;
  a.start_latency = { 1, 2 };
  a.end_latency = { -1, 0 };
  a.match_of_truth = { 0, 1, -1 };
  a.match_of_prediction = { 0, 1, -1, -1 };
  StreamScore b;
  b.truths = 1;
  b.frames = 30;
  b.frame_accuracy = 0.5;
  b.idle_seconds = 40;
  b.stream_seconds = 120;
  b.start_latency = { 3 };
  b.end_latency = { 0.5 };
  b.match_of_truth = { -1 };
  const auto s = combineScores({ a, b });
  EXPECT_EQ(s.truths, 4);
  EXPECT_EQ(s.predictions, 4);
  EXPECT_EQ(s.matched, 2);
  EXPECT_DOUBLE_EQ(s.precision, 0.5);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
  EXPECT_DOUBLE_EQ(s.f1, 0.5);
  EXPECT_EQ(s.frames, 40);
  EXPECT_DOUBLE_EQ(s.frame_accuracy, (7.0 + 15.0) / 40.0);  // weighted by frames, not (0.7 + 0.5) / 2
  EXPECT_DOUBLE_EQ(s.idle_seconds, 60.0);
  EXPECT_EQ(s.idle_false, 1);
  EXPECT_EQ(s.false_labels, 2);
  EXPECT_DOUBLE_EQ(s.stream_seconds, 180.0);
  EXPECT_DOUBLE_EQ(s.idle_false_per_minute(), 1.0);
  EXPECT_DOUBLE_EQ(s.false_per_minute(), 2.0 / 3.0);
  EXPECT_EQ(s.start_latency, (std::vector<double>{ 1, 2, 3 }));
  EXPECT_EQ(s.end_latency, (std::vector<double>{ -1, 0, 0.5 }));
  EXPECT_TRUE(s.match_of_truth.empty());
  EXPECT_TRUE(s.match_of_prediction.empty());

  const auto none = combineScores({});
  EXPECT_EQ(none.truths, 0);
  EXPECT_EQ(none.f1, 0.0);
  EXPECT_EQ(none.frame_accuracy, 0.0);
}

TEST(CombineScores, OfScoredStreamsMatchesOneStreamHoldingBoth)
{
  const auto first = scoreStream({ { "a", 0, 10 } }, { { "a", 0, 10, 11 }, { "b", 20, 25, 25 } }, { 5, 22 }, 0, 30);
  const auto second = scoreStream({ { "b", 0, 10 } }, { { "a", 0, 10, 10 } }, { 5, 15, 25 }, 0, 30);
  const auto s = combineScores({ first, second });
  EXPECT_EQ(s.matched, 1);
  EXPECT_DOUBLE_EQ(s.precision, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
  EXPECT_DOUBLE_EQ(s.frame_accuracy, 3.0 / 5.0);  // 5 a/a right, 22 ""/b wrong; 5 b/a wrong, 15 and 25 right
  EXPECT_EQ(s.idle_false, 1);                      // the b at 25 (the a at 11 is late but right)
  EXPECT_EQ(s.start_latency, (std::vector<double>{ 11 }));
}

TEST(Median, OddEvenEmpty)
{
  EXPECT_DOUBLE_EQ(median({ 3, 1, 2 }), 2.0);
  EXPECT_DOUBLE_EQ(median({ 4, 1, 3, 2 }), 2.5);
  EXPECT_DOUBLE_EQ(median({ 5 }), 5.0);
  EXPECT_DOUBLE_EQ(median({ -1, 2 }), 0.5);
  EXPECT_TRUE(std::isnan(median({})));
}
