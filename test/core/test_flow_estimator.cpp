// Known-answer tests of the 3D flow (the paper's steps 1-4).
#include "clouds.h"

#include <action_flow/flow_estimator.h>
#include <action_flow/person_pipeline.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

using namespace action_flow;
using namespace action_flow::test;

namespace
{
constexpr double kDt = 1.0 / 30.0;  // a Kinect frame

FlowResult flowBetween(const Cloud& a, const Cloud& b, const FlowParams& params = FlowParams(), double dt = kDt)
{
  FlowFrame source(a, 10.0), target(b, 10.0 + dt);
  return FlowEstimator(params).estimate(source, target);
}
}  // namespace

TEST(Hsv, ConvertsPrimariesAndWrapsHue)
{
  const Hsv red = rgbToHsv(255, 0, 0), green = rgbToHsv(0, 255, 0), blue = rgbToHsv(0, 0, 255);
  EXPECT_FLOAT_EQ(red.h, 0.0f);
  EXPECT_NEAR(green.h, 1.0f / 3, 1e-6);
  EXPECT_NEAR(blue.h, 2.0f / 3, 1e-6);
  EXPECT_FLOAT_EQ(red.s, 1.0f);
  EXPECT_FLOAT_EQ(red.v, 1.0f);
  // Hue 0.95 is as near hue 0.05 (across the wrap) as 0.45 is to 0.55: a chord of 0.1 turn at chroma 0.25.
  const float chord = 2 * 0.25f * std::sin(3.14159265f * 0.1f);
  EXPECT_NEAR(hsvDistance({ 0.95f, 0.5f, 0.5f }, { 0.05f, 0.5f, 0.5f }), chord, 1e-5);
  EXPECT_NEAR(hsvDistance({ 0.45f, 0.5f, 0.5f }, { 0.55f, 0.5f, 0.5f }), chord, 1e-5);
  EXPECT_GT(hsvDistance({ 0.05f, 0.5f, 0.5f }, { 0.5f, 0.5f, 0.5f }), 3 * chord);
  // Hue hardly matters for a nearly grey pixel: its hue is noise.
  EXPECT_LT(hsvDistance({ 0.0f, 0.02f, 0.5f }, { 0.5f, 0.02f, 0.5f }), 0.025f);
  EXPECT_NEAR(hsvDistance({ 0.2f, 0.0f, 0.5f }, { 0.2f, 0.0f, 0.1f }), 0.4f, 1e-6);
}

// A rigid shift of a textured cloud: every surviving point moves by exactly d / dt.
TEST(FlowEstimator, RigidShiftGivesTheShiftOverDt)
{
  const Cloud source = texturedBlock(10, 10, 10);
  const Eigen::Vector3f d(0.03f, -0.01f, 0.015f);  // 1.05 m/s, well inside the K=50 neighbourhood
  const FlowResult r = flowBetween(source, shifted(source, d));
  const Eigen::Vector3f expected = d / kDt;
  // Coordinates are floats around 2 m: rounding is ~2e-7 m per coordinate, i.e. ~1e-5 m/s after
  // dividing by dt; 1e-3 m/s leaves ample room and still catches any wrong match (>= 0.6 m/s off).
  ASSERT_EQ(r.stats.kept, source.size()) << "every point has its exact match";
  for (const auto& f : r.flow)
    EXPECT_LT((f.velocity - expected).norm(), 1e-3f);
  EXPECT_EQ(r.stats.removed_reciprocal, 0u);
  EXPECT_NEAR(r.dt, kDt, 1e-12);
}

