// The MOT scores on hand-made truth and predictions whose MOTA, IDF1, switches and the rest are
// worked out by hand (known answers).
#include "../../src/eval/tracking_metrics.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace action_flow;

namespace
{
TrackPoint at(std::uint32_t id, float x, float y = 0.0f, bool ignored = false)
{
  TrackPoint p;
  p.id = id;
  p.position = Eigen::Vector2f(x, y);
  p.ignored = ignored;
  return p;
}

constexpr float kGate = 0.5f;
constexpr double kFrame = 1.0 / 30.0;
}  // namespace

TEST(TrackingMetrics, PerfectTrackingScoresOne)
{
  std::vector<TrackingFrame> frames(10);
  for (int k = 0; k < 10; ++k)
  {
    frames[k].truth = { at(1, 0.1f * k), at(2, 3.0f) };
    frames[k].predicted = { at(7, 0.1f * k + 0.1f), at(9, 3.0f, 0.2f) };
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.truth, 20u);
  EXPECT_EQ(s.matches, 20u);
  EXPECT_EQ(s.misses + s.false_positives + s.id_switches + s.fragmentations, 0u);
  EXPECT_DOUBLE_EQ(s.mota(), 1.0);
  EXPECT_DOUBLE_EQ(s.idf1(), 1.0);
  EXPECT_NEAR(s.motp(), 0.15, 1e-6);  // half the matches 0.1 m off, half 0.2 m
  EXPECT_EQ(s.mostly_tracked, 2u);
  EXPECT_EQ(s.truth_ids, 2u);
  EXPECT_EQ(s.predicted_ids, 2u);
  EXPECT_NEAR(s.person_seconds, 20.0 / 30.0, 1e-9);
}

TEST(TrackingMetrics, ATrackHandedOverHalfWayIsOneSwitch)
{
  // A is followed by track 1 in frames 0-4 and by track 2 in frames 5-9; B by track 3 throughout.
  std::vector<TrackingFrame> frames(10);
  for (int k = 0; k < 10; ++k)
  {
    frames[k].truth = { at(1, 0.0f), at(2, 2.0f) };
    frames[k].predicted = { at(k < 5 ? 1 : 2, 0.05f), at(3, 2.0f) };
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.id_switches, 1u);
  EXPECT_EQ(s.fragmentations, 0u) << "matched in every frame: no interruption";
  EXPECT_DOUBLE_EQ(s.mota(), 1.0 - 1.0 / 20.0);
  // A pairs with one of its two tracks (5 frames): IDTP 5 + 10, IDFN 5, IDFP 5.
  EXPECT_EQ(s.idtp, 15u);
  EXPECT_EQ(s.idfn, 5u);
  EXPECT_EQ(s.idfp, 5u);
  EXPECT_DOUBLE_EQ(s.idf1(), 30.0 / 40.0);
  // 20 person-frames at 30 fps = 2/3 s = 1/90 min: one switch is 90 per person-minute.
  EXPECT_NEAR(s.switchesPerPersonMinute(), 90.0, 1e-9);
}

TEST(TrackingMetrics, MissesAndFalsePositivesCount)
{
  // 10 frames of A; found in frames 0-5; in frames 8 and 9 a track far from anyone.
  std::vector<TrackingFrame> frames(10);
  for (int k = 0; k < 10; ++k)
  {
    frames[k].truth = { at(1, 1.0f) };
    if (k < 6)
      frames[k].predicted = { at(4, 1.2f) };
    else if (k >= 8)
      frames[k].predicted = { at(5, 4.0f) };
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.matches, 6u);
  EXPECT_EQ(s.misses, 4u);
  EXPECT_EQ(s.false_positives, 2u);
  EXPECT_DOUBLE_EQ(s.mota(), 1.0 - 6.0 / 10.0);
  EXPECT_DOUBLE_EQ(s.precision(), 6.0 / 8.0);
  EXPECT_DOUBLE_EQ(s.recall(), 0.6);
  EXPECT_EQ(s.idtp, 6u);
  EXPECT_EQ(s.idfn, 4u);
  EXPECT_EQ(s.idfp, 2u);
  EXPECT_DOUBLE_EQ(s.idf1(), 12.0 / 18.0);
  EXPECT_EQ(s.mostly_tracked, 0u) << "60 % is not mostly tracked";
  EXPECT_EQ(s.mostly_lost, 0u);
}

TEST(TrackingMetrics, TheGateIsInclusiveAndNothingBeyondMatches)
{
  std::vector<TrackingFrame> frames(2);
  frames[0].truth = { at(1, 0.0f) };
  frames[0].predicted = { at(1, 0.5f) };  // exactly at the gate: a match
  frames[1].truth = { at(1, 0.0f) };
  frames[1].predicted = { at(1, 0.51f) };  // just beyond: a miss and a false positive
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.matches, 1u);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.false_positives, 1u);
  EXPECT_DOUBLE_EQ(s.mota(), 0.0);
}

TEST(TrackingMetrics, ATruthKeepsItsTrackWhileWithinTheGate)
{
  // Frame 0: A matched to track 1. Frame 1: track 2 is nearer to A, but track 1 is still within
  // the gate, so A keeps it (no switch) and track 2 is a false positive. Plain nearest matching
  // would switch.
  std::vector<TrackingFrame> frames(2);
  frames[0].truth = { at(1, 0.0f) };
  frames[0].predicted = { at(1, 0.1f) };
  frames[1].truth = { at(1, 0.0f) };
  frames[1].predicted = { at(1, 0.4f), at(2, 0.05f) };
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.id_switches, 0u);
  EXPECT_EQ(s.false_positives, 1u);
  EXPECT_EQ(s.matches, 2u);
}

