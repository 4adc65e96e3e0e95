// Known-answer tests of the tracker's parts (assignment, motion model, ground, projection fit)
// and its handling of bad input and bad parameters.
#include "../core/scene.h"

#include <action_flow/people_tracker.h>
#include "../../src/tracker/tracker_appearance.h"
#include "../../src/tracker/tracker_assignment.h"
#include "../../src/tracker/tracker_clustering.h"
#include "../../src/tracker/tracker_detector.h"
#include "../../src/tracker/tracker_ground.h"

#include <gtest/gtest.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>
#include <set>

#include <cstdio>
#include <fstream>
#include <limits>
#include <random>

using namespace action_flow;

// ---- clustering ----------------------------------------------------------------------------

namespace
{
// Blobs of random sizes scattered in a room-sized box, some touching, plus NaN points: clusters
// that merge and split at the tolerance.
Cloud blobs(unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> room(-3.0f, 3.0f), spread(0.02f, 0.3f), unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  Cloud c;
  for (int b = 0; b < 40; ++b)
  {
    const Eigen::Vector3f centre(room(rng), room(rng) * 0.5f, room(rng) + 4.0f);
    const float s = spread(rng);
    const int n = 5 + static_cast<int>(unit(rng) * 200);
    for (int k = 0; k < n; ++k)
    {
      PointT p;
      p.getVector3fMap() = centre + s * Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng));
      c.push_back(p);
    }
  }
  for (int k = 0; k < 50; ++k)
  {
    PointT p;
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    c.insert(c.begin() + static_cast<long>(unit(rng) * c.size()), p);
  }
  c.is_dense = false;
  return c;
}

std::set<std::vector<int>> asSets(const std::vector<pcl::PointIndices>& clusters)
{
  std::set<std::vector<int>> out;
  for (const auto& c : clusters)
    out.insert(std::vector<int>(c.indices.begin(), c.indices.end()));
  return out;
}
}  // namespace

TEST(RadiusGrid, FindsExactlyThePointsWithinTheRadius)
{
  const Cloud cloud = blobs(3);
  RadiusGrid grid;
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> box(-4.0f, 4.0f);
  for (const float radius : {0.05f, 0.12f, 0.5f})
  {
    grid.build(cloud, radius);
    for (int q = 0; q < 300; ++q)
    {
      // Half the queries at points of the cloud, half anywhere (also outside the grid).
      const Eigen::Vector3f at = q % 2 && cloud[q].getVector3fMap().allFinite()
                                     ? Eigen::Vector3f(cloud[q].getVector3fMap())
                                     : Eigen::Vector3f(box(rng), box(rng), box(rng) + 4.0f);
      std::vector<std::uint32_t> found, expected;
      grid.forEachWithin(at, [&](std::uint32_t i) { found.push_back(i); });
      for (std::size_t i = 0; i < cloud.size(); ++i)
        if ((cloud[i].getVector3fMap() - at).squaredNorm() <= radius * radius)
          expected.push_back(static_cast<std::uint32_t>(i));
      std::sort(found.begin(), found.end());
      ASSERT_EQ(found, expected) << "radius " << radius << ", query " << q;
      EXPECT_EQ(grid.countWithin(at, 3), std::min<int>(3, static_cast<int>(expected.size())));
    }
  }
}

