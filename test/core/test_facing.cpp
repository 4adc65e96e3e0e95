// Known-answer tests of orientation: the turned grid frame, the facing estimate from the trunk's
// shape, and the descriptor of a person turned about the vertical, which is the same once the grid
// turns with them.
#include <action_flow/facing.h>
#include <action_flow/posture_flow.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace action_flow;

namespace
{
constexpr float kDeg = 3.14159265f / 180.0f;

// A hand-built 1.75 m person standing at the origin of the identity frame (x across, y up, z
// towards the camera), facing sin(facing) x + cos(facing) z: an elliptic trunk 0.34 x 0.22 m, arms
// beside it, legs and a head, sampled every 2 cm. With @p near_side_only, only the surface that a
// camera far along +z sees (normals with a positive z). The right forearm, raised in front of the
// chest, moves up at 1 m/s (the flow).
struct Body
{
  Cloud cloud;
  FlowVectors flow;
};

Body person(float facing, bool near_side_only, float noise = 0.0f, unsigned seed = 1)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, noise);
  const Eigen::Vector3f w(std::sin(facing), 0.0f, std::cos(facing)), u(w.z(), 0.0f, -w.x()), up = Eigen::Vector3f::UnitY();
  Body b;
  // An upright elliptic cylinder (half axes ru along u, rw along w) centred at (cu, cw) in body
  // coordinates, between heights y0 and y1.
  const auto cylinder = [&](float cu, float cw, float ru, float rw, float y0, float y1, bool moving) {
    const float perimeter = 2.0f * 3.14159265f * std::sqrt(0.5f * (ru * ru + rw * rw));
    const int around = std::max(12, static_cast<int>(perimeter / 0.02f));
    for (float y = y0; y <= y1; y += 0.02f)
      for (int k = 0; k < around; ++k)
      {
        const float t = 2.0f * 3.14159265f * k / around;
        const Eigen::Vector3f normal = (std::cos(t) / ru) * u + (std::sin(t) / rw) * w;
        if (near_side_only && normal.z() <= 0.0f)
          continue;
        Eigen::Vector3f p = (cu + ru * std::cos(t)) * u + (cw + rw * std::sin(t)) * w + y * up;
        if (noise > 0.0f)
          p.z() += n(rng);
        PointT q;
        q.getVector3fMap() = p;
        b.cloud.push_back(q);
        if (moving)
          b.flow.push_back({ p, up });
      }
  };
  cylinder(0.0f, 0.0f, 0.17f, 0.11f, 0.9f, 1.45f, false);     // trunk
  cylinder(0.22f, 0.0f, 0.045f, 0.045f, 1.1f, 1.42f, false);  // upper arms
  cylinder(-0.22f, 0.0f, 0.045f, 0.045f, 0.85f, 1.42f, false);
  cylinder(0.12f, 0.22f, 0.04f, 0.04f, 1.15f, 1.3f, true);     // right forearm, in front
  cylinder(0.09f, 0.0f, 0.07f, 0.07f, 0.05f, 0.88f, false);    // legs
  cylinder(-0.09f, 0.0f, 0.07f, 0.07f, 0.05f, 0.88f, false);
  cylinder(0.0f, 0.01f, 0.08f, 0.1f, 1.52f, 1.74f, false);     // head
  return b;
}

// The same points and flow turned about the vertical axis through the origin by @p angle (the
// direction sin(a) x + cos(a) z turns by angle).
Body turnedCopy(const Body& in, float angle)
{
  const Eigen::Matrix3f r = Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitY()).toRotationMatrix();
  Body out = in;
  for (auto& p : out.cloud.points)
    p.getVector3fMap() = r * p.getVector3fMap();
  for (auto& f : out.flow)
  {
    f.position = r * f.position;
    f.velocity = r * f.velocity;
  }
  return out;
}

float relativeL1(const Eigen::VectorXf& a, const Eigen::VectorXf& b)
{
  return (a - b).lpNorm<1>() / std::max(1e-9f, a.lpNorm<1>());
}
}  // namespace

