// The flow's grid neighbour index and batch matcher against references: nanoflann's kd-tree for
// the K nearest, and a brute-force transcription of the paper's step 1 (sort all points by
// distance, keep K, take the nearest colour) for the matches.
#include "clouds.h"

#include <action_flow/flow_estimator.h>
#include <action_flow/voxel_filter.h>

#include <gtest/gtest.h>
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace action_flow;

namespace
{
// Random points filling a person-sized slab, voxelised (centroids: irregular, as the tracker's output).
Cloud randomVoxelised(unsigned seed, int n, float voxel)
{
  return voxelFiltered(test::randomBox(seed, n, { -0.3f, -0.9f, 2.4f }, { 0.3f, 0.9f, 2.6f }), voxel);
}

// A regular lattice with few colours: many exactly equal distances and colours, the hard case for ties.
Cloud lattice(int nx, int ny, int nz, float step, const Eigen::Vector3f& corner, int colours)
{
  Cloud c;
  int i = 0;
  for (int a = 0; a < nz; ++a)
    for (int b = 0; b < ny; ++b)
      for (int d = 0; d < nx; ++d, ++i)
      {
        PointT p;
        p.getVector3fMap() = corner + step * Eigen::Vector3f(d, b, a);
        p.r = static_cast<std::uint8_t>(60 * (i % colours));
        p.g = 100;
        p.b = static_cast<std::uint8_t>(200 - 40 * (i % colours));
        c.push_back(p);
      }
  return c;
}

struct Adaptor
{
  const FlowFrame& f;
  std::size_t kdtree_get_point_count() const { return f.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t d) const { return f.point(i)[d]; }
  template <class B>
  bool kdtree_get_bbox(B&) const
  {
    return false;
  }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Adaptor>, Adaptor, 3, std::size_t>;

float sq(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

// The paper's step 1 by brute force, with "nearer" = smaller (distance, index).
std::vector<std::size_t> referenceMatch(const FlowFrame& from, const FlowFrame& to, int k)
{
  std::vector<std::size_t> out(from.size(), 0);
  std::vector<std::size_t> order(to.size());
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    for (std::size_t j = 0; j < to.size(); ++j)
      order[j] = j;
    const Eigen::Vector3f& q = from.point(i);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const float da = sq(q, to.point(a)), db = sq(q, to.point(b));
      return da < db || (da == db && a < b);
    });
    const std::size_t kk = std::min<std::size_t>(k, to.size());
    std::size_t best = order[0];
    float best_h = std::numeric_limits<float>::infinity();
    for (std::size_t r = 0; r < kk; ++r)
    {
      const float h = sq(from.colour(i), to.colour(order[r]));
      if (h < best_h)
      {
        best_h = h;
        best = order[r];
      }
    }
    out[i] = best;
  }
  return out;
}
}  // namespace

// The grid's K nearest are nanoflann's: the same distances in the same order, and the same points
// wherever the K-th distance is not tied with the (K+1)-th.
TEST(NeighbourGrid, KNearestEqualsNanoflannOnRandomVoxelisedClouds)
{
  int compared_sets = 0;
  for (unsigned seed = 1; seed <= 4; ++seed)
  {
    const Cloud cloud = randomVoxelised(seed, 20000, seed % 2 ? 0.02f : 0.04f);
    const FlowFrame frame(cloud, 0.0);
    ASSERT_GT(frame.size(), 200u);
    Adaptor adaptor{ frame };
    Tree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> x(-0.5f, 0.5f), y(-1.1f, 1.1f), z(2.2f, 2.8f);  // also outside the cloud
    for (int k : { 1, 7, 50, 300 })
      for (int t = 0; t < 60; ++t)
      {
        const Eigen::Vector3f q = t % 3 == 0 ? frame.point(rng() % frame.size()) : Eigen::Vector3f(x(rng), y(rng), z(rng));
        std::vector<std::size_t> idx;
        std::vector<float> d2;
        frame.nearest(q, k, idx, d2);
        const std::size_t n = std::min<std::size_t>(k + 1, frame.size());
        std::vector<std::size_t> ref_idx(n);
        std::vector<float> ref_d2(n);
        nanoflann::KNNResultSet<float, std::size_t> result(n);
        result.init(ref_idx.data(), ref_d2.data());
        tree.findNeighbors(result, q.data(), nanoflann::SearchParams());
        ASSERT_EQ(idx.size(), static_cast<std::size_t>(k));
        for (int i = 0; i < k; ++i)
          ASSERT_EQ(d2[i], ref_d2[i]) << "k " << k << " rank " << i;
        if (ref_d2[k - 1] < ref_d2[k])
        {
          std::vector<std::size_t> a(idx.begin(), idx.end()), b(ref_idx.begin(), ref_idx.begin() + k);
          std::sort(a.begin(), a.end());
          std::sort(b.begin(), b.end());
          EXPECT_EQ(a, b);
          ++compared_sets;
        }
      }
  }
  EXPECT_GT(compared_sets, 800) << "ties should be rare on voxel centroids";
}