TEST(EuclideanClusters, SameClustersAsPcl)
{
  RadiusGrid grid;
  for (unsigned seed = 1; seed <= 5; ++seed)
  {
    const auto cloud = pcl::make_shared<Cloud>(blobs(seed));
    for (const float tolerance : {0.06f, 0.12f, 0.25f})
    {
      std::vector<pcl::PointIndices> reference;
      pcl::EuclideanClusterExtraction<PointT> ec;
      ec.setClusterTolerance(tolerance);
      ec.setMinClusterSize(10);
      ec.setMaxClusterSize(400);
      ec.setSearchMethod(pcl::make_shared<pcl::search::KdTree<PointT>>());
      ec.setInputCloud(cloud);
      auto finite = pcl::make_shared<pcl::Indices>();  // PCL's kd-tree refuses NaN queries
      for (std::size_t i = 0; i < cloud->size(); ++i)
        if ((*cloud)[i].getVector3fMap().allFinite())
          finite->push_back(static_cast<int>(i));
      ec.setIndices(finite);
      ec.extract(reference);
      const auto ours = euclideanClusters(*cloud, tolerance, 10, 400, grid);
      ASSERT_GT(reference.size(), 3u);
      EXPECT_EQ(asSets(ours), asSets(reference)) << "seed " << seed << ", tolerance " << tolerance;
      for (std::size_t k = 1; k < ours.size(); ++k)
        EXPECT_GE(ours[k - 1].indices.size(), ours[k].indices.size()) << "largest first";
    }
  }
}

// ---- assignment ----------------------------------------------------------------------------

TEST(Assignment, FindsTheMinimumCostAssignment)
{
  // Greedy (row by row, cheapest first) takes 0-0 (1), then pays 10 + 3; the optimum is 2 + 2 + 3.
  Eigen::MatrixXf c(3, 3);
  c << 1, 2, 10,  //
      2, 10, 10,  //
      10, 3, 3;
  const auto a = solveAssignment(c, 100.0f);
  ASSERT_EQ(a.size(), 3u);
  EXPECT_EQ(a[0], 2 - 1);  // row 0 -> column 1
  EXPECT_EQ(a[1], 0);
  EXPECT_EQ(a[2], 2);
}

TEST(Assignment, RectangularAndGated)
{
  Eigen::MatrixXf wide(2, 4);
  wide << 5, 1, 9, 9,  //
      5, 2, 9, 0.5f;
  EXPECT_EQ(solveAssignment(wide, 10.0f), (std::vector<int>{1, 3}));
  Eigen::MatrixXf tall = wide.transpose();  // 4 rows, 2 columns
  EXPECT_EQ(solveAssignment(tall, 10.0f), (std::vector<int>{-1, 0, -1, 1}));
  // Beyond the gate nothing is assigned.
  EXPECT_EQ(solveAssignment(wide, 0.4f), (std::vector<int>{-1, -1}));
  // As many pairs within the gate as possible: the cheap 0-1 (0.1) alone would leave row 1 out.
  Eigen::MatrixXf g(2, 2);
  g << 0.9f, 0.1f,  //
      5.0f, 0.5f;
  EXPECT_EQ(solveAssignment(g, 1.0f), (std::vector<int>{0, 1}));
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXf(0, 3), 1.0f).empty());
  EXPECT_EQ(solveAssignment(Eigen::MatrixXf(2, 0), 1.0f), (std::vector<int>{-1, -1}));
  Eigen::MatrixXf bad(1, 1);
  bad << std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(solveAssignment(bad, 1.0f), std::invalid_argument);
}

// ---- motion model --------------------------------------------------------------------------

TEST(ConstantVelocityFilter, LearnsAConstantVelocityAndPredicts)
{
  const Eigen::Vector3f v(1.0f, 0.0f, -0.5f);
  ConstantVelocityFilter f(Eigen::Vector3f(0, 0, 3));
  for (int k = 1; k <= 30; ++k)
  {
    f.predict(0.1);
    f.correct(Eigen::Vector3f(0, 0, 3) + 0.1f * k * v);
  }
  EXPECT_LT((f.velocity() - v).norm(), 0.02f);
  f.predict(0.5);
  EXPECT_LT((f.position() - (Eigen::Vector3f(0, 0, 3) + 3.5f * v)).norm(), 0.02f);
  const float sigma = f.positionSigma();
  f.predict(1.0);
  EXPECT_GT(f.positionSigma(), sigma) << "uncertainty grows while coasting";
  f.predict(0.0);
  f.predict(-1.0);  // no effect
  EXPECT_LT((f.position() - (Eigen::Vector3f(0, 0, 3) + 4.5f * v)).norm(), 0.02f);
}