TEST(PersonFrame, TurnedKeepsUpAndTurnsDepthTowardsWhereThePersonFaces)
{
  PersonFrame f;
  f.origin = Eigen::Vector3f(1, 0, 2);
  const PersonFrame same = f.turned(0.0f);
  EXPECT_TRUE(same.axes.isApprox(f.axes));
  const PersonFrame quarter = f.turned(90.0f * kDeg);
  EXPECT_TRUE(quarter.axes.col(2).isApprox(Eigen::Vector3f::UnitX(), 1e-6f));   // z' = old x
  EXPECT_TRUE(quarter.axes.col(0).isApprox(-Eigen::Vector3f::UnitZ(), 1e-6f));  // x' = -old z
  EXPECT_TRUE(quarter.axes.col(1).isApprox(Eigen::Vector3f::UnitY()));
  EXPECT_NEAR(quarter.axes.determinant(), 1.0f, 1e-6f);  // still right-handed
  EXPECT_TRUE(quarter.origin.isApprox(f.origin));
  // A point where the person faces, 1 m in front of them, is at local z = 1.
  const PersonFrame t = f.turned(30.0f * kDeg);
  const Eigen::Vector3f front = f.origin + Eigen::Vector3f(std::sin(30.0f * kDeg), 0, std::cos(30.0f * kDeg));
  EXPECT_TRUE(t.toLocal(front).isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f));
}

TEST(Facing, FromTheNearSideOfTheTrunkGivesTheTurn)
{
  PersonFrame where;  // identity: the camera is far along +z
  for (float deg : { -70.0f, -45.0f, -20.0f, 0.0f, 10.0f, 30.0f, 60.0f })
  {
    const Body b = person(deg * kDeg, true);
    EXPECT_NEAR(facingFromTrunk(b.cloud, where) / kDeg, deg, 5.0f) << "facing " << deg;
    // Depth noise of a Kinect at 2.5 m (about 1 cm).
    const Body rough = person(deg * kDeg, true, 0.01f, 7);
    EXPECT_NEAR(facingFromTrunk(rough.cloud, where) / kDeg, deg, 12.0f) << "facing " << deg << ", noisy";
  }
}

TEST(Facing, TooFewPointsAtChestHeightGiveNaN)
{
  PersonFrame where;
  Cloud legs;
  for (const auto& p : person(0.0f, true).cloud.points)
    if (p.y < 0.8f)
      legs.push_back(p);
  EXPECT_TRUE(std::isnan(facingFromTrunk(legs, where)));
  EXPECT_TRUE(std::isnan(facingFromTrunk(Cloud(), where)));
}

TEST(Facing, ARotatedCopyOfAPersonAndTheirFlowGivesTheSameDescriptorAfterAlignment)
{
  const PostureFlowDescriptor descriptor;
  PersonFrame where;  // the camera's view: the grid of a camera-aligned descriptor
  const Body a = person(15.0f * kDeg, false);
  for (float turn : { 30.0f, -50.0f })
  {
    const Body b = turnedCopy(a, turn * kDeg);
    const float fa = facingFromTrunk(a.cloud, where), fb = facingFromTrunk(b.cloud, where);
    EXPECT_NEAR((fb - fa) / kDeg, turn, 1.0f);
    const Eigen::VectorXf da = descriptor.compute(a.cloud, a.flow, where.turned(fa));
    const Eigen::VectorXf db = descriptor.compute(b.cloud, b.flow, where.turned(fb));
    EXPECT_LT(relativeL1(da, db), 0.05f) << "turned " << turn;
    // The camera-aligned grid sees two different descriptors, several times further apart.
    const Eigen::VectorXf ca = descriptor.compute(a.cloud, a.flow, where), cb = descriptor.compute(b.cloud, b.flow, where);
    EXPECT_GT(relativeL1(ca, cb), 0.1f) << "turned " << turn;
    EXPECT_GT(relativeL1(ca, cb), 3.0f * relativeL1(da, db)) << "turned " << turn;
  }
}
