// The hand-built known-answer scenes of the tests (the virtual Kinect, synth, renders everything
// else): a small ray-cast depth camera over a floor, walls, person-like shapes (legs, a torso, a
// neck and a round head) and textured boxes, seen by a tilted Kinect-like camera as an organized
// XYZRGB cloud in its optical frame (x right, y down, z ahead). The rostests' waving figure
// (renderScene, renderPerson) is made of such boxes, its forearm turned by an angle; each box's
// texture is fixed to it, so the flow's colour matching can follow it.
#pragma once

#include <action_flow/types.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace action_flow
{
namespace test
{
/** A standing person: feet at (x, y) on the floor (world: x right, y ahead, z up). */
struct Figure
{
  Eigen::Vector2f feet = Eigen::Vector2f(0, 3);
  float height = 1.75f;
  std::uint8_t r = 200, g = 60, b = 60;
};

/** A box with a texture fixed to it: its corners @p lo, @p hi in its own frame, @p pose: own frame -> world. */
struct Box
{
  Eigen::Affine3f pose = Eigen::Affine3f::Identity();
  Eigen::Vector3f lo, hi;
  Eigen::Vector3f rgb;
};

/** A vertical wall through two floor points, from z0 to z1. */
struct Wall
{
  Eigen::Vector2f a, b;
  float z0 = 0.0f, z1 = 2.5f;
};

class SceneCamera
{
public:
  /** Camera @p height above the floor at the world origin, looking along +y, pitched down by @p pitch (rad). */
  SceneCamera(float height = 1.3f, float pitch = 0.15f, int width = 320, int rows = 240, float focal = 262.5f)
    : width_(width), rows_(rows), focal_(focal)
  {
    centre_ = Eigen::Vector3f(0, 0, height);
    const Eigen::Vector3f x(1, 0, 0), z(0, std::cos(pitch), -std::sin(pitch));
    axes_.col(0) = x;
    axes_.col(1) = z.cross(x);
    axes_.col(2) = z;
  }

  /** The floor's checker colours (RGB). */
  Eigen::Vector3i floor_light = Eigen::Vector3i(120, 120, 110), floor_dark = Eigen::Vector3i(90, 90, 85);

  /** World point -> camera optical frame. */
  Eigen::Vector3f toCamera(const Eigen::Vector3f& w) const { return axes_.transpose() * (w - centre_); }
  /** Camera optical frame -> world. */
  Eigen::Vector3f toWorld(const Eigen::Vector3f& c) const { return axes_ * c + centre_; }
  /** The floor (world z = 0) in the camera frame, normal up, unit. */
  Eigen::Vector4f floorInCamera() const
  {
    const Eigen::Vector3f n = axes_.transpose() * Eigen::Vector3f(0, 0, 1);
    return Eigen::Vector4f(n.x(), n.y(), n.z(), centre_.z());
  }

  /**
   * Renders the scene. @p floor: whether the floor is there (limited to |x| < 6, 0 < y < 9).
   * @p noise: depth noise (m, standard deviation), seeded by @p seed.
   */
  Cloud render(const std::vector<Figure>& people, bool floor = true, const std::vector<Wall>& walls = {},
               float noise = 0.0f, unsigned seed = 1, const std::vector<Box>& boxes = {}) const
  {
    Cloud c;
    c.width = width_;
    c.height = rows_;
    c.is_dense = false;
    c.points.resize(static_cast<std::size_t>(width_) * rows_);
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int v = 0; v < rows_; ++v)
      for (int u = 0; u < width_; ++u)
      {
        const Eigen::Vector3f ray_c((u - width_ / 2.0f + 0.5f) / focal_, (v - rows_ / 2.0f + 0.5f) / focal_, 1.0f);
        const Eigen::Vector3f d = axes_ * ray_c;  // world direction, camera z component 1
        float best = std::numeric_limits<float>::infinity();
        Eigen::Vector3i colour(0, 0, 0);
        if (floor && d.z() < 0)
        {
          const float t = -centre_.z() / d.z();
          const Eigen::Vector3f p = centre_ + t * d;
          if (std::abs(p.x()) < 6 && p.y() > 0 && p.y() < 9 && t < best)
          {
            best = t;
            const int checker = (static_cast<int>(std::floor(p.x() * 2)) + static_cast<int>(std::floor(p.y() * 2))) & 1;
            colour = checker ? floor_light : floor_dark;
          }
        }
        for (const Wall& w : walls)
          hitWall(w, d, best, colour);
        for (const Figure& f : people)
          hitFigure(f, d, best, colour);
        for (const Box& b : boxes)
          hitBox(b, d, best, colour);
        PointT& p = c.at(u, v);
        if (!std::isfinite(best) || best * 1.0f > 8.0f)
        {
          p.x = p.y = p.z = nan;
          continue;
        }
        const float t = best * (1.0f + noise * gauss(rng) / std::max(1.0f, best));
        const Eigen::Vector3f q = t * ray_c;  // camera frame: z = depth
        p.x = q.x();
        p.y = q.y();
        p.z = q.z();
        p.r = static_cast<std::uint8_t>(colour.x());
        p.g = static_cast<std::uint8_t>(colour.y());
        p.b = static_cast<std::uint8_t>(colour.z());
      }
    return c;
  }

private:
  // Vertical elliptic cylinder centred at (cx, cy), semi-axes (ax, ay), between z0 and z1.
  void hitCylinder(float cx, float cy, float ax, float ay, float z0, float z1, const Eigen::Vector3f& d, float& best,
                   Eigen::Vector3i& colour, const Eigen::Vector3i& c) const
  {
    const float ox = (centre_.x() - cx) / ax, oy = (centre_.y() - cy) / ay, dx = d.x() / ax, dy = d.y() / ay;
    const float A = dx * dx + dy * dy, B = 2 * (ox * dx + oy * dy), C = ox * ox + oy * oy - 1;
    const float disc = B * B - 4 * A * C;
    if (A < 1e-12f || disc < 0)
      return;
    const float t = (-B - std::sqrt(disc)) / (2 * A);
    const float z = centre_.z() + t * d.z();
    if (t > 0 && t < best && z >= z0 && z <= z1)
    {
      best = t;
      colour = c;
    }
  }

  void hitSphere(const Eigen::Vector3f& s, float r, const Eigen::Vector3f& d, float& best, Eigen::Vector3i& colour,
                 const Eigen::Vector3i& c) const
  {
    const Eigen::Vector3f o = centre_ - s;
    const float A = d.squaredNorm(), B = 2 * o.dot(d), C = o.squaredNorm() - r * r;
    const float disc = B * B - 4 * A * C;
    if (disc < 0)
      return;
    const float t = (-B - std::sqrt(disc)) / (2 * A);
    if (t > 0 && t < best)
    {
      best = t;
      colour = c;
    }
  }

  void hitFigure(const Figure& f, const Eigen::Vector3f& d, float& best, Eigen::Vector3i& colour) const
  {
    const float H = f.height, x = f.feet.x(), y = f.feet.y();
    const Eigen::Vector3i body(f.r, f.g, f.b), skin(220, 180, 150), trousers(40, 40, 80);
    const float hip = 0.5f * H, shoulder = H - 0.28f;
    hitCylinder(x - 0.1f, y, 0.08f, 0.08f, 0.0f, hip, d, best, colour, trousers);
    hitCylinder(x + 0.1f, y, 0.08f, 0.08f, 0.0f, hip, d, best, colour, trousers);
    hitCylinder(x, y, 0.22f, 0.13f, hip, shoulder, d, best, colour, body);
    hitCylinder(x, y, 0.06f, 0.06f, shoulder, H - 0.18f, d, best, colour, skin);
    hitSphere(Eigen::Vector3f(x, y, H - 0.11f), 0.11f, d, best, colour, skin);
  }

  // Ray-box intersection in the box's frame (slab method); the texture: stripes plus a fixed pattern.
  void hitBox(const Box& b, const Eigen::Vector3f& dir, float& best, Eigen::Vector3i& colour) const
  {
    const Eigen::Affine3f inv = b.pose.inverse();
    const Eigen::Vector3f o = inv * centre_, d = inv.linear() * dir;
    float t0 = 0.0f, t1 = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i)
    {
      if (std::abs(d[i]) < 1e-9f)
      {
        if (o[i] < b.lo[i] || o[i] > b.hi[i])
          return;
        continue;
      }
      float a = (b.lo[i] - o[i]) / d[i], c = (b.hi[i] - o[i]) / d[i];
      if (a > c)
        std::swap(a, c);
      t0 = std::max(t0, a);
      t1 = std::min(t1, c);
      if (t0 > t1)
        return;
    }
    if (!(t0 > 0 && t0 < best))
      return;
    best = t0;
    const Eigen::Vector3f local = o + t0 * d;
    const int stripe = static_cast<int>(std::floor((local.y() - b.lo.y()) / 0.06f)) % 2 ? 40 : 0;
    const float pattern = 20.0f * std::sin(local.x() * 61.0f) * std::cos(local.y() * 47.0f + local.z() * 53.0f);
    for (int k = 0; k < 3; ++k)
      colour[k] = static_cast<int>(std::min(255.0f, std::max(0.0f, b.rgb[k] - stripe + pattern)));
  }

  void hitWall(const Wall& w, const Eigen::Vector3f& d, float& best, Eigen::Vector3i& colour) const
  {
    const Eigen::Vector2f e = w.b - w.a;
    const Eigen::Vector2f n(-e.y(), e.x());
    const float den = n.dot(d.head<2>());
    if (std::abs(den) < 1e-9f)
      return;
    const float t = n.dot(w.a - centre_.head<2>()) / den;
    const Eigen::Vector3f p = centre_ + t * d;
    const float s = (p.head<2>() - w.a).dot(e) / e.squaredNorm();
    if (t > 0 && t < best && s >= 0 && s <= 1 && p.z() >= w.z0 && p.z() <= w.z1)
    {
      best = t;
      colour = Eigen::Vector3i(200, 200, 190);
    }
  }

  int width_, rows_;
  float focal_;
  Eigen::Vector3f centre_;
  Eigen::Matrix3f axes_;  // columns: camera x, y, z in the world
};

