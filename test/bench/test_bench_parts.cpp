// The benchmark's own parts: timing statistics, the generated person, the octree baseline (it
// must compute the same flow as the core, or comparing their speed means nothing) and the
// generated descriptor sequences.
#include "../../src/bench/moving_person.h"
#include "../../src/bench/octree_flow_baseline.h"
#include "../../src/bench/stage_stats.h"
#include "../../src/bench/training_set.h"

#include <action_flow/flow_estimator.h>

#include <gtest/gtest.h>

#include <set>

using namespace action_flow;
using namespace action_flow::bench;

TEST(StageSamples, NearestRankPercentiles)
{
  StageSamples s;
  EXPECT_THROW(s.median(), std::logic_error);
  for (int v : { 7, 1, 3, 9, 5 })
    s.add(v);
  EXPECT_EQ(s.median(), 5.0);
  EXPECT_EQ(s.percentile(0.2), 1.0);
  EXPECT_EQ(s.percentile(0.21), 3.0);
  EXPECT_EQ(s.p95(), 9.0);
  StageSamples h;
  for (int v = 100; v >= 1; --v)
    h.add(v);
  EXPECT_EQ(h.median(), 50.0);  // lower median of an even count
  EXPECT_EQ(h.p95(), 95.0);
  EXPECT_EQ(h.percentile(1.0), 100.0);
  EXPECT_THROW(h.percentile(0.0), std::invalid_argument);
}

TEST(MovingPerson, RendersAPersonWhoseArmMoves)
{
  const MovingPerson person;
  Cloud full;
  std::vector<std::uint8_t> mask;
  person.render(0, full, &mask);
  ASSERT_EQ(full.width, 640u);
  ASSERT_EQ(full.height, 480u);
  ASSERT_EQ(mask.size(), full.size());
  std::size_t person_pixels = 0, room_pixels = 0;
  for (std::size_t i = 0; i < full.size(); ++i)
  {
    if (!std::isfinite(full.points[i].z))
      continue;
    (mask[i] ? person_pixels : room_pixels)++;
    if (mask[i])
    {
      EXPECT_NEAR(full.points[i].z, 2.5f, 0.3f);
    }
  }
  // A 1.75 m person at 2.5 m fills a few percent of a VGA frame; the room the rest.
  EXPECT_GT(person_pixels, 10000u);
  EXPECT_LT(person_pixels, 40000u);
  EXPECT_GT(room_pixels, 200000u);

  // Without sensor noise, the flow between two frames is mostly on the waving right arm (x > 0.2 m),
  // not on the still body (its sway, 0.04 m/s at most, is below the 0.3 m/s threshold).
  MovingPersonParams exact;
  exact.depth_noise = 0.0f;
  exact.colour_noise = 0;
  const MovingPerson still(exact);
  const FlowFrame a(still.personCloud(5, 0.02f), still.stamp(5)), b(still.personCloud(6, 0.02f), still.stamp(6));
  const FlowResult r = FlowEstimator().estimate(a, b);
  ASSERT_GT(r.flow.size(), 20u);
  std::size_t arm_points = 0, on_arm = 0;
  for (std::size_t i = 0; i < b.size(); ++i)
    arm_points += b.point(i).x() > 0.2f;
  for (const auto& f : r.flow)
    on_arm += f.position.x() > 0.2f;
  // The arm is about a tenth of the points; a good part of it moves, and flow is far denser there
  // than on the body (where only matching noise from the slight sway and voxelisation remains).
  ASSERT_GT(arm_points, b.size() / 20);
  EXPECT_GT(on_arm, arm_points / 5);
  const double arm_density = static_cast<double>(on_arm) / arm_points;
  const double body_density = static_cast<double>(r.flow.size() - on_arm) / (b.size() - arm_points);
  EXPECT_GT(arm_density, 2.0 * body_density);
}

TEST(OctreeFlowBaseline, FindsTheSameFlowAsTheCore)
{
  const MovingPerson person;
  FlowParams params;
  const FlowEstimator ours(params);
  const OctreeFlowBaseline base(params, 0.04);
  std::size_t same = 0, total = 0;
  for (int i = 0; i < 3; ++i)
  {
    const Cloud c0 = person.personCloud(7 * i, 0.04f), c1 = person.personCloud(7 * i + 1, 0.04f);
    const FlowFrame a(c0, person.stamp(7 * i)), b(c1, person.stamp(7 * i + 1));
    const auto fa = base.prepare(c0, person.stamp(7 * i)), fb = base.prepare(c1, person.stamp(7 * i + 1));
    FlowStats so, sb;
    const auto mo = ours.correspond(a, b, so), mb = base.correspond(*fa, *fb, sb);
    std::set<std::pair<std::size_t, std::size_t>> in_base;
    for (const auto& m : mb)
      in_base.insert({ m.target, m.source });
    for (const auto& m : mo)
      same += in_base.count({ m.target, m.source });
    total += mo.size();
    EXPECT_NEAR(static_cast<double>(mo.size()), static_cast<double>(mb.size()), 0.01 * mo.size() + 1);
    // Downstream steps agree as well.
    const FlowVectors vo = ours.rejectOutliers(b, mo, FlowEstimator::velocities(a, b, mo, b.stamp() - a.stamp()), so);
    const FlowVectors vb = base.rejectOutliers(*fb, mb, base.velocities(*fa, *fb, mb), sb);
    EXPECT_NEAR(static_cast<double>(vo.size()), static_cast<double>(vb.size()), 0.02 * vo.size() + 2);
  }
  // Only exact ties in distance (voxel centroids rarely have any) may be ordered differently.
  ASSERT_GT(total, 500u);
  EXPECT_GT(same, total * 99 / 100);
  EXPECT_THROW(OctreeFlowBaseline(params, 0.0), std::invalid_argument);
}

TEST(TrainingSet, SequencesAreNormalisedAndLabelled)
{
  const auto seqs = makeSequences(30, 15, 192, 3);
  ASSERT_EQ(seqs.size(), 30u);
  EXPECT_EQ(seqs[0].label, seqs[15].label);
  EXPECT_NE(seqs[0].label, seqs[1].label);
  for (const auto& s : seqs)
  {
    ASSERT_EQ(s.frames.size(), s.stamps.size());
    EXPECT_GE(s.frames.size(), 40u);
    for (const auto& f : s.frames)
    {
      ASSERT_EQ(f.size(), 192);
      EXPECT_NEAR(f.norm(), 1.0f, 1e-4f);
    }
  }
  EXPECT_THROW(makeSequences(0, 15, 192, 1), std::invalid_argument);
  EXPECT_THROW(makeSequences(10, 15, 190, 1), std::invalid_argument);
}