// ---- appearance (re-identification) ------------------------------------------------------

namespace
{
Cloud colouredCloud(std::uint8_t r, std::uint8_t g, std::uint8_t b, int n, float x = 0.0f)
{
  Cloud c;
  for (int i = 0; i < n; ++i)
  {
    PointT p;
    p.x = x + 0.01f * i, p.y = 0.0f, p.z = 3.0f;
    p.r = r, p.g = g, p.b = b;
    c.push_back(p);
  }
  return c;
}
}  // namespace

TEST(Appearance, HistogramBinsChromaticityAndBrightnessByHand)
{
  // (200, 60, 60): r/sum = 0.625 -> bin 3 of 6, g/sum = 0.1875 -> bin 1; brightness 320/768 = 0.42
  // -> bin 1 of 4. Each half weighs 0.5.
  Cloud c = colouredCloud(200, 60, 60, 10);
  PointT nan;
  nan.x = nan.y = nan.z = std::numeric_limits<float>::quiet_NaN();
  c.push_back(nan);  // not counted
  const Appearance::Histogram h = Appearance::histogram(c);
  EXPECT_FLOAT_EQ(h.sum(), 1.0f);
  EXPECT_FLOAT_EQ(h(3 * 6 + 1), 0.5f);
  EXPECT_FLOAT_EQ(h(36 + 1), 0.5f);
  // Black points (sum below 30) count in brightness only: bin 0.
  const Appearance::Histogram black = Appearance::histogram(colouredCloud(5, 5, 5, 4));
  EXPECT_FLOAT_EQ(black(36), 1.0f);
  EXPECT_FLOAT_EQ(black.head<36>().sum(), 0.0f);
  // Half the points red, half green: each chroma bin 0.25.
  Cloud mixed = colouredCloud(200, 60, 60, 10);
  mixed += colouredCloud(60, 200, 60, 10);
  const Appearance::Histogram m = Appearance::histogram(mixed);
  EXPECT_FLOAT_EQ(m(3 * 6 + 1), 0.25f);
  EXPECT_FLOAT_EQ(m(1 * 6 + 3), 0.25f);
  EXPECT_FLOAT_EQ(Appearance::histogram(Cloud()).sum(), 0.0f);
}

TEST(Appearance, ColourDistanceIsHellinger)
{
  Appearance red, red2, green, half;
  red.add(colouredCloud(200, 60, 60, 10), 1.7f);
  red2.add(colouredCloud(200, 60, 60, 30, 1.0f), 1.8f);
  green.add(colouredCloud(60, 200, 60, 10), 1.7f);
  EXPECT_NEAR(red.colourDistance(red2), 0.0f, 1e-4f) << "the same colours, wherever and however many";
  // Same brightness bin, disjoint chroma bins: BC = 0.5, distance sqrt(0.5).
  EXPECT_NEAR(red.colourDistance(green), std::sqrt(0.5f), 1e-5f);
  EXPECT_NEAR(red.colourDistance(green), green.colourDistance(red), 1e-6f);
  EXPECT_FLOAT_EQ(red.colourDistance(Appearance()), 1.0f) << "never seen";
  // A running mean: red then green gives half of each, height the mean.
  half.add(colouredCloud(200, 60, 60, 10), 1.6f);
  half.add(colouredCloud(60, 200, 60, 10), 1.8f);
  EXPECT_EQ(half.frames(), 2);
  EXPECT_NEAR(half.height(), 1.7f, 1e-6f);
  EXPECT_NEAR(half.colours()(3 * 6 + 1), 0.25f, 1e-6f);
  // BC(red, half) = 0.5 (brightness) + sqrt(0.5 * 0.25) = 0.5 + 0.3536.
  EXPECT_NEAR(red.colourDistance(half), std::sqrt(1.0f - 0.5f - std::sqrt(0.125f)), 1e-5f);
}

