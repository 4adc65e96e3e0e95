// The benchmark's own parts: timing statistics, the octree baseline (it must compute the same
// flow as the core, or comparing their speed means nothing) and the generated descriptor sequences.
#include "../core/clouds.h"
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

TEST(OctreeFlowBaseline, FindsTheSameFlowAsTheCore)
{
  FlowParams params;
  const FlowEstimator ours(params);
  const OctreeFlowBaseline base(params, 0.04);
  std::size_t same = 0, total = 0;
  // A body of 0.02 m voxels whose upper part (an arm) moves fast and the rest a little, with noise.
  Cloud body = test::texturedBlock(10, 40, 6), arm = test::texturedBlock(4, 12, 3, Eigen::Vector3f(0.25f, -0.4f, 2));
  for (int i = 0; i < 3; ++i)
  {
    const double t0 = i / 10.0, t1 = t0 + 1.0 / 30;
    Cloud c0 = test::noisy(body, 0.003f, 6, 3 * i) + test::noisy(arm, 0.003f, 6, 3 * i + 1);
    Cloud c1 = test::noisy(test::shifted(body, Eigen::Vector3f(0.002f, 0, 0)), 0.003f, 6, 3 * i + 2) +
               test::noisy(test::shifted(arm, Eigen::Vector3f(0.05f, 0.02f, 0)), 0.003f, 6, 3 * i + 3);
    const FlowFrame a(c0, t0), b(c1, t1);
    const auto fa = base.prepare(c0, t0), fb = base.prepare(c1, t1);
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
