#include "moving_person.h"

#include <pcl/filters/voxel_grid.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace action_flow
{
namespace bench
{
namespace
{
constexpr int kWidth = 640, kHeight = 480;
constexpr float kF = 525.0f, kCx = 319.5f, kCy = 239.5f;
constexpr float kPi = 3.14159265f;
constexpr float kBaseline = 0.075f;  // projector-camera baseline (m)
constexpr float kStep = 0.003f;  // surface sampling (m): finer than a pixel's footprint at 2.5 m (4.8 mm)

// A deterministic hash of integers to [0,1): the fine grain of a texture, fixed to the surface.
float grain(std::uint32_t a, std::uint32_t b, std::uint32_t c)
{
  std::uint64_t h = (static_cast<std::uint64_t>(a) * 0x9E3779B97F4A7C15ull) ^ (static_cast<std::uint64_t>(b) << 21) ^ c;
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  h ^= h >> 31;
  return (h & 0xFFFFFF) / 16777216.0f;
}

struct Material
{
  Eigen::Vector3f base, second;
  int pattern;  // 0 plain, 1 stripes across the axis, 2 checks, 3 stripes along the axis
  float period;
};

// One capsule in body coordinates (x right, y up, z toward the camera).
struct Part
{
  Eigen::Vector3f a, b;
  float radius;
  Material material;
  std::uint32_t id;
};

struct Splat
{
  float z = std::numeric_limits<float>::infinity();
  std::uint8_t r = 0, g = 0, b = 0;
};

Eigen::Vector3f shade(const Material& m, float s, float phi, std::uint32_t id)
{
  const float around = phi * 0.1f / (2 * kPi);  // angular coordinate scaled to metres of a 0.1 m girth
  bool second = false;
  if (m.pattern == 1)
    second = std::fmod(s / m.period, 2.0f) >= 1.0f;
  else if (m.pattern == 2)
    second = (static_cast<int>(std::floor(s / m.period)) + static_cast<int>(std::floor(around / m.period * 4))) % 2 != 0;
  else if (m.pattern == 3)
    second = std::fmod(std::floor(phi / (2 * kPi) * 12.0f), 2.0f) != 0.0f;
  Eigen::Vector3f c = second ? m.second : m.base;
  // A 1 cm grain fixed to the surface: enough texture for the colour matching to find the right point.
  const float g = grain(id, static_cast<std::uint32_t>(s / 0.01f + 1000), static_cast<std::uint32_t>(phi * 8)) - 0.5f;
  return (c * (1.0f + 0.35f * g)).cwiseMax(0.0f).cwiseMin(1.0f);
}

// The body at time t: arms down except the right arm, raised and waving from the elbow; the body sways.
std::vector<Part> pose(float t, const MovingPersonParams& p)
{
  const float s = p.height / 1.75f;
  const Material skin{ { 0.85f, 0.65f, 0.52f }, { 0.8f, 0.6f, 0.5f }, 0, 0.05f };
  const Material hair{ { 0.25f, 0.15f, 0.08f }, { 0.15f, 0.1f, 0.05f }, 3, 0.02f };
  const Material shirt{ { 0.75f, 0.15f, 0.12f }, { 0.95f, 0.85f, 0.3f }, 1, 0.05f };
  const Material sleeve{ { 0.75f, 0.15f, 0.12f }, { 0.95f, 0.85f, 0.3f }, 2, 0.04f };
  const Material jeans{ { 0.15f, 0.22f, 0.45f }, { 0.25f, 0.32f, 0.55f }, 3, 0.03f };
  const Material shoes{ { 0.12f, 0.12f, 0.12f }, { 0.3f, 0.3f, 0.3f }, 1, 0.03f };
  const float sway = 0.015f * std::sin(2 * kPi * 0.4f * t);  // 0.04 m/s at most: a still body's drift
  const Eigen::Vector3f o(sway, 0, 0);
  auto at = [&](float x, float y, float z) { return Eigen::Vector3f(o + s * Eigen::Vector3f(x, y, z)); };
  std::vector<Part> parts;
  std::uint32_t id = 0;
  auto add = [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b, float r, const Material& m) {
    parts.push_back({ a, b, r * s, m, ++id });
  };
  add(at(0, 1.60f, 0), at(0, 1.66f, 0), 0.095f, hair);       // head
  add(at(0, 1.46f, 0), at(0, 1.53f, 0), 0.05f, skin);        // neck
  add(at(-0.06f, 0.98f, 0), at(-0.06f, 1.36f, 0), 0.13f, shirt);  // torso, two capsules side by side
  add(at(0.06f, 0.98f, 0), at(0.06f, 1.36f, 0), 0.13f, shirt);
  for (float side : { -1.0f, 1.0f })
  {
    add(at(0.09f * side, 0.90f, 0), at(0.095f * side, 0.50f, 0.01f), 0.07f, jeans);   // thigh
    add(at(0.095f * side, 0.50f, 0.01f), at(0.1f * side, 0.10f, 0), 0.05f, jeans);    // shin
    add(at(0.1f * side, 0.05f, 0.0f), at(0.1f * side, 0.05f, 0.12f), 0.045f, shoes);  // foot
  }
  // Left arm hanging.
  add(at(-0.21f, 1.40f, 0), at(-0.24f, 1.12f, 0), 0.045f, sleeve);
  add(at(-0.24f, 1.12f, 0), at(-0.25f, 0.86f, 0.02f), 0.038f, skin);
  // Right arm: upper arm raised sideways, forearm waving about the elbow in the image plane.
  const float w = 2 * kPi * p.wave_hz * t;
  const Eigen::Vector3f shoulder = at(0.21f, 1.40f, 0);
  const float upper = 1.25f + 0.12f * std::sin(w);        // from hanging down, about the camera axis
  const Eigen::Vector3f elbow = shoulder + 0.28f * s * Eigen::Vector3f(std::sin(upper), -std::cos(upper), 0);
  const float fore = upper + 0.9f + 0.55f * std::sin(w + 0.6f);
  const Eigen::Vector3f hand = elbow + 0.27f * s * Eigen::Vector3f(std::sin(fore), -std::cos(fore), 0.1f);
  add(shoulder, elbow, 0.045f, sleeve);
  add(elbow, hand, 0.038f, skin);
  return parts;
}

// Any unit vector perpendicular to u, chosen continuously so the texture does not jump between frames.
Eigen::Vector3f perpendicular(const Eigen::Vector3f& u)
{
  const Eigen::Vector3f ref = std::abs(u.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  return u.cross(ref).normalized();
}
}  // namespace

MovingPerson::MovingPerson(const MovingPersonParams& params) : params_(params)
{
}

void MovingPerson::render(int i, Cloud& organized, std::vector<std::uint8_t>* mask, bool with_room) const
{
  const float t = static_cast<float>(stamp(i));
  const auto parts = pose(t, params_);
  std::vector<Splat> zbuf(kWidth * kHeight);
  std::vector<std::uint8_t> is_person(kWidth * kHeight, 0);
  // Body coordinates to the optical frame: x right, y down, z forward.
  auto toOptical = [&](const Eigen::Vector3f& b) {
    return Eigen::Vector3f(b.x(), params_.camera_height - b.y(), params_.distance - b.z());
  };
  auto splat = [&](const Eigen::Vector3f& body, const Eigen::Vector3f& colour) {
    const Eigen::Vector3f q = toOptical(body);
    if (q.z() <= 0.3f)
      return;
    const int u = static_cast<int>(std::lround(kF * q.x() / q.z() + kCx));
    const int v = static_cast<int>(std::lround(kF * q.y() / q.z() + kCy));
    if (u < 0 || v < 0 || u >= kWidth || v >= kHeight)
      return;
    Splat& s = zbuf[v * kWidth + u];
    if (q.z() < s.z)
    {
      s.z = q.z();
      s.r = static_cast<std::uint8_t>(255 * colour.x());
      s.g = static_cast<std::uint8_t>(255 * colour.y());
      s.b = static_cast<std::uint8_t>(255 * colour.z());
      is_person[v * kWidth + u] = 1;
    }
  };
  for (const Part& part : parts)
  {
    const Eigen::Vector3f axis = part.b - part.a;
    const float len = axis.norm();
    const Eigen::Vector3f u = axis / len, e1 = perpendicular(u), e2 = u.cross(e1);
    const int n_phi = std::max(8, static_cast<int>(2 * kPi * part.radius / kStep));
    for (int k = 0; k < n_phi; ++k)
    {
      const float phi = 2 * kPi * k / n_phi;
      const Eigen::Vector3f radial = std::cos(phi) * e1 + std::sin(phi) * e2;
      for (float s = 0; s <= len; s += kStep)
        splat(part.a + s * u + part.radius * radial, shade(part.material, s, phi, part.id));
      // Hemispherical caps, textured as the nearest end of the cylinder.
      const int n_theta = std::max(3, static_cast<int>(0.5f * kPi * part.radius / kStep));
      for (int j = 1; j <= n_theta; ++j)
      {
        const float th = 0.5f * kPi * j / n_theta, c = std::cos(th), sn = std::sin(th);
        splat(part.a + part.radius * (c * radial - sn * u), shade(part.material, -sn * part.radius, phi, part.id));
        splat(part.b + part.radius * (c * radial + sn * u), shade(part.material, len + sn * part.radius, phi, part.id));
      }
    }
  }

  if (with_room)
  {
    // Floor (y = 0 in body coordinates) and a back wall 1.8 m behind the person, tiled.
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u)
      {
        Splat& s = zbuf[v * kWidth + u];
        const Eigen::Vector3f ray((u - kCx) / kF, (v - kCy) / kF, 1.0f);  // z = 1
        const float wall_z = params_.distance + 1.8f;
        float z = wall_z;
        Eigen::Vector3f hit = ray * z;
        if (ray.y() > 0)
        {
          const float floor_z = params_.camera_height / ray.y();
          if (floor_z < z)
          {
            z = floor_z;
            hit = ray * z;
          }
        }
        if (z >= s.z || z > 6.0f)
          continue;
        const int tile = (static_cast<int>(std::floor(hit.x() / 0.3f)) + static_cast<int>(std::floor(hit.z() / 0.3f)) +
                          static_cast<int>(std::floor(hit.y() / 0.3f))) & 1;
        const float g = 0.85f + 0.3f * grain(99, static_cast<std::uint32_t>(hit.x() * 100 + 1e4),
                                             static_cast<std::uint32_t>((hit.y() + hit.z()) * 100 + 1e4));
        const float base = (tile ? 0.55f : 0.7f) * g;
        s.z = z;
        s.r = static_cast<std::uint8_t>(std::min(255.0f, 255 * base));
        s.g = static_cast<std::uint8_t>(std::min(255.0f, 240 * base));
        s.b = static_cast<std::uint8_t>(std::min(255.0f, 210 * base));
      }
  }

  std::mt19937 rng(params_.seed * 7919u + static_cast<std::uint32_t>(i));
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_int_distribution<int> cnoise(-params_.colour_noise, params_.colour_noise);
  auto jitter = [&](std::uint8_t c) { return static_cast<std::uint8_t>(std::clamp(c + cnoise(rng), 0, 255)); };
  organized.clear();
  organized.width = kWidth;
  organized.height = kHeight;
  organized.is_dense = false;
  organized.points.resize(kWidth * kHeight);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
    {
      const Splat& s = zbuf[v * kWidth + u];
      PointT& p = organized.points[v * kWidth + u];
      if (!std::isfinite(s.z))
      {
        p.x = p.y = p.z = nan;
        p.r = p.g = p.b = 0;
        continue;
      }
      // The Kinect measures disparity, in steps of 1/8 pixel, with noise: depth noise of
      // depth_noise * z^2 standard deviation and quantisation steps that also grow with z^2.
      const float fb = kF * kBaseline;
      const float disparity = std::round((fb / s.z + params_.depth_noise * fb * gauss(rng)) * 8.0f) / 8.0f;
      const float z = fb / disparity;
      p.x = (u - kCx) / kF * z;
      p.y = (v - kCy) / kF * z;
      p.z = z;
      p.r = jitter(s.r);
      p.g = jitter(s.g);
      p.b = jitter(s.b);
    }
  if (mask)
    *mask = std::move(is_person);
}

Cloud MovingPerson::personCloud(int i, float voxel) const
{
  Cloud organized;
  std::vector<std::uint8_t> mask;
  render(i, organized, &mask, false);
  Cloud person;
  for (std::size_t k = 0; k < organized.size(); ++k)
    if (mask[k] && std::isfinite(organized.points[k].z))
      person.push_back(organized.points[k]);
  return voxelise(person, voxel);
}

Cloud voxelise(const Cloud& in, float voxel)
{
  auto input = std::make_shared<Cloud>(in);
  pcl::VoxelGrid<PointT> grid;
  grid.setInputCloud(input);
  grid.setLeafSize(voxel, voxel, voxel);
  Cloud out;
  grid.filter(out);
  return out;
}

}  // namespace bench
}  // namespace action_flow