// The histogram of some of a cloud's points (a weak detection's, every stride-th) and the distance
// of a track's appearance to one frame's histogram.
TEST(Appearance, HistogramOfIndicesAndDistanceToOneFrame)
{
  Cloud c = colouredCloud(200, 60, 60, 10);  // points 0-9 red
  c += colouredCloud(60, 200, 60, 10);       // 10-19 green
  pcl::Indices reds, every_other;
  for (int i = 0; i < 10; ++i)
    reds.push_back(i);
  for (int i = 0; i < 20; ++i)
    every_other.push_back(i);
  const Appearance::Histogram r = Appearance::histogram(c, reds);
  EXPECT_FLOAT_EQ(r(3 * 6 + 1), 0.5f) << "only the red points";
  EXPECT_FLOAT_EQ(r(1 * 6 + 3), 0.0f);
  // Every 3rd of 0..19: 0 3 6 9 red, 12 15 18 green: 4 of 7 red.
  const Appearance::Histogram s = Appearance::histogram(c, every_other, 3);
  EXPECT_NEAR(s(3 * 6 + 1), 0.5f * 4.0f / 7.0f, 1e-6f);
  EXPECT_NEAR(s(1 * 6 + 3), 0.5f * 3.0f / 7.0f, 1e-6f);
  EXPECT_FLOAT_EQ(Appearance::histogram(c, pcl::Indices()).sum(), 0.0f);
  Appearance red, green;
  red.add(colouredCloud(200, 60, 60, 10), 1.7f);
  green.add(colouredCloud(60, 200, 60, 10), 1.7f);
  EXPECT_NEAR(red.colourDistance(r), 0.0f, 1e-4f);
  EXPECT_NEAR(red.colourDistance(Appearance::histogram(colouredCloud(60, 200, 60, 10))), red.colourDistance(green), 1e-6f);
  EXPECT_FLOAT_EQ(red.colourDistance(Appearance::Histogram::Zero()), 1.0f) << "an empty frame";
}

// ---- ground --------------------------------------------------------------------------------

namespace
{
void addPlanePatch(Cloud& c, const Eigen::Vector3f& origin, const Eigen::Vector3f& u, const Eigen::Vector3f& v, int nu,
                   int nv, float step)
{
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
    {
      PointT p;
      p.getVector3fMap() = origin + u * (i * step) + v * (j * step);
      c.push_back(p);
    }
}
}  // namespace

