// The voxel filter against pcl::VoxelGrid itself: the same voxels, in the same order, with the same
// centroids and colours (up to the last bit: PCL's sort is not stable, so it may sum a voxel's points
// in another order), on organized scenes with NaNs, index subsets and random clouds, also when one
// filter is reused from frame to frame.
#include "clouds.h"
#include "scene.h"

#include <action_flow/voxel_filter.h>

#include <gtest/gtest.h>
#include <pcl/filters/voxel_grid.h>


using namespace action_flow;

namespace
{
Cloud pclVoxelGrid(const Cloud& in, float leaf, const pcl::Indices* indices)
{
  pcl::VoxelGrid<PointT> grid;
  grid.setInputCloud(in.makeShared());
  if (indices)
    grid.setIndices(pcl::make_shared<pcl::Indices>(*indices));
  grid.setLeafSize(leaf, leaf, leaf);
  Cloud out;
  grid.filter(out);
  return out;
}

void expectSame(const Cloud& expected, const Cloud& actual, float leaf)
{
  ASSERT_EQ(expected.size(), actual.size());
  EXPECT_EQ(actual.width, actual.size());
  EXPECT_EQ(actual.height, 1u);
  EXPECT_TRUE(actual.is_dense);
  EXPECT_EQ(expected.header.frame_id, actual.header.frame_id);
  EXPECT_EQ(expected.header.stamp, actual.header.stamp);
  // The same voxel (a centroid lies in its voxel), then the same centroid (within 0.1 mm: float sums
  // of a hundred points 5 m away, in another order) and colour.
  const auto cell = [&](const PointT& p) { return (p.getArray3fMap() / leaf).floor().eval(); };
  std::size_t other_voxel = 0, other_centroid = 0, other_colour = 0;
  for (std::size_t i = 0; i < expected.size(); ++i)
  {
    const PointT &e = expected[i], &a = actual[i];
    other_voxel += !(cell(e) == cell(a)).all();
    other_centroid += (e.getVector3fMap() - a.getVector3fMap()).cwiseAbs().maxCoeff() > 1e-4f;
    other_colour += std::abs(e.r - a.r) > 1 || std::abs(e.g - a.g) > 1 || std::abs(e.b - a.b) > 1 || e.a != a.a;
  }
  EXPECT_EQ(other_voxel, 0u) << "of " << expected.size() << " voxels";
  EXPECT_EQ(other_centroid, 0u) << "of " << expected.size() << " voxels";
  EXPECT_EQ(other_colour, 0u) << "of " << expected.size() << " voxels";

}

Cloud randomCloud(unsigned seed, int n)
{
  Cloud cloud = test::randomBox(seed, n, { -2.0f, -1.0f, 0.5f }, { 2.0f, 1.2f, 6.0f });
  cloud.header.frame_id = "camera_rgb_optical_frame";
  cloud.header.stamp = 1234567;
  return cloud;
}
}  // namespace

TEST(VoxelFilter, SameAsPclVoxelGridOnOrganizedScenesWithNaNs)
{
  test::SceneOptions o;
  o.width = 640;
  o.height = 480;
  o.focal = 525.0f;
  VoxelFilter filter;  // reused, as the tracker reuses it
  for (float angle : { 0.0f, 0.7f, 1.4f })
  {
    Cloud scene = test::renderScene(o, angle);
    scene.header.frame_id = "camera_rgb_optical_frame";
    ASSERT_FALSE(scene.is_dense);
    std::size_t nan = 0;
    for (const PointT& p : scene.points)
      nan += !std::isfinite(p.z);
    ASSERT_GT(nan, 0u) << "the scene should have pixels without depth";
    for (float leaf : { 0.02f, 0.06f, 0.13f })
    {
      Cloud ours;
      filter.filter(scene, leaf, nullptr, ours);
      ASSERT_GT(ours.size(), 100u);
      expectSame(pclVoxelGrid(scene, leaf, nullptr), ours, leaf);
    }
    // Every second row and column, as the tracker feeds detection.
    pcl::Indices sampled;
    for (std::uint32_t r = 0; r < scene.height; r += 2)
      for (std::uint32_t c = 0; c < scene.width; c += 2)
        sampled.push_back(static_cast<int>(r * scene.width + c));
    Cloud ours;
    filter.filter(scene, 0.06f, &sampled, ours);
    expectSame(pclVoxelGrid(scene, 0.06f, &sampled), ours, 0.06f);
  }
}

