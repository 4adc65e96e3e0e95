// Runs the core on a generated pair of person-like clouds (a standing body waving its right
// forearm) and prints the flow statistics and the frame descriptor. No sensor, no ROS.
#include <action_flow/flow_estimator.h>
#include <action_flow/grid_descriptor.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <random>

using namespace action_flow;

namespace
{
// A box of points on a 0.02 m lattice with a striped, noisy texture (the matching uses colour).
void addBox(Cloud& c, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi, std::uint8_t r, std::uint8_t g,
            std::uint8_t b, std::mt19937& rng, const Eigen::Affine3f& pose = Eigen::Affine3f::Identity())
{
  std::uniform_int_distribution<int> noise(-25, 25);
  const float step = 0.02f;
  for (float x = lo.x(); x <= hi.x(); x += step)
    for (float y = lo.y(); y <= hi.y(); y += step)
      for (float z = lo.z(); z <= hi.z(); z += step)
      {
        PointT p;
        p.getVector3fMap() = pose * Eigen::Vector3f(x, y, z);
        const int stripe = static_cast<int>((y - lo.y()) / 0.06f) % 2 ? 40 : 0;
        p.r = static_cast<std::uint8_t>(std::clamp(r - stripe + noise(rng), 0, 255));
        p.g = static_cast<std::uint8_t>(std::clamp(g - stripe + noise(rng), 0, 255));
        p.b = static_cast<std::uint8_t>(std::clamp(b - stripe + noise(rng), 0, 255));
        c.push_back(p);
      }
}

// A 1.75 m person 3 m ahead in a frame with y up; the forearm turned by @p angle about the elbow.
Cloud person(float angle)
{
  std::mt19937 rng(42);  // same texture in both frames
  Cloud c;
  const Eigen::Vector3f at(0, 0, 3);
  addBox(c, at + Eigen::Vector3f(-0.18f, 0.0f, -0.1f), at + Eigen::Vector3f(0.18f, 0.85f, 0.1f), 40, 40, 120, rng);
  addBox(c, at + Eigen::Vector3f(-0.2f, 0.85f, -0.1f), at + Eigen::Vector3f(0.2f, 1.45f, 0.1f), 200, 40, 40, rng);
  addBox(c, at + Eigen::Vector3f(-0.1f, 1.5f, -0.1f), at + Eigen::Vector3f(0.1f, 1.75f, 0.1f), 220, 170, 140, rng);
  addBox(c, at + Eigen::Vector3f(0.2f, 1.1f, -0.04f), at + Eigen::Vector3f(0.45f, 1.18f, 0.04f), 200, 40, 40, rng);
  const Eigen::Vector3f elbow = at + Eigen::Vector3f(0.45f, 1.14f, 0.0f);
  const Eigen::Affine3f forearm = Eigen::Translation3f(elbow) * Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitZ());
  addBox(c, Eigen::Vector3f(0.0f, -0.04f, -0.04f), Eigen::Vector3f(0.3f, 0.04f, 0.04f), 220, 170, 140, rng, forearm);
  return c;
}
}  // namespace

int main()
{
  const double dt = 1.0 / 30.0;
  const float omega = 4.0f;  // rad/s: a brisk wave
  const Cloud a = person(0.6f), b = person(0.6f + omega * dt);
  const FlowFrame source(a, 0.0), target(b, dt);
  const FlowResult r = FlowEstimator().estimate(source, target);
  std::printf("person clouds: %zu and %zu points, dt = %.4f s\n", r.stats.source_points, r.stats.target_points, r.dt);
  std::printf("matched %zu; removed: %zu not reciprocal, %zu slower than 0.3 m/s, %zu isolated; kept %zu\n",
              r.stats.matched, r.stats.removed_reciprocal, r.stats.removed_slow, r.stats.removed_isolated, r.stats.kept);
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  float fastest = 0.0f;
  for (const auto& f : r.flow)
  {
    mean += f.velocity;
    fastest = std::max(fastest, f.velocity.norm());
  }
  if (!r.flow.empty())
    mean /= static_cast<float>(r.flow.size());
  std::printf("mean flow (%.2f, %.2f, %.2f) m/s, fastest %.2f m/s (forearm tip moves at %.2f m/s)\n", mean.x(),
              mean.y(), mean.z(), fastest, omega * 0.3f);

  PersonFrame where;  // y is already up here: origin under the person, z toward the camera
  where.origin = Eigen::Vector3f(0, 0, 3);
  where.axes.col(2) = -Eigen::Vector3f::UnitZ();
  where.axes.col(0) = -Eigen::Vector3f::UnitX();
  const Eigen::VectorXf d = GridDescriptor().compute(r.flow, where);
  std::printf("SUMFLOW descriptor (64 cubes x 3, L2 norm %.3f), non-zero cubes:\n", d.norm());
  for (int c = 0; c < 64; ++c)
  {
    const Eigen::Vector3f v = d.segment<3>(3 * c);
    if (v.norm() > 0)
      std::printf("  cube x%d y%d z%d: (%+.3f, %+.3f, %+.3f)\n", c % 4, (c / 4) % 4, c / 16, v.x(), v.y(), v.z());
  }
  return r.flow.empty() ? 1 : 0;
}
