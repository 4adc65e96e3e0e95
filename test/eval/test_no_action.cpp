// The no-action windows that teach an online model what transitions and idle periods look like:
// known windows on a hand-built stream, never across tracks, capped evenly, bad settings refused.
#include "../../src/eval/no_action.h"

#include <gtest/gtest.h>

using namespace action_flow;

namespace
{
// 10 s at 10 Hz, one track (or two taking turns), each row's value its track.
SampleFrames stream(bool two_tracks = false)
{
  SampleFrames s;
  const int n = two_tracks ? 200 : 100;
  s.descriptors.resize(n, 1);
  for (int i = 0; i < n; ++i)
  {
    const std::uint32_t track = two_tracks ? 1 + i % 2 : 1;
    s.descriptors(i, 0) = static_cast<float>(track);
    s.stamps.push_back((two_tracks ? i / 2 : i) / 10.0);
    if (two_tracks)
      s.tracks.push_back(track);
  }
  return s;
}

const std::vector<TruthSegment> kTruth = { { "wave", 2.0, 4.0 }, { "kick", 6.0, 8.0 } };

NoActionWindows windows(std::vector<double> lengths, int per_stream = 100)
{
  NoActionWindows w;
  w.lengths = std::move(lengths);
  w.per_stream = per_stream;
  return w;
}
}  // namespace

TEST(NoActionWindows, KnownWindowsLieOutsideTheActions)
{
  // 1.5 s windows every 0.5 s with at most 0.375 s inside an action: those starting at 0, 0.5
  // (before wave), 4, 4.5 (between the two) and 8 (after kick; 8.5 would run past the last frame).
  const auto found = noActionWindows(kTruth, stream(), windows({ 1.5 }));
  ASSERT_EQ(found.size(), 5u);
  const std::vector<double> starts = { 0.0, 0.5, 4.0, 4.5, 8.0 };
  for (std::size_t k = 0; k < found.size(); ++k)
  {
    EXPECT_DOUBLE_EQ(found[k].stamps.front(), starts[k]);
    EXPECT_DOUBLE_EQ(found[k].stamps.back(), starts[k] + 1.5);
    EXPECT_EQ(found[k].descriptors.rows(), 16);
    EXPECT_TRUE(found[k].tracks.empty());
  }
  // No 3 s window fits between or around the actions with at most 0.75 s inside one.
  EXPECT_TRUE(noActionWindows(kTruth, stream(), windows({ 3.0 })).empty());
  // Without any action every window of the stream is one: 1 + (9.9 - 3) / 0.5 of them.
  EXPECT_EQ(noActionWindows({}, stream(), windows({ 3.0 })).size(), 14u);
}

TEST(NoActionWindows, NeverMixTracksAndAreCappedEvenly)
{
  const auto found = noActionWindows(kTruth, stream(true), windows({ 1.5 }));
  ASSERT_EQ(found.size(), 10u);  // five of each track
  for (const auto& w : found)
    EXPECT_TRUE((w.descriptors.array() == w.descriptors(0, 0)).all()) << "a window mixes tracks";
  // Two of the five of one track: the second and the fourth (evenly spread).
  const auto two = noActionWindows(kTruth, stream(), windows({ 1.5 }, 2));
  ASSERT_EQ(two.size(), 2u);
  EXPECT_DOUBLE_EQ(two[0].stamps.front(), 0.5);
  EXPECT_DOUBLE_EQ(two[1].stamps.front(), 4.5);
  EXPECT_TRUE(noActionWindows(kTruth, stream(), windows({ 1.5 }, 0)).empty());
}

TEST(NoActionWindows, GapsInTheTrackMakeNoWindow)
{
  // The track is lost from 0.3 to 1.4 s: the windows at 0 and 0.5 no longer span 80% of 1.5 s.
  SampleFrames s = stream(), kept;
  std::vector<Eigen::Index> rows;
  for (Eigen::Index r = 0; r < s.descriptors.rows(); ++r)
    if (s.stamps[static_cast<std::size_t>(r)] < 0.3 || s.stamps[static_cast<std::size_t>(r)] > 1.4)
      rows.push_back(r);
  kept.descriptors.resize(static_cast<Eigen::Index>(rows.size()), 1);
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    kept.descriptors(static_cast<Eigen::Index>(i), 0) = 1.0f;
    kept.stamps.push_back(s.stamps[static_cast<std::size_t>(rows[i])]);
  }
  const auto found = noActionWindows(kTruth, kept, windows({ 1.5 }));
  ASSERT_EQ(found.size(), 3u);
  EXPECT_DOUBLE_EQ(found[0].stamps.front(), 4.0);
}