TEST(GroundEstimator, PrefersTheFloorToABiggerTableTop)
{
  // Camera at the origin, y down; floor 1.2 m below, a 2 x 2.4 m table 0.45 m above the floor,
  // with more points than the floor around it.
  Cloud c;
  addPlanePatch(c, Eigen::Vector3f(-3, 1.2f, 1), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ(), 20, 40, 0.06f);
  addPlanePatch(c, Eigen::Vector3f(-1, 0.75f, 2), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ(), 34, 40, 0.06f);
  // Table legs reach the floor: something below the table top.
  for (float y = 0.75f; y < 1.2f; y += 0.06f)
    for (float x : {-1.0f, 1.0f})
      addPlanePatch(c, Eigen::Vector3f(x, y, 2), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitZ(), 2, 2, 0.06f);
  GroundEstimator g;
  ASSERT_TRUE(g.update(c, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
  EXPECT_FALSE(g.assumed());
  // (the legs' lowest points pull the least-squares fit a little)
  EXPECT_GT(-g.plane()[1], 0.9995f) << g.plane().transpose();
  EXPECT_NEAR(g.plane()[3], 1.2f, 0.015f);
}

TEST(GroundEstimator, TiltedFloorAndAFloorlessCloud)
{
  // A floor seen by a camera pitched down by 0.4 rad.
  const Eigen::Vector3f up(0, -std::cos(0.4f), -std::sin(0.4f));
  const Eigen::Vector3f a = Eigen::Vector3f::UnitX(), b = up.cross(a);
  Cloud c;
  addPlanePatch(c, -1.1f * up - 2.0f * a + 1.0f * b, a, b, 60, 60, 0.06f);
  GroundEstimator g;
  ASSERT_TRUE(g.update(c, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
  EXPECT_TRUE(g.plane().isApprox(Eigen::Vector4f(up.x(), up.y(), up.z(), 1.1f), 1e-3f)) << g.plane().transpose();
  EXPECT_EQ(g.searches(), 1);
  // The next frames refine the plane found instead of searching again.
  ASSERT_TRUE(g.update(c, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
  EXPECT_EQ(g.searches(), 1);

  // A single upright box floating in space: no floor, and no bottom level wide enough to assume one.
  Cloud box;
  addPlanePatch(box, Eigen::Vector3f(-0.2f, -0.5f, 3), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(), 7, 25, 0.06f);
  GroundEstimator none;
  EXPECT_FALSE(none.update(box, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
  EXPECT_FALSE(none.valid());
}

TEST(GroundEstimator, AssumesTheGroundBelowTheLowestPointsWhenNoFloorIsVisible)
{
  // Three upright boxes whose bottoms lie at y = 1.3 (a floor giving no depth), 2 m apart.
  Cloud c;
  for (float x : {-1.5f, 0.5f, 1.5f})
    addPlanePatch(c, Eigen::Vector3f(x, 0.0f, 3 + x), Eigen::Vector3f::UnitX(), Eigen::Vector3f::UnitY(), 5, 22, 0.06f);
  for (auto& p : c.points)
    p.y += 1.3f - 21 * 0.06f;
  GroundParams params;
  GroundEstimator g(params);
  ASSERT_TRUE(g.update(c, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
  EXPECT_TRUE(g.assumed());
  EXPECT_TRUE(g.plane().isApprox(Eigen::Vector4f(0, -1, 0, 1.3f), 1e-3f)) << g.plane().transpose();

  params.assume_below_points = false;
  GroundEstimator strict(params);
  EXPECT_FALSE(strict.update(c, Eigen::Vector3f::Zero(), Eigen::Vector3f(0, -1, 0)));
}

// ---- projection fit (for HOG) -----------------------------------------------------------------

TEST(FitProjection, RecoversAPinholeCamera)
{
  test::SceneCamera cam(1.3f, 0.2f, 160, 120, 131.25f);
  const Cloud c = cam.render({test::Figure{}});
  Eigen::Matrix<float, 3, 4> P;
  ASSERT_TRUE(fitProjection(c, P));
  int checked = 0;
  for (std::uint32_t v = 0; v < c.height; v += 7)
    for (std::uint32_t u = 0; u < c.width; u += 7)
    {
      const PointT& p = c.at(u, v);
      if (!std::isfinite(p.z))
        continue;
      const Eigen::Vector2f px = (P * p.getVector3fMap().homogeneous()).hnormalized();
      EXPECT_NEAR(px.x(), u, 0.5f);
      EXPECT_NEAR(px.y(), v, 0.5f);
      ++checked;
    }
  EXPECT_GT(checked, 100);
  Cloud flat = c;
  flat.width = static_cast<std::uint32_t>(flat.size());
  flat.height = 1;
  EXPECT_FALSE(fitProjection(flat, P));
}

// ---- bad input -----------------------------------------------------------------------------

TEST(TrackerBadInput, EmptyNanUnorganizedAndFloorlessCloudsGiveNoPeople)
{
  PeopleTracker tracker;
  const float nan = std::numeric_limits<float>::quiet_NaN();

  TrackerResult r = tracker.update(Cloud(), 0.0);
  EXPECT_TRUE(r.people.empty());
  EXPECT_FALSE(r.ground_valid);

  Cloud all_nan(320, 240);
  for (auto& p : all_nan.points)
    p.x = p.y = p.z = nan;
  r = tracker.update(all_nan, 0.1);
  EXPECT_TRUE(r.people.empty());
  EXPECT_FALSE(r.ground_valid);

  // Unorganized junk: points scattered at random in a box in front of the camera.
  Cloud junk;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(-2, 2), y(-1.5f, 1.5f), z(1, 6);
  for (int i = 0; i < 20000; ++i)
  {
    PointT p;
    p.x = x(rng);
    p.y = y(rng);
    p.z = z(rng);
    junk.push_back(p);
  }
  for (int k = 0; k < 3; ++k)
  {
    r = tracker.update(junk, 0.2 + 0.1 * k);
    EXPECT_TRUE(r.people.empty());
    EXPECT_EQ(r.detections, 0u);
  }

  // Floorless: person-like figures and a wall with no floor under them, and one figure alone.
  test::SceneCamera cam;
  PeopleTracker fresh;
  const Cloud lone = cam.render({test::Figure{{0.0f, 3.0f}, 1.8f}}, false);
  for (int k = 0; k < 3; ++k)
  {
    r = fresh.update(lone, 0.1 * k);
    EXPECT_TRUE(r.people.empty());
    EXPECT_FALSE(r.ground_valid);
  }
  TrackerParams strict;
  strict.assume_ground_below_points = false;
  PeopleTracker no_assumption(strict);
  const Cloud floorless = cam.render({test::Figure{{-0.8f, 3.0f}, 1.8f}, test::Figure{{0.8f, 4.0f}, 1.7f}}, false,
                                     {test::Wall{{-3, 6}, {3, 6}}});
  for (int k = 0; k < 3; ++k)
  {
    r = no_assumption.update(floorless, 0.1 * k);
    EXPECT_TRUE(r.people.empty());
    EXPECT_FALSE(r.ground_valid);
  }

  // Inconsistent organisation (width * height != size), a non-finite stamp or camera origin: ignored.
  Cloud broken = cam.render({test::Figure{}});
  broken.width = 17;
  r = tracker.update(broken, 1.0);
  EXPECT_TRUE(r.people.empty());
  const Cloud good = cam.render({test::Figure{}});
  EXPECT_TRUE(tracker.update(good, nan).people.empty());
  EXPECT_TRUE(tracker.update(good, 1.0, Eigen::Vector3f(nan, 0, 0)).people.empty());
  // ... and the tracker still works afterwards.
  tracker.update(good, 2.0);
  EXPECT_EQ(tracker.update(good, 2.1).people.size(), 1u);
}

TEST(TrackerBadInput, BadParametersThrow)
{
  const auto bad = [](auto change) {
    TrackerParams p;
    change(p);
    return p;
  };
  EXPECT_NO_THROW(PeopleTracker{TrackerParams()});
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.detection_voxel_size = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.person_voxel_size = -0.02f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.max_range = std::nanf(""); })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.max_range = 1e6f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.min_height = 2.5f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.max_width = 0.05f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.ground_tolerance = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.cluster_tolerance = -1; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.min_points = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.sampling_factor = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.split_max_distance = -0.1f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) {
                 p.ground = Eigen::Vector4f(0, 0, 0, 1);
               })),
               std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.gate = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.lost_after = -1; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.confirm_after = 0; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.reid_after = -1; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.reid_max_colour_distance = 1.5f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.weak_max_colour_distance = -0.1f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.reid_max_height_difference = std::nanf(""); })),
               std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.up_hint = Eigen::Vector3f::Zero(); })),
               std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.ground_max_angle = 2.0f; })), std::invalid_argument);
  EXPECT_THROW(PeopleTracker(bad([](TrackerParams& p) { p.hog_classifier_file = "no/such/classifier.yaml"; })),
               std::invalid_argument);
  // A readable file that is no classifier.
  const std::string junk = ::testing::TempDir() + "not_a_classifier.yaml";
  std::ofstream(junk) << "hello: world\n";
  EXPECT_THROW(PeopleTracker(bad([&](TrackerParams& p) { p.hog_classifier_file = junk; })), std::invalid_argument);
  std::remove(junk.c_str());
}
