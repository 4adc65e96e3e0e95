#include <action_flow/facing.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace action_flow
{
namespace
{
constexpr float kPi = 3.14159265358979f;
// The trunk's half width and half depth for a person of the grid's reference height (1.75 m).
constexpr float kHalfWidth = 0.18f, kHalfDepth = 0.11f;
// Chest height, as shares of the person's height.
constexpr float kBandLow = 0.55f, kBandHigh = 0.8f;
// Residuals (in ellipse radii) beyond this count as this much: arms, hands, noise.
constexpr float kResidualCap = 0.35f;
constexpr int kMinPoints = 30, kMaxPoints = 600, kCoarseSteps = 24, kIterations = 8;

// How badly the ellipse turned by @p angle fits @p pts (ground-plane x, z), its centre fitted.
float misfit(const std::vector<Eigen::Vector2f>& pts, float angle, float a, float b, const Eigen::Vector2f& start)
{
  // u: along the shoulders; w: where the person faces (sin, cos in x, z).
  const Eigen::Vector2f w(std::sin(angle), std::cos(angle)), u(w.y(), -w.x());
  Eigen::Matrix2f rot;
  rot.row(0) = u.transpose() / a;
  rot.row(1) = w.transpose() / b;
  Eigen::Vector2f c = start;
  float score = 0.0f;
  for (int it = 0; it <= kIterations; ++it)
  {
    Eigen::Matrix2f jtj = Eigen::Matrix2f::Zero();
    Eigen::Vector2f jtr = Eigen::Vector2f::Zero();
    score = 0.0f;
    for (const auto& p : pts)
    {
      const Eigen::Vector2f e = rot * (p - c);
      const float radius = std::max(e.norm(), 1e-4f), r = radius - 1.0f;
      score += std::min(r * r, kResidualCap * kResidualCap);
      if (std::abs(r) > kResidualCap)
        continue;  // capped: no pull on the centre
      const Eigen::Vector2f j = -(rot.transpose() * e) / radius;  // d r / d c
      jtj += j * j.transpose();
      jtr += j * r;
    }
    if (it == kIterations || jtj.determinant() < 1e-9f)
      break;
    c -= jtj.ldlt().solve(jtr);
  }
  return score / static_cast<float>(pts.size());
}
}  // namespace

float facingFromTrunk(const Cloud& person, const PersonFrame& where)
{
  std::vector<Eigen::Vector2f> pts;
  for (const auto& p : person.points)
  {
    const Eigen::Vector3f xyz = p.getVector3fMap();
    if (!xyz.allFinite())
      continue;
    const Eigen::Vector3f l = where.toLocal(xyz);
    if (l.y() >= kBandLow * where.height && l.y() <= kBandHigh * where.height)
      pts.emplace_back(l.x(), l.z());
  }
  if (static_cast<int>(pts.size()) < kMinPoints)
    return std::numeric_limits<float>::quiet_NaN();
  if (static_cast<int>(pts.size()) > kMaxPoints)  // an even subsample: the fit costs per point
  {
    const std::size_t n = pts.size();
    std::vector<Eigen::Vector2f> kept;
    for (int i = 0; i < kMaxPoints; ++i)
      kept.push_back(pts[static_cast<std::size_t>(i) * n / kMaxPoints]);
    pts.swap(kept);
  }
  const float scale = where.height / 1.75f, a = kHalfWidth * scale, b = kHalfDepth * scale;
  Eigen::Vector2f mean = Eigen::Vector2f::Zero();
  for (const auto& p : pts)
    mean += p;
  mean /= static_cast<float>(pts.size());
  // The camera sees the near side: the centre lies behind the points (z points to the camera).
  const Eigen::Vector2f start = mean - Eigen::Vector2f(0.0f, 0.6f * b);
  const float step = kPi / kCoarseSteps;
  std::array<float, kCoarseSteps> score;
  int best = 0;
  for (int i = 0; i < kCoarseSteps; ++i)
  {
    score[i] = misfit(pts, -kPi / 2 + step * (i + 1), a, b, start);
    if (score[i] < score[best])
      best = i;
  }
  // A parabola through the best turn and its neighbours (the turns wrap around by 180 degrees).
  const float s0 = score[(best + kCoarseSteps - 1) % kCoarseSteps], s1 = score[best], s2 = score[(best + 1) % kCoarseSteps];
  const float curvature = s0 - 2.0f * s1 + s2;
  const float shift = curvature > 1e-12f ? std::clamp(0.5f * (s0 - s2) / curvature, -0.5f, 0.5f) : 0.0f;
  float angle = -kPi / 2 + step * (best + 1 + shift);
  if (angle <= -kPi / 2)
    angle += kPi;
  else if (angle > kPi / 2)
    angle -= kPi;
  return angle;
}

}  // namespace action_flow
