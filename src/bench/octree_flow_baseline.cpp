#include "octree_flow_baseline.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace bench
{
OctreeFlowBaseline::OctreeFlowBaseline(const FlowParams& params, double resolution)
  : params_(params), resolution_(resolution)
{
  if (!(resolution_ > 0.0))
    throw std::invalid_argument("OctreeFlowBaseline: octree resolution must be positive");
  if (params_.k < 1)
    throw std::invalid_argument("OctreeFlowBaseline: k must be at least 1");
}

std::unique_ptr<OctreeFlowBaseline::Frame> OctreeFlowBaseline::prepare(const Cloud& cloud, double stamp) const
{
  auto f = std::make_unique<Frame>();
  f->stamp = stamp;
  f->cloud.reset(new Cloud);
  f->cloud->reserve(cloud.size());
  for (const auto& p : cloud.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    f->cloud->push_back(p);
    f->colour.push_back(hsvCone(rgbToHsv(p.r, p.g, p.b)));
  }
  f->octree = std::make_unique<pcl::octree::OctreePointCloudSearch<PointT>>(resolution_);
  f->octree->setInputCloud(f->cloud);
  f->octree->addPointsFromInputCloud();
  return f;
}

std::vector<int> OctreeFlowBaseline::match(const Frame& from, const Frame& to) const
{
  std::vector<int> out(from.cloud->size(), 0);
  if (to.cloud->empty())
    return out;
  std::vector<int> idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < from.cloud->size(); ++i)
  {
    to.octree->nearestKSearch(from.cloud->points[i], params_.k, idx, d2);
    int best = idx.empty() ? 0 : idx[0];
    float best_d = std::numeric_limits<float>::infinity();
    for (int j : idx)
    {
      const float d = (from.colour[i] - to.colour[j]).squaredNorm();
      if (d < best_d)
      {
        best_d = d;
        best = j;
      }
    }
    out[i] = best;
  }
  return out;
}

std::vector<Correspondence> OctreeFlowBaseline::correspond(const Frame& source, const Frame& target,
                                                           FlowStats& stats) const
{
  std::vector<Correspondence> out;
  if (source.cloud->empty() || target.cloud->empty())
    return out;
  const std::vector<int> t2s = match(target, source);
  stats.matched = t2s.size();
  if (!params_.reciprocal)
  {
    for (std::size_t t = 0; t < t2s.size(); ++t)
      out.push_back({ t, static_cast<std::size_t>(t2s[t]) });
    return out;
  }
  const std::vector<int> s2t = match(source, target);
  for (std::size_t t = 0; t < t2s.size(); ++t)
    if (s2t[t2s[t]] == static_cast<int>(t))
      out.push_back({ t, static_cast<std::size_t>(t2s[t]) });
  stats.removed_reciprocal = stats.matched - out.size();
  return out;
}

FlowVectors OctreeFlowBaseline::velocities(const Frame& source, const Frame& target,
                                           const std::vector<Correspondence>& matches) const
{
  FlowVectors out;
  out.reserve(matches.size());
  const float inv_dt = static_cast<float>(1.0 / (target.stamp - source.stamp));
  for (const auto& m : matches)
  {
    const Eigen::Vector3f p = target.cloud->points[m.target].getVector3fMap();
    out.push_back({ p, (p - source.cloud->points[m.source].getVector3fMap()) * inv_dt });
  }
  return out;
}

FlowVectors OctreeFlowBaseline::rejectOutliers(const Frame& target, const std::vector<Correspondence>& matches,
                                               const FlowVectors& flow, FlowStats& stats) const
{
  std::vector<float> speed(target.cloud->size(), 0.0f);
  std::vector<std::size_t> moving;
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
  std::vector<int> near;
  std::vector<float> d2;
  for (std::size_t i : moving)
  {
    const int self = static_cast<int>(matches[i].target);
    target.octree->radiusSearch(target.cloud->points[self], params_.neighbour_radius, near, d2);
    bool fast = false;
    for (int j : near)
      if (j != self && speed[j] > params_.isolation_speed)
      {
        fast = true;
        break;
      }
    if (fast)
      out.push_back(flow[i]);
    else
      ++stats.removed_isolated;
  }
  return out;
}

}  // namespace bench
}  // namespace action_flow
