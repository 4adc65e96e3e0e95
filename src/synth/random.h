// Deterministic hashing and random numbers for the renderer. Our own generator (not <random>'s
// distributions, whose output differs between standard libraries) so that a seed gives the same
// bytes everywhere.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

namespace action_flow
{
namespace synth
{
inline std::uint64_t mix64(std::uint64_t x)
{
  // splitmix64's finaliser: a bijective avalanche of 64 bits.
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline std::uint64_t hash64(std::uint64_t a, std::uint64_t b, std::uint64_t c = 0, std::uint64_t d = 0)
{
  return mix64(mix64(mix64(mix64(a) ^ b) ^ c) ^ d);
}

/** FNV-1a of a string (std::hash differs between standard libraries). */
inline std::uint64_t hashString(const std::string& s)
{
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char ch : s)
    h = (h ^ ch) * 0x100000001b3ULL;
  return h;
}

/** Uniform in [0,1) from a hash. */
inline float unit(std::uint64_t h) { return float(h >> 40) * (1.0f / 16777216.0f); }

/** Approximately standard normal from one hash: the sum of four 16-bit uniforms, rescaled. */
inline float gauss(std::uint64_t h)
{
  const float s = float(h & 0xffff) + float((h >> 16) & 0xffff) + float((h >> 32) & 0xffff) + float(h >> 48);
  // mean 2*65535, variance 4 * 65536^2 / 12
  return (s - 131070.0f) * (1.7320508f / 65536.0f);
}

/** @brief A small deterministic generator for scene and motion parameters. */
class Rng
{
public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed ^ 0x5851f42d4c957f2dULL)) {}
  std::uint64_t next() { return mix64(state_++); }
  double uniform(double a, double b) { return a + (b - a) * (double(next() >> 11) * (1.0 / 9007199254740992.0)); }
  int integer(int lo, int hi) { return lo + int(next() % std::uint64_t(hi - lo + 1)); }  // inclusive
  bool chance(double p) { return uniform(0, 1) < p; }
  double normal()
  {
    const double u1 = uniform(1e-12, 1.0), u2 = uniform(0.0, 1.0);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }

private:
  std::uint64_t state_;
};

}  // namespace synth
}  // namespace action_flow
