// Hand-built clouds for the core's known-answer tests.
#pragma once

#include <action_flow/types.h>


#include <random>

namespace action_flow
{
namespace test
{
/** A fine random texture: a colour drawn from a hash of index i (deterministic, never near black). */
inline void uniqueColour(PointT& p, int i)
{
  std::uint64_t h = static_cast<std::uint64_t>(i) * 0x9E3779B97F4A7C15ull;  // splitmix64
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  h ^= h >> 31;
  p.r = static_cast<std::uint8_t>(30 + h % 226);
  p.g = static_cast<std::uint8_t>(30 + (h >> 16) % 226);
  p.b = static_cast<std::uint8_t>(30 + (h >> 32) % 226);
}

/** A solid block of nx*ny*nz points on a 0.02 m lattice (a person's voxel size), each its own colour. */
inline Cloud texturedBlock(int nx, int ny, int nz, const Eigen::Vector3f& corner = Eigen::Vector3f(0, 0, 2))
{
  Cloud c;
  int i = 0;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x, ++i)
      {
        PointT p;
        p.x = corner.x() + 0.02f * x;
        p.y = corner.y() + 0.02f * y;
        p.z = corner.z() + 0.02f * z;
        uniqueColour(p, i);
        c.push_back(p);
      }
  return c;
}

/** @p n points drawn uniformly in the box @p lo .. @p hi, each with a random colour (mt19937 @p seed). */
inline Cloud randomBox(unsigned seed, int n, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> x(lo.x(), hi.x()), y(lo.y(), hi.y()), z(lo.z(), hi.z());
  std::uniform_int_distribution<int> c(0, 255);
  Cloud cloud;
  for (int i = 0; i < n; ++i)
  {
    PointT p;
    p.x = x(rng), p.y = y(rng), p.z = z(rng);
    p.r = static_cast<std::uint8_t>(c(rng)), p.g = static_cast<std::uint8_t>(c(rng)), p.b = static_cast<std::uint8_t>(c(rng));
    cloud.push_back(p);
  }
  return cloud;
}

/** The same cloud moved by @p d. */
inline Cloud shifted(const Cloud& in, const Eigen::Vector3f& d)
{
  Cloud out = in;
  for (auto& p : out.points)
  {
    p.x += d.x();
    p.y += d.y();
    p.z += d.z();
  }
  return out;
}

/** The same cloud with Gaussian position noise of @p sigma (m) and colour noise of +-@p colour levels. */
inline Cloud noisy(const Cloud& in, float sigma, int colour, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, sigma);
  std::uniform_int_distribution<int> c(-colour, colour);
  auto jitter = [&](std::uint8_t v) { return static_cast<std::uint8_t>(std::min(255, std::max(0, v + c(rng)))); };
  Cloud out = in;
  for (auto& p : out.points)
  {
    p.x += n(rng);
    p.y += n(rng);
    p.z += n(rng);
    p.r = jitter(p.r);
    p.g = jitter(p.g);
    p.b = jitter(p.b);
  }
  return out;
}

}  // namespace test
}  // namespace action_flow
