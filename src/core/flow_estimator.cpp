// The paper's 3D flow estimation (Munaro et al. 2013), one function per step:
//   step 1  match():          each point's K nearest in XYZ in the next frame, of those the nearest
//                             in colour (HSV cone), searched on the frame's grid (neighbour_grid.h);
//   step 2  correspond():     kept where the match is reciprocal (optional);
//   step 3  velocities():     displacement over the frames' time difference;
//   step 4  rejectOutliers(): dropped when slower than min_speed, or isolated (no other point faster
//                             than isolation_speed within neighbour_radius).
#include <action_flow/flow_estimator.h>

#include "neighbour_grid.h"

#include <algorithm>
#include <cstring>
#include <cstdint>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
Hsv rgbToHsv(std::uint8_t r8, std::uint8_t g8, std::uint8_t b8)
{
  const float r = r8 / 255.0f, g = g8 / 255.0f, b = b8 / 255.0f;
  const float max = std::max({ r, g, b });
  const float min = std::min({ r, g, b });
  const float delta = max - min;
  Hsv out{ 0.0f, max > 0.0f ? delta / max : 0.0f, max };
  if (delta > 0.0f)
  {
    float h;
    if (max == r)
      h = (g - b) / delta;
    else if (max == g)
      h = 2.0f + (b - r) / delta;
    else
      h = 4.0f + (r - g) / delta;
    h /= 6.0f;
    out.h = h < 0.0f ? h + 1.0f : h;
  }
  return out;
}

Eigen::Vector3f hsvCone(const Hsv& c)
{
  const float chroma = c.s * c.v, angle = 6.2831853f * c.h;
  return { chroma * std::cos(angle), chroma * std::sin(angle), c.v };
}

float hsvDistance(const Hsv& a, const Hsv& b)
{
  return (hsvCone(a) - hsvCone(b)).norm();
}

FlowEstimator::FlowEstimator(const FlowParams& params) : params_(params)
{
  if (params_.k < 1)
    throw std::invalid_argument("FlowEstimator: k must be at least 1");
  if (!(params_.min_speed >= 0.0f) || !(params_.isolation_speed >= 0.0f) || !(params_.neighbour_radius > 0.0f))
    throw std::invalid_argument("FlowEstimator: speeds must be >= 0 and neighbour_radius > 0");
}

std::vector<std::size_t> FlowEstimator::match(const FlowFrame& from, const FlowFrame& to) const
{
  std::vector<std::size_t> out(from.size(), 0);
  if (to.empty() || from.empty())
    return out;
  std::vector<std::uint32_t> all(from.size());
  for (std::uint32_t i = 0; i < all.size(); ++i)
    all[i] = i;
  matchNearest(from, to.index(), static_cast<std::size_t>(params_.k), all, out);
  return out;
}

std::vector<Correspondence> FlowEstimator::correspond(const FlowFrame& source, const FlowFrame& target,
                                                      FlowStats& stats) const
{
  std::vector<Correspondence> out;
  if (source.empty() || target.empty())
    return out;
  const std::vector<std::size_t> t2s = match(target, source);
  stats.matched = t2s.size();
  if (!params_.reciprocal)
  {
    out.reserve(t2s.size());
    for (std::size_t t = 0; t < t2s.size(); ++t)
      out.push_back({ t, t2s[t] });
    return out;
  }
  // The source->target match is needed only for the source points that some target point chose:
  // those alone are matched back, instead of a second full pass.
  std::vector<std::uint8_t> chosen(source.size(), 0);
  std::vector<std::uint32_t> back;
  for (std::size_t s : t2s)
    if (!chosen[s])
    {
      chosen[s] = 1;
      back.push_back(static_cast<std::uint32_t>(s));
    }
  std::vector<std::size_t> s2t(source.size(), 0);
  matchNearest(source, target.index(), static_cast<std::size_t>(params_.k), back, s2t);
  for (std::size_t t = 0; t < t2s.size(); ++t)
  {
    if (s2t[t2s[t]] == t)
      out.push_back({ t, t2s[t] });
  }
  stats.removed_reciprocal = stats.matched - out.size();
  return out;
}

