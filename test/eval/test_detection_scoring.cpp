// Known answers for the detection scoring of evaluate --protocol detection.
#include "../../src/eval/detection_scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace action_flow;

namespace
{
TruthPerson person(float x, float y, bool required = true)
{
  TruthPerson t;
  t.position = Eigen::Vector2f(x, y);
  t.required = required;
  return t;
}
}  // namespace

TEST(DetectionScoring, OneDetectionOnThePersonAndOneOnAWall)
{
  const FrameScore s = scoreFrame({ { 3.1f, 0.2f }, { 4.0f, -1.0f } }, { person(3.0f, 0.0f) }, 0.5f);
  EXPECT_EQ(s.counts.true_positives, 1);
  EXPECT_EQ(s.counts.false_positives, 1);
  EXPECT_EQ(s.counts.misses, 0);
  EXPECT_EQ(s.counts.frames, 1);
  ASSERT_EQ(s.truth_of_detection.size(), 2u);
  EXPECT_EQ(s.truth_of_detection[0], 0);
  EXPECT_EQ(s.truth_of_detection[1], -1);
  ASSERT_EQ(s.false_detections.size(), 1u);
  EXPECT_EQ(s.false_detections[0], 1);
  EXPECT_DOUBLE_EQ(s.counts.precision(), 0.5);
  EXPECT_DOUBLE_EQ(s.counts.recall(), 1.0);
}

TEST(DetectionScoring, TheGateIsStrict)
{
  // 0.5 m away exactly: outside a 0.5 m gate, inside a 0.51 m one.
  EXPECT_EQ(scoreFrame({ { 3.5f, 0.0f } }, { person(3.0f, 0.0f) }, 0.5f).counts.misses, 1);
  EXPECT_EQ(scoreFrame({ { 3.5f, 0.0f } }, { person(3.0f, 0.0f) }, 0.51f).counts.true_positives, 1);
}

TEST(DetectionScoring, TwoDetectionsOfOnePersonMakeOneFalse)
{
  const FrameScore s = scoreFrame({ { 3.3f, 0.0f }, { 3.1f, 0.0f } }, { person(3.0f, 0.0f) }, 0.5f);
  EXPECT_EQ(s.counts.true_positives, 1);
  EXPECT_EQ(s.counts.false_positives, 1);
  // The nearer one is the match.
  EXPECT_EQ(s.truth_of_detection[1], 0);
  EXPECT_EQ(s.truth_of_detection[0], -1);
}

TEST(DetectionScoring, NearestPairsFirstNotDetectionOrder)
{
  // Detection 0 lies between both people, detection 1 right on person 0: greedy in detection order
  // would give d0-p0 and leave d1 unmatched; nearest first gives d1-p0, d0-p1.
  const FrameScore s = scoreFrame({ { 0.3f, 0.0f }, { 0.0f, 0.0f } }, { person(0.0f, 0.0f), person(0.6f, 0.0f) }, 0.5f);
  EXPECT_EQ(s.counts.true_positives, 2);
  EXPECT_EQ(s.counts.false_positives, 0);
  EXPECT_EQ(s.truth_of_detection[1], 0);
  EXPECT_EQ(s.truth_of_detection[0], 1);
}

TEST(DetectionScoring, PeopleNotRequiredNeitherCountNorMiss)
{
  const FrameScore s = scoreFrame({ { 1.0f, 1.0f } }, { person(1.0f, 1.1f, false), person(5.0f, 0.0f, false) }, 0.5f);
  EXPECT_EQ(s.counts.true_positives, 0);
  EXPECT_EQ(s.counts.false_positives, 0);
  EXPECT_EQ(s.counts.misses, 0);
  EXPECT_EQ(s.counts.ignored, 1);
  EXPECT_TRUE(std::isnan(s.counts.precision()));
  EXPECT_TRUE(std::isnan(s.counts.recall()));
}

TEST(DetectionScoring, MissesListTheRequiredPeopleNotFound)
{
  const FrameScore s = scoreFrame({}, { person(1.0f, 0.0f), person(2.0f, 0.0f, false), person(3.0f, 0.0f) }, 0.5f);
  EXPECT_EQ(s.counts.misses, 2);
  ASSERT_EQ(s.missed.size(), 2u);
  EXPECT_EQ(s.missed[0], 0);
  EXPECT_EQ(s.missed[1], 2);
  EXPECT_DOUBLE_EQ(s.counts.recall(), 0.0);
}

TEST(DetectionScoring, CountsAddUp)
{
  DetectionCounts a, b;
  a.true_positives = 9;
  a.false_positives = 1;
  a.frames = 10;
  b.true_positives = 1;
  b.misses = 3;
  b.ignored = 2;
  b.frames = 5;
  a += b;
  EXPECT_EQ(a.true_positives, 10);
  EXPECT_EQ(a.false_positives, 1);
  EXPECT_EQ(a.misses, 3);
  EXPECT_EQ(a.ignored, 2);
  EXPECT_EQ(a.frames, 15);
  EXPECT_DOUBLE_EQ(a.precision(), 10.0 / 11.0);
  EXPECT_DOUBLE_EQ(a.recall(), 10.0 / 13.0);
}

TEST(DetectionScoring, BadGateIsRefused)
{
  EXPECT_THROW(scoreFrame({}, {}, 0.0f), std::invalid_argument);
  EXPECT_THROW(scoreFrame({}, {}, std::nanf("")), std::invalid_argument);
}

TEST(DetectionScoring, BinLabels)
{
  const std::vector<double> edges = { 0.5, 0.9, 1.3, 1.8 };
  EXPECT_EQ(binLabel(0.5, edges), "0.5..0.9");
  EXPECT_EQ(binLabel(0.89, edges), "0.5..0.9");
  EXPECT_EQ(binLabel(0.9, edges), "0.9..1.3");
  EXPECT_EQ(binLabel(1.79, edges), "1.3..1.8");
  EXPECT_EQ(binLabel(1.8, edges), ">=1.8");
  EXPECT_EQ(binLabel(0.2, edges), "<0.5");
  EXPECT_EQ(binLabel(-5.0, { -20, -10, 0, 10 }, "%+.0f"), "-10..+0");
  EXPECT_THROW(binLabel(1.0, { 1.0 }), std::invalid_argument);
  EXPECT_THROW(binLabel(1.0, { 2.0, 1.0 }), std::invalid_argument);
}
