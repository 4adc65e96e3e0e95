#include "tracker_walls.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace action_flow
{
namespace
{
constexpr std::size_t kRansacSample = 1000;  // RANSAC scores its hypotheses on this many points
constexpr int kIterations = 300;
constexpr float kBehind = 0.15f;  // points this far behind a wall (m) count against it

// The spread of values between their 2nd and 98th percentiles; @p top: the 98th.
float spread(std::vector<float> v, float* top = nullptr)
{
  if (v.size() < 2)
    return 0.0f;
  const std::size_t lo = v.size() / 50, hi = v.size() - 1 - v.size() / 50;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
  const float a = v[lo];
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(hi), v.end());
  if (top)
    *top = v[hi];
  return v[hi] - a;
}

// The plane parallel to up (within max_angle) through most of the sampled points, by RANSAC on
// three-point samples (PCL's SampleConsensusModelParallelPlane does the same but reports every
// degenerate sample on the console: voxelised walls of quantised depth give many collinear ones).
bool bestPlane(const Cloud& points, const pcl::Indices& sample, const Eigen::Vector3f& up, const WallParams& p,
               std::mt19937& rng, Eigen::Vector4f& best)
{
  if (sample.size() < 3)
    return false;
  std::uniform_int_distribution<std::size_t> pick(0, sample.size() - 1);
  const float max_sin = std::sin(p.max_angle);
  std::size_t most = 0;
  for (int it = 0; it < kIterations; ++it)
  {
    const Eigen::Vector3f a = points[sample[pick(rng)]].getVector3fMap(), b = points[sample[pick(rng)]].getVector3fMap(),
                          c = points[sample[pick(rng)]].getVector3fMap();
    Eigen::Vector3f n = (b - a).cross(c - a);
    if (!(n.norm() > 1e-6f))
      continue;  // degenerate
    n.normalize();
    if (std::abs(n.dot(up)) > max_sin)
      continue;  // not vertical enough
    const float d = -n.dot(a);
    std::size_t in = 0;
    for (const auto i : sample)
      in += std::abs(n.dot(points[i].getVector3fMap()) + d) < p.inlier_distance;
    if (in > most)
    {
      most = in;
      best << n, d;
    }
  }
  return most >= 3;
}

// How far along the wall (horizontally) the points of the image's top edge lie on @p plane: the wall
// goes on above the view over that length.
float lengthAtTopEdge(const std::vector<Eigen::Vector3f>& image_top, const Eigen::Vector4f& plane,
                      const Eigen::Vector3f& along, float inlier_distance)
{
  std::vector<float> s;
  for (const auto& q : image_top)
    if (std::abs(plane.head<3>().dot(q) + plane[3]) < inlier_distance)
      s.push_back(along.dot(q));
  return spread(std::move(s));
}
}  // namespace

std::vector<Eigen::Vector4f> findWalls(const Cloud& points, const Eigen::Vector4f& ground, const Eigen::Vector3f& camera,
                                       const WallParams& p, const std::vector<Eigen::Vector3f>& image_top)
{
  const Eigen::Vector3f up = ground.head<3>();
  std::vector<Eigen::Vector4f> walls;
  std::mt19937 rng(12345);  // deterministic: the same cloud, the same walls
  pcl::Indices remaining(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    remaining[i] = static_cast<pcl::index_t>(i);
  const std::size_t least = static_cast<std::size_t>(p.min_cover * p.min_width * p.min_height / (p.voxel * p.voxel));
  // A few planes more than walls are looked at: the largest vertical plane may be a cabinet's front.
  for (int attempt = 0; attempt < p.max_walls + 2 && static_cast<int>(walls.size()) < p.max_walls &&
                        remaining.size() >= least;
       ++attempt)
  {
    pcl::Indices sample;
    const std::size_t stride = std::max<std::size_t>(1, remaining.size() / kRansacSample);
    for (std::size_t i = 0; i < remaining.size(); i += stride)
      sample.push_back(remaining[i]);
    Eigen::Vector4f plane;
    if (!bestPlane(points, sample, up, p, rng, plane))
      break;
    pcl::Indices inliers, rest;
    for (const auto i : remaining)
      (std::abs(plane.head<3>().dot(points[i].getVector3fMap()) + plane[3]) < p.inlier_distance ? inliers : rest)
          .push_back(i);
    if (inliers.size() < least)
      break;
    // The plane's points leave the pool whether or not it is a wall, so the next round finds another.
    remaining.swap(rest);
    if (plane.head<3>().dot(camera) + plane[3] < 0.0f)
      plane = -plane;
    // Its extent along the wall (horizontal) and up it.
    const Eigen::Vector3f along = up.cross(plane.head<3>()).normalized();
    std::vector<float> s, h;
    for (const auto i : inliers)
    {
      s.push_back(along.dot(points[i].getVector3fMap()));
      h.push_back(up.dot(points[i].getVector3fMap()) + ground[3]);
    }
    float top = 0.0f;
    const float width = spread(s), height = spread(h, &top);
    if (width < p.min_width || height < p.min_height ||
        (top < p.min_top && lengthAtTopEdge(image_top, plane, along, p.inlier_distance) < p.min_width) ||
        static_cast<float>(inliers.size()) * p.voxel * p.voxel < p.min_cover * width * height)
      continue;
    // A wall bounds the room: (almost) nothing lies behind it. A plane strung through the room has
    // points on both sides.
    std::size_t behind = 0;
    for (const auto& q : points.points)
      behind += plane.head<3>().dot(q.getVector3fMap()) + plane[3] < -kBehind;
    if (behind <= points.size() / 50)
      walls.push_back(plane);
  }
  return walls;
}

}  // namespace action_flow