FlowVectors FlowEstimator::velocities(const FlowFrame& source, const FlowFrame& target,
                                      const std::vector<Correspondence>& matches, double dt)
{
  FlowVectors out;
  out.reserve(matches.size());
  const float inv_dt = static_cast<float>(1.0 / dt);
  for (const auto& m : matches)
    out.push_back({ target.point(m.target), (target.point(m.target) - source.point(m.source)) * inv_dt });
  return out;
}

FlowVectors FlowEstimator::rejectOutliers(const FlowFrame& target, const std::vector<Correspondence>& matches,
                                          const FlowVectors& flow, FlowStats& stats) const
{
  // Speed of every target point that survived the slow-point rule; 0 for all others.
  std::vector<float> speed(target.size(), 0.0f);
  std::vector<std::size_t> moving;  // indices into matches/flow
  for (std::size_t i = 0; i < flow.size(); ++i)
  {
    const float s = flow[i].velocity.norm();
    if (s < params_.min_speed)
    {
      ++stats.removed_slow;
      continue;
    }
    speed[matches[i].target] = s;
    moving.push_back(i);
  }
  FlowVectors out;
  out.reserve(moving.size());
  // Radius search straight on the grid, stopping at the first fast neighbour.
  const FlowFrame::Index& ix = target.index();
  const float r2 = params_.neighbour_radius * params_.neighbour_radius;
  const int n[3] = { ix.nx, ix.ny, ix.nz };
  for (std::size_t i : moving)
  {
    const std::size_t self = matches[i].target;
    const Eigen::Vector3f& q = target.point(self);
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
    {
      lo[a] = ix.coord(q[a] - params_.neighbour_radius, ix.origin[a], n[a]);
      hi[a] = ix.coord(q[a] + params_.neighbour_radius, ix.origin[a], n[a]);
    }
    bool has_fast_neighbour = false;
    for (int c = lo[2]; c <= hi[2] && !has_fast_neighbour; ++c)
      for (int b = lo[1]; b <= hi[1] && !has_fast_neighbour; ++b)
      {
        const std::size_t row = static_cast<std::size_t>(ix.nx) * (b + static_cast<std::size_t>(ix.ny) * c);
        for (std::uint32_t s = ix.start[row + lo[0]], e = ix.start[row + hi[0] + 1]; s < e; ++s)
        {
          const float dx = ix.x[s] - q.x(), dy = ix.y[s] - q.y(), dz = ix.z[s] - q.z();
          const std::uint32_t j = ix.id[s];
          if (dx * dx + dy * dy + dz * dz < r2 && j != self && speed[j] > params_.isolation_speed)
          {
            has_fast_neighbour = true;
            break;
          }
        }
      }
    if (has_fast_neighbour)
      out.push_back(flow[i]);
    else
      ++stats.removed_isolated;
  }
  return out;
}

FlowResult FlowEstimator::estimate(const FlowFrame& source, const FlowFrame& target) const
{
  FlowVectors unfiltered;
  return estimate(source, target, unfiltered);
}

FlowResult FlowEstimator::estimate(const FlowFrame& source, const FlowFrame& target, FlowVectors& unfiltered) const
{
  FlowResult result;
  result.dt = target.stamp() - source.stamp();
  if (!std::isfinite(result.dt) || result.dt <= 0.0)
  {
    std::ostringstream msg;
    msg << "FlowEstimator: target stamp must be later than source stamp (dt = " << result.dt << " s)";
    throw std::invalid_argument(msg.str());
  }
  result.stats.source_points = source.size();
  result.stats.target_points = target.size();
  const auto matches = correspond(source, target, result.stats);
  unfiltered = velocities(source, target, matches, result.dt);
  result.flow = params_.reject_outliers ? rejectOutliers(target, matches, unfiltered, result.stats) : unfiltered;
  result.stats.kept = result.flow.size();
  return result;
}

}  // namespace action_flow
