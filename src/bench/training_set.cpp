#include "training_set.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace action_flow
{
namespace bench
{
namespace
{
// An action: which cubes move, in which direction, how fast and with which rhythm.
struct ActionPattern
{
  struct Mover
  {
    int cube;
    Eigen::Vector3f direction, second;  // main and harmonic directions
    float amplitude, phase;
  };
  std::vector<Mover> movers;
  float hz;
};
}  // namespace

std::vector<DescriptorSequence> makeSequences(int count, int actions, int descriptor_size, std::uint32_t seed)
{
  if (count < 1 || actions < 1 || descriptor_size < 3 || descriptor_size % 3 != 0)
    throw std::invalid_argument("makeSequences: need count >= 1, actions >= 1 and a size that is a multiple of 3");
  const int cubes = descriptor_size / 3;
  // The action patterns come from a fixed seed so that training and query sets share them.
  std::mt19937 pattern_rng(12345u);
  // Motion happens where limbs are: the grid's middle depth layers (for the paper's 4x4x4 grid the
  // 32 cubes with z index 1 or 2); the front and back layers stay nearly empty, as on real data.
  const int layer = std::max(1, cubes / 4);
  const int first_cube = cubes >= 8 ? layer : 0, limb_cubes = cubes >= 8 ? 2 * layer : cubes;
  std::uniform_int_distribution<int> limb(0, limb_cubes - 1);
  auto cube = [&](std::mt19937& r) { return first_cube + limb(r); };
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto randomDirection = [&](std::mt19937& r) {
    Eigen::Vector3f v(gauss(r), gauss(r), gauss(r));
    return Eigen::Vector3f(v.normalized());
  };
  std::vector<ActionPattern> patterns(actions);
  for (auto& p : patterns)
  {
    p.hz = 0.4f + 1.2f * unit(pattern_rng);
    const int n = 3 + static_cast<int>(unit(pattern_rng) * 5);
    for (int m = 0; m < n; ++m)
      p.movers.push_back({ cube(pattern_rng), randomDirection(pattern_rng), randomDirection(pattern_rng),
                           0.3f + unit(pattern_rng), 6.2831853f * unit(pattern_rng) });
  }

  std::mt19937 rng(seed);
  std::vector<DescriptorSequence> out(count);
  for (int s = 0; s < count; ++s)
  {
    const ActionPattern& p = patterns[s % actions];
    DescriptorSequence& seq = out[s];
    seq.label = "action_" + std::to_string(s % actions);
    const int frames = 40 + static_cast<int>(unit(rng) * 110);
    const float pace = 0.8f + 0.4f * unit(rng), scale = 0.7f + 0.6f * unit(rng), phase0 = 0.5f * gauss(rng);
    // This performer's direction error per mover (a person does the action a little differently).
    std::vector<Eigen::Vector3f> tilt;
    for (std::size_t m = 0; m < p.movers.size(); ++m)
      tilt.push_back(0.25f * Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng)));
    for (int f = 0; f < frames; ++f)
    {
      const float t = f / 30.0f;
      Eigen::VectorXf d = Eigen::VectorXf::Zero(descriptor_size);
      for (std::size_t m = 0; m < p.movers.size(); ++m)
      {
        const auto& mv = p.movers[m];
        const float w = 6.2831853f * p.hz * pace * t + mv.phase + phase0;
        const Eigen::Vector3f v =
            scale * mv.amplitude * (std::sin(w) * (mv.direction + tilt[m]) + 0.4f * std::sin(2 * w) * mv.second);
        d.segment<3>(3 * mv.cube) += v;
      }
      // Noise that survives outlier rejection: a few random cubes with small flow.
      const int noisy = static_cast<int>(unit(rng) * 4);
      for (int k = 0; k < noisy; ++k)
        d.segment<3>(3 * cube(rng)) += 0.15f * Eigen::Vector3f(gauss(rng), gauss(rng), gauss(rng));
      d += 0.003f * Eigen::VectorXf::NullaryExpr(descriptor_size, [&]() { return gauss(rng); });
      const float norm = d.norm();
      if (norm > 0.0f)
        d /= norm;
      seq.frames.push_back(d);
      seq.stamps.push_back(t);
    }
  }
  return out;
}

}  // namespace bench
}  // namespace action_flow