// A limb rotating about its shoulder: flow is tangential with speed omega * radius.
TEST(FlowEstimator, RotatingLimbGivesTangentialFlow)
{
  const Eigen::Vector3f pivot(0, 0, 2);
  const Cloud limb = texturedBlock(30, 3, 3, pivot);  // 0.6 m along x
  const float omega = 3.0f;                            // rad/s about z: the tip moves at 1.7 m/s
  const Eigen::Matrix3f rot = Eigen::AngleAxisf(omega * kDt, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  Cloud moved = limb;
  for (auto& p : moved.points)
    p.getVector3fMap() = pivot + rot * (p.getVector3fMap() - pivot);
  const FlowResult r = flowBetween(limb, moved);
  ASSERT_GT(r.flow.size(), limb.size() / 2);
  // The chord over dt lags the tangent at the end point by half the rotation angle.
  const float half_angle = 0.5f * omega * kDt;
  for (const auto& f : r.flow)
  {
    Eigen::Vector3f radius = f.position - pivot;
    radius.z() = 0.0f;  // distance from the rotation axis
    const Eigen::Vector3f tangent = Eigen::Vector3f::UnitZ().cross(radius).normalized();
    const float speed = f.velocity.norm();
    EXPECT_NEAR(speed, omega * radius.norm(), 0.01f * omega * radius.norm());
    EXPECT_GT(f.velocity.dot(tangent) / speed, std::cos(half_angle) - 1e-3f);
  }
  // Points near the pivot move slower than 0.3 m/s and are dropped.
  EXPECT_GT(r.stats.removed_slow, 0u);
  for (const auto& f : r.flow)
    EXPECT_GE(omega * (f.position - pivot).head<2>().norm(), 0.3f - 0.01f);
}

// Two target points want the same source point; only the one it wants back survives.
TEST(FlowEstimator, ReciprocalCheckRemovesAmbiguousMatch)
{
  Cloud source, target;
  PointT a;
  a.getVector3fMap() = Eigen::Vector3f(0, 0, 2);
  a.r = 200, a.g = 30, a.b = 30;
  source.push_back(a);
  PointT exact = a, similar = a;
  exact.getVector3fMap() = Eigen::Vector3f(0.03f, 0, 2);
  similar.getVector3fMap() = Eigen::Vector3f(0.02f, 0.01f, 2);
  similar.r = 190;  // a slightly different red: A prefers 'exact'
  target.push_back(similar);
  target.push_back(exact);

  FlowParams loose;
  loose.reciprocal = false;
  loose.reject_outliers = false;
  EXPECT_EQ(flowBetween(source, target, loose).flow.size(), 2u);

  FlowParams strict = loose;
  strict.reciprocal = true;
  const FlowResult r = flowBetween(source, target, strict);
  ASSERT_EQ(r.flow.size(), 1u);
  EXPECT_EQ(r.stats.removed_reciprocal, 1u);
  EXPECT_TRUE(r.flow[0].position.isApprox(exact.getVector3fMap()));
}

// A still person seen through sensor noise: the thresholds leave no flow.
TEST(FlowEstimator, StaticNoisyCloudYieldsNoFlow)
{
  const Cloud base = texturedBlock(12, 12, 6);
  // 2 mm is the Kinect's depth noise at about 1.2 m (1.425e-3 z^2); 2 colour levels of sensor noise.
  const Cloud a = noisy(base, 0.002f, 2, 1), b = noisy(base, 0.002f, 2, 2);
  FlowParams raw;
  raw.reject_outliers = false;
  const FlowResult unfiltered = flowBetween(a, b, raw);
  EXPECT_GT(unfiltered.flow.size(), base.size() / 2) << "noise alone produces many small vectors";
  const FlowResult r = flowBetween(a, b);
  EXPECT_EQ(r.flow.size(), 0u);
  EXPECT_GT(r.stats.removed_slow, base.size() / 2);
}

// One fast point among still ones is isolated and removed; two fast neighbours support each other.
TEST(FlowEstimator, IsolationRuleRemovesLoneFastPoint)
{
  const Cloud still = texturedBlock(8, 8, 4);
  PointT fast;
  fast.getVector3fMap() = Eigen::Vector3f(0.07f, 0.07f, 1.9f);  // just in front of the block
  fast.r = 250, fast.g = 250, fast.b = 0;
  Cloud a = still, b = still;
  a.push_back(fast);
  fast.y += 0.04f;  // 1.2 m/s
  b.push_back(fast);

  const FlowResult lone = flowBetween(a, b);
  EXPECT_EQ(lone.flow.size(), 0u);
  EXPECT_EQ(lone.stats.removed_isolated, 1u);

  FlowParams no_rules;
  no_rules.reject_outliers = false;
  const FlowResult kept = flowBetween(a, b, no_rules);
  EXPECT_EQ(kept.flow.size(), a.size());

  // A second fast point 0.02 m away (within neighbour_radius): both are kept.
  PointT mate = fast;
  mate.x += 0.02f;
  mate.r = 0, mate.g = 250, mate.b = 250;
  mate.y -= 0.04f;
  a.push_back(mate);
  mate.y += 0.04f;
  b.push_back(mate);
  const FlowResult pair = flowBetween(a, b);
  EXPECT_EQ(pair.flow.size(), 2u);
  EXPECT_EQ(pair.stats.removed_isolated, 0u);
}

TEST(FlowEstimator, BadInputGivesDefinedResultsOrClearErrors)
{
  const Cloud block = texturedBlock(5, 5, 5);
  const Cloud empty;
  EXPECT_EQ(flowBetween(empty, block).flow.size(), 0u);
  EXPECT_EQ(flowBetween(block, empty).flow.size(), 0u);

  // NaN points are ignored: the same result as without them.
  Cloud with_nan = block;
  PointT nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  with_nan.push_back(nan);
  with_nan.points.insert(with_nan.points.begin(), nan);
  const Eigen::Vector3f d(0.03f, 0, 0);
  const FlowResult clean = flowBetween(block, shifted(block, d));
  const FlowResult dirty = flowBetween(with_nan, shifted(with_nan, d));
  EXPECT_EQ(dirty.flow.size(), clean.flow.size());
  EXPECT_EQ(dirty.stats.source_points, block.size());
  for (const auto& f : dirty.flow)
    EXPECT_TRUE(f.velocity.allFinite());
  Cloud all_nan;
  all_nan.push_back(nan);
  EXPECT_EQ(flowBetween(all_nan, all_nan).flow.size(), 0u);

  // dt <= 0 is an error, not an infinite velocity.
  EXPECT_THROW(flowBetween(block, block, FlowParams(), 0.0), std::invalid_argument);
  EXPECT_THROW(flowBetween(block, block, FlowParams(), -0.1), std::invalid_argument);
  FlowParams bad;
  bad.k = 0;
  EXPECT_THROW(FlowEstimator{ bad }, std::invalid_argument);
}

TEST(FlowTrack, ResetsWhenTimeGoesBackwardsOrJumps)
{
  const Cloud block = texturedBlock(6, 6, 6);
  const Eigen::Vector3f d(0.03f, 0, 0);
  FlowTrack track;
  EXPECT_EQ(track.add(block, 1.0).status, FlowTrack::Status::First);
  const auto step = track.add(shifted(block, d), 1.0 + kDt);
  EXPECT_EQ(step.status, FlowTrack::Status::Flow);
  EXPECT_EQ(step.result.flow.size(), block.size());
  // A bag looping: time goes back. No throw, no flow, then flow again from the new start.
  EXPECT_EQ(track.add(block, 0.5).status, FlowTrack::Status::Reset);
  EXPECT_EQ(track.add(shifted(block, d), 0.5 + kDt).status, FlowTrack::Status::Flow);
  // A gap longer than max_gap (1 s) restarts too; so does a repeated stamp.
  EXPECT_EQ(track.add(block, 5.0).status, FlowTrack::Status::Reset);
  EXPECT_EQ(track.add(block, 5.0).status, FlowTrack::Status::Reset);
}

// Several parameter sets in one PersonPipeline share the flow's matching; each set's descriptors
// must be exactly those of a pipeline of its own, including the set without outlier rejection.
TEST(PersonPipeline, VariantsSharingTheMatchingGiveTheirOwnDescriptors)
{
  RecognitionParams sum, mean, raw, other_k;
  sum.grid.aggregation = raw.grid.aggregation = other_k.grid.aggregation = FlowAggregation::Sum;
  mean.grid.aggregation = FlowAggregation::Mean;
  raw.flow.reject_outliers = false;
  other_k.flow.k = 10;
  const std::vector<RecognitionParams> sets = { sum, mean, raw, other_k };
  PersonPipeline shared(sets);
  std::vector<std::unique_ptr<PersonPipeline>> alone;
  for (const auto& s : sets)
    alone.push_back(std::make_unique<PersonPipeline>(s));

  // A still, noisy body (noise flow is what rejection removes) and a block moving across it.
  const Cloud body = texturedBlock(10, 20, 4, Eigen::Vector3f(-0.1f, -0.2f, 2.0f));
  const Cloud hand = texturedBlock(3, 3, 3, Eigen::Vector3f(0.2f, 0.0f, 1.9f));
  const PersonFrame where = PersonFrame::fromGround(Eigen::Vector3f(0, 0, 2), Eigen::Vector4f(0, -1, 0, 1), 1.75f,
                                                    Eigen::Vector3f(0, 0, 2));
  const double stamps[] = { 1.0, 1.0 + kDt, 1.0 + 2 * kDt, 1.0 + 3 * kDt, 0.5, 0.5 + kDt, 0.5 + 2 * kDt };
  for (int i = 0; i < 7; ++i)
  {
    Cloud frame = noisy(body, 0.003f, 2, static_cast<unsigned>(i + 1));
    frame += shifted(hand, Eigen::Vector3f(0.0f, 0.04f * i, 0.0f));
    shared.add(frame, stamps[i], where);
    for (auto& p : alone)
      p->add(frame, stamps[i], where);
  }
  ASSERT_EQ(shared.variants(), sets.size());
  for (std::size_t v = 0; v < sets.size(); ++v)
  {
    ASSERT_EQ(shared.descriptors(v).size(), 2u) << "set " << v << ": the time reset cleared the first three";
    EXPECT_EQ(shared.stamps(v), alone[v]->stamps());
    for (std::size_t f = 0; f < shared.descriptors(v).size(); ++f)
      EXPECT_EQ(shared.descriptors(v)[f], alone[v]->descriptors()[f]) << "set " << v << ", frame " << f;
  }
  EXPECT_NE(shared.descriptors(0)[0], shared.descriptors(2)[0]) << "rejection must change the SUMFLOW descriptor";
  EXPECT_NE(shared.descriptors(0)[0], shared.descriptors(3)[0]) << "K must change the SUMFLOW descriptor";
}