TEST(NeighbourGrid, KNearestOnSmallAndDegenerateClouds)
{
  // Fewer points than K, a single point, a flat sheet (zero thickness), a line.
  for (const Cloud& cloud : { lattice(3, 3, 1, 0.02f, { 0, 0, 2 }, 2), lattice(1, 1, 1, 0.02f, { 0, 0, 2 }, 1),
                              lattice(30, 20, 1, 0.02f, { 0, 0, 2 }, 5), lattice(50, 1, 1, 0.02f, { 0, 0, 2 }, 3) })
  {
    const FlowFrame frame(cloud, 0.0);
    std::vector<std::size_t> idx;
    std::vector<float> d2;
    const Eigen::Vector3f q(0.11f, 0.07f, 2.01f);
    frame.nearest(q, 50, idx, d2);
    ASSERT_EQ(idx.size(), std::min<std::size_t>(50, cloud.size()));
    // Against a full sort by (distance, index).
    std::vector<std::size_t> order(frame.size());
    for (std::size_t j = 0; j < order.size(); ++j)
      order[j] = j;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      const float da = sq(q, frame.point(a)), db = sq(q, frame.point(b));
      return da < db || (da == db && a < b);
    });
    for (std::size_t i = 0; i < idx.size(); ++i)
      EXPECT_EQ(idx[i], order[i]);
  }
  const FlowFrame empty(Cloud(), 0.0);
  std::vector<std::size_t> idx{ 1, 2 };
  std::vector<float> d2{ 1.0f };
  empty.nearest(Eigen::Vector3f::Zero(), 5, idx, d2);
  EXPECT_TRUE(idx.empty());
  empty.within(Eigen::Vector3f::Zero(), 1.0f, idx);
  EXPECT_TRUE(idx.empty());
}

TEST(NeighbourGrid, WithinEqualsBruteForce)
{
  const Cloud cloud = randomVoxelised(7, 20000, 0.02f);
  const FlowFrame frame(cloud, 0.0);
  std::mt19937 rng(7);
  for (int t = 0; t < 200; ++t)
  {
    const Eigen::Vector3f q = frame.point(rng() % frame.size()) + Eigen::Vector3f(0.01f, -0.02f, 0.005f) * (t % 4);
    const float radius = 0.01f + 0.03f * (t % 5);
    std::vector<std::size_t> got;
    frame.within(q, radius, got);
    std::sort(got.begin(), got.end());
    std::vector<std::size_t> want;
    for (std::size_t j = 0; j < frame.size(); ++j)
      if (sq(q, frame.point(j)) < radius * radius)
        want.push_back(j);
    EXPECT_EQ(got, want);
  }
}

// The batch matcher (no sorting, tries in colour order) gives exactly the brute-force matches,
// including on lattices full of ties in distance and in colour.
TEST(FlowMatching, MatchEqualsBruteForceReference)
{
  FlowParams params;
  for (int k : { 1, 5, 50 })
  {
    params.k = k;
    const FlowEstimator est(params);
    for (unsigned seed = 1; seed <= 3; ++seed)
    {
      const FlowFrame a(randomVoxelised(seed, 1500, 0.04f), 0.0), b(randomVoxelised(seed + 10, 1500, 0.04f), 0.1);
      EXPECT_EQ(est.match(a, b), referenceMatch(a, b, k)) << "k " << k << " seed " << seed;
      EXPECT_EQ(est.match(b, a), referenceMatch(b, a, k)) << "k " << k << " seed " << seed;
    }
    const FlowFrame la(lattice(12, 10, 3, 0.02f, { 0, 0, 2 }, 3), 0.0);
    const FlowFrame lb(lattice(12, 10, 3, 0.02f, { 0.01f, 0.02f, 2 }, 2), 0.1);
    EXPECT_EQ(est.match(la, lb), referenceMatch(la, lb, k)) << "lattice, k " << k;
    EXPECT_EQ(est.match(lb, la), referenceMatch(lb, la, k)) << "lattice, k " << k;
  }
}

// correspond() matches back only the source points some target point chose; the result must be
// the two-full-passes reciprocal check.
TEST(FlowMatching, ReciprocalCheckEqualsTwoFullPasses)
{
  const FlowEstimator est;
  const Cloud body = test::texturedBlock(10, 40, 6);
  for (int i = 0; i < 3; ++i)
  {
    // A body moved a little, with sensor-like noise: many, but not all, matches are reciprocal.
    const FlowFrame source(test::noisy(body, 0.004f, 8, 10 * i), 0.0);
    const FlowFrame target(test::noisy(test::shifted(body, Eigen::Vector3f(0.01f * i, 0.005f, 0)), 0.004f, 8, 10 * i + 1),
                           1.0 / 30);
    const auto t2s = referenceMatch(target, source, 50), s2t = referenceMatch(source, target, 50);
    std::vector<std::pair<std::size_t, std::size_t>> want;
    for (std::size_t t = 0; t < t2s.size(); ++t)
      if (s2t[t2s[t]] == t)
        want.push_back({ t, t2s[t] });
    FlowStats stats;
    const auto got = est.correspond(source, target, stats);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t j = 0; j < got.size(); ++j)
      EXPECT_EQ(std::make_pair(got[j].target, got[j].source), want[j]);
    EXPECT_EQ(stats.matched, target.size());
    EXPECT_EQ(stats.removed_reciprocal, target.size() - want.size());
    EXPECT_GT(want.size(), target.size() / 3);
  }
}
