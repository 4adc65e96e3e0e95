#include "test_scene.h"

#include <cmath>
#include <limits>

namespace action_flow
{
namespace test
{
namespace
{
struct Box
{
  Eigen::Affine3f pose;  // box frame -> camera frame
  Eigen::Vector3f lo, hi;
  Eigen::Vector3f rgb;
};

// Deterministic texture on the box's own coordinates: stripes plus a fixed pattern.
void shade(const Box& b, const Eigen::Vector3f& local, PointT& p)
{
  const int stripe = static_cast<int>(std::floor((local.y() - b.lo.y()) / 0.06f)) % 2 ? 40 : 0;
  const float pattern = 20.0f * std::sin(local.x() * 61.0f) * std::cos(local.y() * 47.0f + local.z() * 53.0f);
  auto channel = [&](float c) { return static_cast<std::uint8_t>(std::min(255.0f, std::max(0.0f, c - stripe + pattern))); };
  p.r = channel(b.rgb.x());
  p.g = channel(b.rgb.y());
  p.b = channel(b.rgb.z());
}

// Ray-box intersection in the box's frame (slab method); returns the entry distance or +inf.
float hit(const Box& b, const Eigen::Vector3f& dir, Eigen::Vector3f& local)
{
  const Eigen::Affine3f inv = b.pose.inverse();
  const Eigen::Vector3f o = inv.translation();
  const Eigen::Vector3f d = inv.linear() * dir;
  float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 3; ++i)
  {
    if (std::abs(d[i]) < 1e-9f)
    {
      if (o[i] < b.lo[i] || o[i] > b.hi[i])
        return std::numeric_limits<float>::infinity();
      continue;
    }
    float a = (b.lo[i] - o[i]) / d[i], c = (b.hi[i] - o[i]) / d[i];
    if (a > c)
      std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1)
      return std::numeric_limits<float>::infinity();
  }
  local = o + t0 * d;
  return t0;
}

std::vector<Box> person(const SceneOptions& o, float angle)
{
  // Person frame: origin on the floor under the person, x right, y UP, z toward the camera.
  Eigen::Affine3f body = Eigen::Affine3f::Identity();
  body.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // y up -> camera y down, z toward camera -> camera -z
  body.translation() = Eigen::Vector3f(o.person_x, o.camera_height, o.distance);
  auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi, Eigen::Vector3f rgb, const Eigen::Affine3f& local) {
    return Box{ body * local, lo, hi, rgb };
  };
  const Eigen::Affine3f id = Eigen::Affine3f::Identity();
  std::vector<Box> boxes;
  boxes.push_back(box({ -0.18f, 0.0f, -0.1f }, { 0.18f, 0.85f, 0.1f }, { 40, 40, 120 }, id));      // legs
  boxes.push_back(box({ -0.2f, 0.85f, -0.1f }, { 0.2f, 1.45f, 0.1f }, { 200, 40, 40 }, id));       // torso
  boxes.push_back(box({ -0.1f, 1.5f, -0.1f }, { 0.1f, 1.75f, 0.1f }, { 220, 170, 140 }, id));      // head
  boxes.push_back(box({ -0.45f, 1.1f, -0.04f }, { -0.2f, 1.18f, 0.04f }, { 200, 40, 40 }, id));    // left arm
  boxes.push_back(box({ 0.2f, 1.1f, -0.04f }, { 0.45f, 1.18f, 0.04f }, { 200, 40, 40 }, id));      // right upper arm
  const Eigen::Affine3f forearm = Eigen::Translation3f(0.45f, 1.14f, 0.0f) * Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitZ());
  boxes.push_back(box({ 0.0f, -0.04f, -0.04f }, { 0.3f, 0.04f, 0.04f }, { 220, 170, 140 }, forearm));
  return boxes;
}

Cloud render(const SceneOptions& o, float angle, bool floor, bool keep_missing)
{
  const std::vector<Box> boxes = o.person ? person(o, angle) : std::vector<Box>();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Cloud cloud;
  for (int v = 0; v < o.height; ++v)
    for (int u = 0; u < o.width; ++u)
    {
      const Eigen::Vector3f dir((u - 0.5f * o.width) / o.focal, (v - 0.5f * o.height) / o.focal, 1.0f);
      float best = std::numeric_limits<float>::infinity();
      PointT p;
      p.x = p.y = p.z = nan;
      p.r = p.g = p.b = 0;
      for (const Box& b : boxes)
      {
        Eigen::Vector3f local;
        const float t = hit(b, dir, local);
        if (t < best)
        {
          best = t;
          p.getVector3fMap() = t * dir;
          shade(b, local, p);
        }
      }
      if (floor && dir.y() > 1e-6f)
      {
        const float t = o.camera_height / dir.y();
        if (t < best && t * dir.z() < 8.0f)
        {
          best = t;
          p.getVector3fMap() = t * dir;
          const bool check = (static_cast<int>(std::floor(p.x / 0.25f)) + static_cast<int>(std::floor(p.z / 0.25f))) % 2;
          p.r = p.g = p.b = check ? 150 : 110;
        }
      }
      if (std::isfinite(best) || keep_missing)
        cloud.push_back(p);
    }
  if (keep_missing)
  {
    cloud.width = o.width;
    cloud.height = o.height;
  }
  cloud.is_dense = !keep_missing;
  return cloud;
}
}  // namespace

Cloud renderScene(const SceneOptions& o, float angle)
{
  return render(o, angle, o.floor, true);
}

Cloud renderPerson(const SceneOptions& o, float angle)
{
  SceneOptions only = o;
  only.person = true;
  return render(only, angle, false, false);
}

}  // namespace test
}  // namespace action_flow