TEST(NoActionWindows, RefusesBadSettings)
{
  NoActionWindows w;
  w.step = 0.0;
  EXPECT_THROW(noActionWindows(kTruth, stream(), w), std::invalid_argument);
  w = NoActionWindows();
  w.lengths = { -1.0 };
  EXPECT_THROW(noActionWindows(kTruth, stream(), w), std::invalid_argument);
  w = NoActionWindows();
  w.max_action_share = 1.5;
  EXPECT_THROW(noActionWindows(kTruth, stream(), w), std::invalid_argument);
  SampleFrames bad = stream();
  bad.stamps.pop_back();
  EXPECT_THROW(noActionWindows(kTruth, bad, NoActionWindows()), std::invalid_argument);
}

TEST(ActionWindows, KnownWindowsHoldOneWholeAction)
{
  // 3 s windows every 0.5 s holding at least 1.6 s of a 2 s action and at most 0.3 s of another:
  // wave from 1, 1.5 and 2; kick from 5, 5.5 and 6 (6.5 would hold only 1.5 s of kick).
  ActionWindows w;
  w.per_stream = 100;
  const auto found = actionWindows(kTruth, stream(), w);
  ASSERT_EQ(found.size(), 6u);
  const std::vector<std::pair<std::string, double>> expected = { { "wave", 1.0 }, { "wave", 1.5 }, { "wave", 2.0 },
                                                                 { "kick", 5.0 }, { "kick", 5.5 }, { "kick", 6.0 } };
  for (std::size_t k = 0; k < found.size(); ++k)
  {
    EXPECT_EQ(found[k].label, expected[k].first);
    EXPECT_NEAR(found[k].frames.stamps.front(), expected[k].second, 1e-9);
    EXPECT_NEAR(found[k].frames.stamps.back(), expected[k].second + 3.0, 1e-9);
    EXPECT_EQ(found[k].frames.descriptors.rows(), 31);
  }
  // Capped at 2: spread evenly, one of each.
  w.per_stream = 2;
  const auto two = actionWindows(kTruth, stream(), w);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].label, "wave");
  EXPECT_NEAR(two[0].frames.stamps.front(), 1.5, 1e-9);
  EXPECT_EQ(two[1].label, "kick");
  EXPECT_NEAR(two[1].frames.stamps.front(), 5.5, 1e-9);
  // An action of 4 s never fits 80 % of itself into a 3 s window.
  EXPECT_TRUE(actionWindows({ { "wave", 2.0, 6.0 } }, stream(), ActionWindows()).empty());
  // With 0.5 s between two actions and none of the other allowed, only windows that touch neither
  // neighbour: wave from 1.0 and 1.5 (to 4.5, where kick starts), kick from 4.0 (where wave ends) and 4.5.
  w = ActionWindows();
  w.max_other_share = 0.0;
  w.per_stream = 100;
  const auto tight = actionWindows({ { "wave", 2.0, 4.0 }, { "kick", 4.5, 6.5 } }, stream(), w);
  ASSERT_EQ(tight.size(), 4u);
  const std::vector<double> tight_starts = { 1.0, 1.5, 4.0, 4.5 };
  for (std::size_t k = 0; k < tight.size(); ++k)
  {
    EXPECT_EQ(tight[k].label, k < 2 ? "wave" : "kick");
    EXPECT_NEAR(tight[k].frames.stamps.front(), tight_starts[k], 1e-9);
  }
  EXPECT_TRUE(actionWindows({}, stream(), ActionWindows()).empty());
}

TEST(ActionWindows, RefusesBadSettings)
{
  ActionWindows w;
  w.length = 0.0;
  EXPECT_THROW(actionWindows(kTruth, stream(), w), std::invalid_argument);
  w = ActionWindows();
  w.max_other_share = 1.5;
  EXPECT_THROW(actionWindows(kTruth, stream(), w), std::invalid_argument);
  SampleFrames bad = stream();
  bad.stamps.pop_back();
  EXPECT_THROW(actionWindows(kTruth, bad, ActionWindows()), std::invalid_argument);
}
