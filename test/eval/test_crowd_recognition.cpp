// Which track's descriptors recognition reads for one person's action in a crowd
// (evaluate --protocol crowd): matching tracks to people frame by frame, and the rows of the track
// that followed the person longest, on hand-made scenes with worked-out answers.
#include "../../src/eval/crowd_recognition.h"

#include <gtest/gtest.h>

#include <stdexcept>

using namespace action_flow;

namespace
{
TrackPoint at(std::uint32_t id, float x, bool ignored = false)
{
  TrackPoint p;
  p.id = id;
  p.position = Eigen::Vector2f(x, 0.0f);
  p.ignored = ignored;
  return p;
}

/** Rows of every track: row r of track t has descriptor value 100 t + r and the frame's stamp. */
SampleFrames rowsOf(const std::vector<std::pair<std::uint32_t, double>>& track_stamp)
{
  SampleFrames s;
  s.descriptors.resize(Eigen::Index(track_stamp.size()), 2);
  for (std::size_t r = 0; r < track_stamp.size(); ++r)
  {
    s.descriptors.row(Eigen::Index(r)) << float(100 * track_stamp[r].first + r), 1.0f;
    s.tracks.push_back(track_stamp[r].first);
    s.stamps.push_back(track_stamp[r].second);
  }
  return s;
}
}  // namespace

TEST(CrowdRecognition, MatchesFollowTheGateAndKeepATrackOnAHiddenPerson)
{
  // Person 1 at x = 0 followed by track 5; person 2 at x = 2 by track 8, which in frame 1 is 0.7 m
  // off (outside the 0.5 m gate) and in frame 2 follows person 2 while they are hidden (ignored).
  std::vector<TrackingFrame> frames(3);
  frames[0].truth = { at(1, 0.0f), at(2, 2.0f) };
  frames[0].predicted = { at(8, 2.1f), at(5, 0.1f) };
  frames[1].truth = { at(1, 0.0f), at(2, 2.0f) };
  frames[1].predicted = { at(5, 0.0f), at(8, 2.7f) };
  frames[2].truth = { at(1, 0.0f), at(2, 2.0f, true) };
  frames[2].predicted = { at(5, 0.0f), at(8, 2.0f) };
  const auto m = matchTracking(frames, 0.5f);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0], (std::vector<int>{ 1, 0 }));
  EXPECT_EQ(m[1], (std::vector<int>{ 0, -1 }));
  EXPECT_EQ(m[2], (std::vector<int>{ 0, 1 }));

  const TrackedScene scene = trackScene(frames, { 0.0, 0.1, 0.2 }, 0.5f);
  ASSERT_EQ(scene.track_of.size(), 3u);
  EXPECT_EQ(scene.track_of[0].at(1), 5u);
  EXPECT_EQ(scene.track_of[0].at(2), 8u);
  EXPECT_EQ(scene.track_of[1].count(2), 0u);
  EXPECT_EQ(scene.track_of[2].at(2), 8u);
  EXPECT_THROW(trackScene(frames, { 0.0, 0.1 }, 0.5f), std::invalid_argument);
}

TEST(CrowdRecognition, ASegmentReadsTheTrackThatFollowedThePersonLongest)
{
  // Person 1 over frames 0..4 (stamps 0..0.4): track 3 in frames 0, 1; track 4 in frames 2, 3, 4.
  TrackedScene scene;
  scene.stamps = { 0.0, 0.1, 0.2, 0.3, 0.4, 0.5 };
  scene.track_of = { { { 1, 3 } }, { { 1, 3 } }, { { 1, 4 } }, { { 1, 4 } }, { { 1, 4 } }, { { 1, 4 }, { 2, 6 } } };
  // Rows: track 4 from 0.1 to 0.5, track 3 at 0.0 and 0.1, track 6 at 0.5.
  const SampleFrames rows = rowsOf({ { 3, 0.0 }, { 3, 0.1 }, { 4, 0.1 }, { 4, 0.2 }, { 4, 0.3 }, { 4, 0.4 },
                                     { 4, 0.5 }, { 6, 0.5 } });
  SampleFrames out;
  EXPECT_EQ(segmentFrames(rows, scene, { 1, "wave", 0, 4 }, out), 4u);
  // Track 4's rows inside 0.0..0.4: rows 2..5 (the row at 0.5 is after the segment).
  ASSERT_EQ(out.descriptors.rows(), 4);
  EXPECT_EQ(out.descriptors(0, 0), 402.0f);
  EXPECT_EQ(out.descriptors(3, 0), 405.0f);
  EXPECT_EQ(out.stamps, (std::vector<double>{ 0.1, 0.2, 0.3, 0.4 }));
  EXPECT_TRUE(out.tracks.empty()) << "one performer's rows";

  // A tie (two frames each) goes to the lower id.
  EXPECT_EQ(segmentFrames(rows, scene, { 1, "wave", 0, 3 }, out), 3u);
  EXPECT_EQ(out.descriptors.rows(), 2);
  // Person 2 is followed only in frame 5.
  EXPECT_EQ(segmentFrames(rows, scene, { 2, "kick", 5, 5 }, out), 6u);
  EXPECT_EQ(out.descriptors.rows(), 1);
  EXPECT_EQ(out.descriptors(0, 0), 607.0f);
  // Nobody followed person 2 in frames 0..4: no track, no rows.
  EXPECT_EQ(segmentFrames(rows, scene, { 2, "kick", 0, 4 }, out), 0u);
  EXPECT_EQ(out.descriptors.rows(), 0);
  EXPECT_EQ(out.descriptors.cols(), 2);
}

TEST(CrowdRecognition, SegmentsOutsideTheSceneAndRowsWithoutTracksAreRefused)
{
  TrackedScene scene;
  scene.stamps = { 0.0, 0.1 };
  scene.track_of = { { { 1, 3 } }, { { 1, 3 } } };
  const SampleFrames rows = rowsOf({ { 3, 0.0 }, { 3, 0.1 } });
  SampleFrames out;
  EXPECT_THROW(segmentFrames(rows, scene, { 1, "wave", 0, 2 }, out), std::invalid_argument);
  EXPECT_THROW(segmentFrames(rows, scene, { 1, "wave", -1, 1 }, out), std::invalid_argument);
  EXPECT_THROW(segmentFrames(rows, scene, { 1, "wave", 1, 0 }, out), std::invalid_argument);
  SampleFrames no_tracks = rows;
  no_tracks.tracks.clear();
  EXPECT_THROW(segmentFrames(no_tracks, scene, { 1, "wave", 0, 1 }, out), std::invalid_argument);
}