TEST(VoxelFilter, SameAsPclVoxelGridOnRandomCloudsAndTheOneOffFunction)
{
  VoxelFilter filter;
  Cloud ours;
  for (unsigned seed = 1; seed <= 3; ++seed)
  {
    const Cloud cloud = randomCloud(seed, 20000 * static_cast<int>(seed));
    filter.filter(cloud, 0.05f, nullptr, ours);
    expectSame(pclVoxelGrid(cloud, 0.05f, nullptr), ours, 0.05f);
    expectSame(pclVoxelGrid(cloud, 0.2f, nullptr), voxelFiltered(cloud, 0.2f), 0.2f);
  }
  // A larger cloud, then a smaller one: nothing of the first is left in the reused output.
  filter.filter(randomCloud(9, 50000), 0.05f, nullptr, ours);
  const Cloud small = randomCloud(10, 300);
  filter.filter(small, 0.05f, nullptr, ours);
  expectSame(pclVoxelGrid(small, 0.05f, nullptr), ours, 0.05f);
}

TEST(VoxelFilter, KnownCentroidsAndColours)
{
  Cloud in;
  const auto add = [&](float x, float y, float z, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    PointT p;
    p.x = x, p.y = y, p.z = z, p.r = r, p.g = g, p.b = b;
    in.push_back(p);
  };
  add(0.01f, 0.01f, 1.01f, 100, 0, 10);  // voxel (0, 0, 10) at leaf 0.1
  add(0.03f, 0.05f, 1.03f, 200, 51, 21);
  add(0.25f, 0.01f, 1.01f, 7, 7, 7);     // voxel (2, 0, 10)
  const Cloud out = voxelFiltered(in, 0.1f);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_NEAR(out[0].x, 0.02f, 1e-6f);
  EXPECT_NEAR(out[0].y, 0.03f, 1e-6f);
  EXPECT_NEAR(out[0].z, 1.02f, 1e-6f);
  EXPECT_EQ(out[0].r, 150);
  EXPECT_EQ(out[0].g, 25);  // 25.5, truncated as PCL does
  EXPECT_EQ(out[0].b, 15);
  EXPECT_NEAR(out[1].x, 0.25f, 1e-6f);
  EXPECT_EQ(out[1].r, 7);

  // A box 2047.2 voxels long, from 0.9 of a voxel: its points span 2049 voxels, one more than the
  // box's length says; the last must still come last.
  Cloud line;
  for (float x : { 204.81f, 0.09f, 100.05f })
  {
    PointT p;
    p.x = x, p.y = 0.0f, p.z = 0.0f;
    line.push_back(p);
  }
  const Cloud sorted = voxelFiltered(line, 0.1f);
  ASSERT_EQ(sorted.size(), 3u);
  EXPECT_NEAR(sorted[0].x, 0.09f, 1e-4f);
  EXPECT_NEAR(sorted[1].x, 100.05f, 1e-3f);
  EXPECT_NEAR(sorted[2].x, 204.81f, 1e-3f);
  expectSame(pclVoxelGrid(line, 0.1f, nullptr), sorted, 0.1f);
}

TEST(VoxelFilter, EmptyNaNOnlyAndBadLeaf)
{
  Cloud nan_only;
  PointT p;
  p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
  nan_only.points.assign(50, p);
  nan_only.width = 50;
  nan_only.height = 1;
  nan_only.is_dense = false;
  VoxelFilter filter;
  Cloud out = randomCloud(1, 10);
  filter.filter(nan_only, 0.05f, nullptr, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(out.width, 0u);
  EXPECT_TRUE(voxelFiltered(Cloud(), 0.05f).empty());
  const pcl::Indices none;
  filter.filter(randomCloud(2, 10), 0.05f, &none, out);
  EXPECT_TRUE(out.empty());
  EXPECT_THROW(filter.filter(randomCloud(3, 10), 0.0f, nullptr, out), std::invalid_argument);
  EXPECT_THROW(filter.filter(randomCloud(3, 10), std::numeric_limits<float>::quiet_NaN(), nullptr, out),
               std::invalid_argument);
  EXPECT_THROW(filter.filter(randomCloud(3, 1000), 1e-6f, nullptr, out), std::invalid_argument);
}