TEST(TrackingMetrics, TheAssignmentMatchesAsManyAsPossible)
{
  // Track 1 is nearest to A, but A and B can both be matched only as A-2, B-1.
  std::vector<TrackingFrame> frames(1);
  frames[0].truth = { at(1, 0.0f), at(2, 0.6f) };
  frames[0].predicted = { at(1, 0.3f), at(2, -0.35f) };
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.matches, 2u);
  EXPECT_EQ(s.misses, 0u);
  EXPECT_NEAR(s.motp(), 0.325, 1e-6);
}

TEST(TrackingMetrics, ASwitchAfterAGapIsASwitchAndAFragmentation)
{
  // A: track 1 in frames 0-2, nobody in 3-4, track 2 in 5-7.
  std::vector<TrackingFrame> frames(8);
  for (int k = 0; k < 8; ++k)
  {
    frames[k].truth = { at(1, 0.0f) };
    if (k < 3)
      frames[k].predicted = { at(1, 0.0f) };
    else if (k >= 5)
      frames[k].predicted = { at(2, 0.0f) };
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.id_switches, 1u);
  EXPECT_EQ(s.fragmentations, 1u);
  EXPECT_EQ(s.misses, 2u);
  EXPECT_DOUBLE_EQ(s.mota(), 1.0 - 3.0 / 8.0);
  // A pairs with track 2 (3 frames) or 1 (3 frames): IDTP 3, IDFN 5, IDFP 3.
  EXPECT_DOUBLE_EQ(s.idf1(), 6.0 / (6.0 + 3.0 + 5.0));
}

TEST(TrackingMetrics, IgnoredTruthAbsorbsItsTrackAndIsNoMiss)
{
  // B is hidden (ignored) in frames 2-3: a track on it there is no false positive, no track on it no miss.
  std::vector<TrackingFrame> frames(4);
  for (int k = 0; k < 4; ++k)
  {
    frames[k].truth = { at(1, 0.0f), at(2, 2.0f, 0.0f, k >= 2) };
    frames[k].predicted = { at(1, 0.0f) };
    if (k != 3)
      frames[k].predicted.push_back(at(2, 2.0f));
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.truth, 6u);
  EXPECT_EQ(s.matches, 6u);
  EXPECT_EQ(s.false_positives, 0u);
  EXPECT_EQ(s.misses, 0u);
  EXPECT_DOUBLE_EQ(s.mota(), 1.0);
  EXPECT_DOUBLE_EQ(s.idf1(), 1.0);
}

TEST(TrackingMetrics, IdentityPairingMaximisesTheFramesInCommon)
{
  // A shares 6 frames with track 1 and 1 with track 2; B shares 2 frames with track 1. Pairing as
  // many as possible (A-2, B-1) would give IDTP 1 + 2 = 3; the best pairing is A-1 alone: IDTP 6.
  std::vector<TrackingFrame> frames(9);
  for (int k = 0; k < 6; ++k)
  {
    frames[k].truth = { at(1, 0.0f) };
    frames[k].predicted = { at(1, 0.0f) };
  }
  frames[6].truth = { at(1, 0.0f) };
  frames[6].predicted = { at(2, 0.0f) };
  for (int k = 7; k < 9; ++k)
  {
    frames[k].truth = { at(2, 5.0f) };
    frames[k].predicted = { at(1, 5.0f) };
  }
  const TrackingScores s = scoreTracking(frames, kGate, kFrame);
  EXPECT_EQ(s.idtp, 6u);
  EXPECT_EQ(s.idfn, 3u);  // A's frame with track 2, B's two frames
  EXPECT_EQ(s.idfp, 3u);  // track 2's frame, track 1's two frames on B
}

TEST(TrackingMetrics, SummingSequencesAddsTheCounts)
{
  std::vector<TrackingFrame> one(2), two(3);
  for (auto& f : one)
    f.truth = { at(1, 0.0f) }, f.predicted = { at(1, 0.0f) };
  for (auto& f : two)
    f.truth = { at(1, 0.0f) };
  const TrackingScores s = addTrackingScores(scoreTracking(one, kGate, kFrame), scoreTracking(two, kGate, kFrame));
  EXPECT_EQ(s.frames, 5u);
  EXPECT_EQ(s.truth, 5u);
  EXPECT_EQ(s.matches, 2u);
  EXPECT_EQ(s.misses, 3u);
  EXPECT_EQ(s.truth_ids, 2u);
  EXPECT_DOUBLE_EQ(s.idf1(), 4.0 / (4.0 + 3.0));
}

TEST(TrackingMetrics, BadInputIsRefused)
{
  std::vector<TrackingFrame> frames(1);
  frames[0].truth = { at(1, 0.0f), at(1, 1.0f) };
  EXPECT_THROW(scoreTracking(frames, kGate, kFrame), std::invalid_argument) << "an id twice in one frame";
  frames[0].truth = { at(1, std::nanf("")) };
  EXPECT_THROW(scoreTracking(frames, kGate, kFrame), std::invalid_argument);
  frames[0].truth = { at(1, 0.0f) };
  EXPECT_THROW(scoreTracking(frames, 0.0f, kFrame), std::invalid_argument);
  EXPECT_THROW(scoreTracking(frames, kGate, -1.0), std::invalid_argument);
  EXPECT_NO_THROW(scoreTracking({}, kGate, kFrame));
}