/** The rostests' scene: a figure of boxes on a floor in front of a level camera, waving its right forearm. */
struct SceneOptions
{
  int width = 320, height = 240;
  float focal = 262.5f;        // Kinect v1 at 320x240
  float camera_height = 1.2f;  // above the floor
  float distance = 2.5f;       // the person's distance ahead
  float person_x = 0.0f;       // their lateral offset
  bool floor = true;
  bool person = true;
};

/** The person's height in the scene (top of the head above the floor). */
constexpr float kPersonHeight = 1.75f;

/** The figure's boxes with the forearm at @p angle (rad), in the world (x right, y ahead, z up). */
inline std::vector<Box> wavingFigure(const SceneOptions& o, float angle)
{
  // The figure's frame: origin on the floor under it, x right, y up, z toward the camera.
  Eigen::Affine3f body = Eigen::Affine3f::Identity();
  body.linear() << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  body.translation() = Eigen::Vector3f(o.person_x, o.distance, 0.0f);
  const Eigen::Affine3f id = Eigen::Affine3f::Identity();
  const auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi, Eigen::Vector3f rgb, const Eigen::Affine3f& local) {
    return Box{ body * local, lo, hi, rgb };
  };
  const Eigen::Affine3f forearm =
      Eigen::Translation3f(0.45f, 1.14f, 0.0f) * Eigen::AngleAxisf(angle, Eigen::Vector3f::UnitZ());
  return { box({ -0.18f, 0.0f, -0.1f }, { 0.18f, 0.85f, 0.1f }, { 40, 40, 120 }, id),        // legs
           box({ -0.2f, 0.85f, -0.1f }, { 0.2f, 1.45f, 0.1f }, { 200, 40, 40 }, id),         // torso
           box({ -0.1f, 1.5f, -0.1f }, { 0.1f, 1.75f, 0.1f }, { 220, 170, 140 }, id),        // head
           box({ -0.45f, 1.1f, -0.04f }, { -0.2f, 1.18f, 0.04f }, { 200, 40, 40 }, id),      // left arm
           box({ 0.2f, 1.1f, -0.04f }, { 0.45f, 1.18f, 0.04f }, { 200, 40, 40 }, id),        // right upper arm
           box({ 0.0f, -0.04f, -0.04f }, { 0.3f, 0.04f, 0.04f }, { 220, 170, 140 }, forearm) };
}

/** The scene with the forearm at @p angle, as the level camera's organized cloud. */
inline Cloud renderScene(const SceneOptions& o, float angle)
{
  SceneCamera camera(o.camera_height, 0.0f, o.width, o.height, o.focal);
  camera.floor_light = Eigen::Vector3i(150, 150, 150);  // a grey floor: the annotator test reads it back
  camera.floor_dark = Eigen::Vector3i(110, 110, 110);
  return camera.render({}, o.floor, {}, 0.0f, 1, o.person ? wavingFigure(o, angle) : std::vector<Box>());
}

/** The person's points only (no floor, no missing points), for publishing person clouds directly. */
inline Cloud renderPerson(const SceneOptions& o, float angle)
{
  SceneOptions only = o;
  only.floor = false;
  only.person = true;
  const Cloud all = renderScene(only, angle);
  Cloud person;
  for (const PointT& p : all.points)
    if (std::isfinite(p.z))
      person.push_back(p);
  return person;
}

}  // namespace test
}  // namespace action_flow
