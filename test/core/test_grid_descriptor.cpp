// Known-answer tests of the gridded flow descriptor (SUMFLOW / MEANFLOW).
#include <action_flow/grid_descriptor.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace action_flow;

namespace
{
// Cube (ix, iy, iz) of the default 4x4x4 grid for a 1.75 m person at the origin with identity axes:
// 2.0 x 2.3 x 1.8 m, so cubes of 0.5 x 0.575 x 0.45 m; x and z centred, y from the ground up.
Eigen::Vector3f centreOfCube(int ix, int iy, int iz, float scale = 1.0f)
{
  return scale * Eigen::Vector3f(-1.0f + 0.5f * (ix + 0.5f), 0.575f * (iy + 0.5f), -0.9f + 0.45f * (iz + 0.5f));
}
int cube(int ix, int iy, int iz)
{
  return ix + 4 * (iy + 4 * iz);
}
}  // namespace

TEST(GridDescriptor, HandBuiltFieldGivesKnownSumflow)
{
  const GridDescriptor grid;
  ASSERT_EQ(grid.size(), 192);
  PersonFrame person;  // origin 0, identity axes, 1.75 m
  FlowVectors flow = {
    { centreOfCube(0, 0, 0), { 1, 0, 0 } },
    { centreOfCube(0, 0, 0) + Eigen::Vector3f(0.1f, 0.1f, 0.1f), { 0, 1, 0 } },
    { centreOfCube(3, 3, 3), { 0, 0, 2 } },
    { centreOfCube(1, 2, 3), { 0, -1, 0 } },
    { Eigen::Vector3f(5, 0, 0), { 9, 9, 9 } },      // outside the grid: ignored
    { Eigen::Vector3f(0, -0.1f, 0), { 9, 9, 9 } },  // below the ground: ignored
  };
  const Eigen::VectorXf d = grid.compute(flow, person);
  Eigen::VectorXf expected = Eigen::VectorXf::Zero(192);
  expected.segment<3>(3 * cube(0, 0, 0)) << 1, 1, 0;
  expected.segment<3>(3 * cube(3, 3, 3)) << 0, 0, 2;
  expected.segment<3>(3 * cube(1, 2, 3)) << 0, -1, 0;
  expected /= std::sqrt(7.0f);
  EXPECT_LT((d - expected).norm(), 1e-6f);
  EXPECT_NEAR(d.norm(), 1.0f, 1e-6f);
}

TEST(GridDescriptor, HandBuiltFieldGivesKnownMeanflow)
{
  GridParams params;
  params.aggregation = FlowAggregation::Mean;
  const GridDescriptor grid(params);
  FlowVectors flow = {
    { centreOfCube(0, 0, 0), { 1, 0, 0 } },
    { centreOfCube(0, 0, 0), { 0, 1, 0 } },
    { centreOfCube(2, 1, 0), { 0, 0, 2 } },
  };
  const Eigen::VectorXf d = grid.compute(flow, PersonFrame());
  Eigen::VectorXf expected = Eigen::VectorXf::Zero(192);
  expected.segment<3>(3 * cube(0, 0, 0)) << 0.5f, 0.5f, 0;
  expected.segment<3>(3 * cube(2, 1, 0)) << 0, 0, 2;
  expected /= std::sqrt(4.5f);
  EXPECT_LT((d - expected).norm(), 1e-6f);
}

TEST(GridDescriptor, GridScalesWithPersonHeight)
{
  const GridDescriptor grid;
  PersonFrame tall;
  tall.height = 3.5f;  // twice the reference: cubes twice as large
  const FlowVectors flow = { { centreOfCube(3, 2, 1, 2.0f), { 0, 1, 0 } } };
  const Eigen::VectorXf d = grid.compute(flow, tall);
  EXPECT_FLOAT_EQ(d[3 * cube(3, 2, 1) + 1], 1.0f);
  EXPECT_EQ(grid.cellOf(centreOfCube(3, 2, 1, 2.0f), 1.75f), -1) << "outside the grid of a 1.75 m person";
}

TEST(GridDescriptor, NoFlowGivesZerosNeverNan)
{
  const GridDescriptor grid;
  const Eigen::VectorXf empty = grid.compute({}, PersonFrame());
  EXPECT_EQ(empty.size(), 192);
  EXPECT_EQ(empty.norm(), 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const FlowVectors bad = { { centreOfCube(1, 1, 1), { nan, 0, 0 } }, { { nan, 0, 0 }, { 1, 0, 0 } } };
  const Eigen::VectorXf d = grid.compute(bad, PersonFrame());
  EXPECT_TRUE(d.allFinite());
  EXPECT_EQ(d.norm(), 0.0f);
}

// In a camera's optical frame (y down, z forward) a person 3 m ahead on a floor 1.1 m below the
// camera: upward motion is +y of the grid, motion toward the camera is +z.
TEST(PersonFrame, FromGroundInCameraFrame)
{
  const Eigen::Vector4f floor(0, -1, 0, 1.1f);  // -y + 1.1 = 0, normal pointing up (-y)
  const Eigen::Vector3f centroid(0.0f, 0.2f, 3.0f);
  const PersonFrame f = PersonFrame::fromGround(centroid, floor, 1.75f, centroid);
  EXPECT_TRUE(f.origin.isApprox(Eigen::Vector3f(0, 1.1f, 3.0f)));
  EXPECT_NEAR(f.axes.determinant(), 1.0f, 1e-5f);
  EXPECT_TRUE(f.toLocal(Eigen::Vector3f(0, 0.1f, 3.0f)).isApprox(Eigen::Vector3f(0, 1.0f, 0)));
  const GridDescriptor grid;
  const FlowVectors up = { { centroid, { 0, -1, 0 } } }, toward = { { centroid, { 0, 0, -1 } } },
                    right = { { centroid, { 1, 0, 0 } } };
  const int c = grid.cellOf(f.toLocal(centroid), f.height);
  ASSERT_GE(c, 0);
  EXPECT_FLOAT_EQ(grid.compute(up, f)[3 * c + 1], 1.0f);
  EXPECT_FLOAT_EQ(grid.compute(toward, f)[3 * c + 2], 1.0f);
  EXPECT_FLOAT_EQ(grid.compute(right, f)[3 * c + 0], 1.0f);
  EXPECT_THROW(PersonFrame::fromGround(centroid, Eigen::Vector4f(0, 0, 0, 1), 1.75f, centroid), std::invalid_argument);
  EXPECT_THROW(PersonFrame::fromGround(centroid, floor, 1.75f, Eigen::Vector3f(0, 1, 0)), std::invalid_argument);
}

TEST(GridDescriptor, AggregationNames)
{
  EXPECT_EQ(aggregationFromString("sumflow"), FlowAggregation::Sum);
  EXPECT_EQ(aggregationFromString(toString(FlowAggregation::Mean)), FlowAggregation::Mean);
  EXPECT_THROW(aggregationFromString("histflow"), std::invalid_argument);
}
