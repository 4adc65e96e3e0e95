#include <action_flow/flow_estimator.h>

#include <nanoflann.hpp>

#include <algorithm>
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

// nanoflann adaptor over the frame's own point vector: the tree indexes it in place.
struct PointsAdaptor
{
  const std::vector<Eigen::Vector3f>& pts;
  std::size_t kdtree_get_point_count() const { return pts.size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return pts[i][dim]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const
  {
    return false;
  }
};

struct FlowFrame::Index
{
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointsAdaptor>,
                                                   PointsAdaptor, 3, std::size_t>;
  PointsAdaptor adaptor;
  Tree tree;
  explicit Index(const std::vector<Eigen::Vector3f>& pts)
    : adaptor{ pts }, tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(10))
  {
    tree.buildIndex();
  }
};

FlowFrame::FlowFrame(const Cloud& cloud, double stamp) : stamp_(stamp)
{
  xyz_.reserve(cloud.size());
  colour_.reserve(cloud.size());
  for (const auto& p : cloud.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    xyz_.emplace_back(p.x, p.y, p.z);
    colour_.push_back(hsvCone(rgbToHsv(p.r, p.g, p.b)));
  }
  index_ = std::make_unique<Index>(xyz_);
}

FlowFrame::~FlowFrame() = default;

void FlowFrame::nearest(const Eigen::Vector3f& q, int k, std::vector<std::size_t>& indices,
                        std::vector<float>& sq_dists) const
{
  const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), xyz_.size());
  indices.resize(n);
  sq_dists.resize(n);
  if (n == 0)
    return;
  nanoflann::KNNResultSet<float, std::size_t> result(n);
  result.init(indices.data(), sq_dists.data());
  index_->tree.findNeighbors(result, q.data(), nanoflann::SearchParams());
  indices.resize(result.size());
  sq_dists.resize(result.size());
}

void FlowFrame::within(const Eigen::Vector3f& q, float radius, std::vector<std::size_t>& indices) const
{
  indices.clear();
  if (xyz_.empty())
    return;
  std::vector<std::pair<std::size_t, float>> found;
  nanoflann::SearchParams params;
  params.sorted = false;
  index_->tree.radiusSearch(q.data(), radius * radius, found, params);
  indices.reserve(found.size());
  for (const auto& f : found)
    indices.push_back(f.first);
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
  if (to.empty())
    return out;
  std::vector<std::size_t> idx;
  std::vector<float> d2;
  for (std::size_t i = 0; i < from.size(); ++i)
  {
    to.nearest(from.point(i), params_.k, idx, d2);
    // Nearest first from the tree, and strict '<': among equal colours the closest point wins.
    std::size_t best = idx[0];
    float best_d = std::numeric_limits<float>::infinity();
    for (std::size_t j : idx)
    {
      const float d = (from.colour(i) - to.colour(j)).squaredNorm();
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
  const std::vector<std::size_t> s2t = match(source, target);
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
  std::vector<std::size_t> near;
  for (std::size_t i : moving)
  {
    const std::size_t self = matches[i].target;
    target.within(target.point(self), params_.neighbour_radius, near);
    const bool has_fast_neighbour = std::any_of(near.begin(), near.end(), [&](std::size_t j) {
      return j != self && speed[j] > params_.isolation_speed;
    });
    if (has_fast_neighbour)
      out.push_back(flow[i]);
    else
      ++stats.removed_isolated;
  }
  return out;
}

FlowResult FlowEstimator::estimate(const FlowFrame& source, const FlowFrame& target) const
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
  FlowVectors flow = velocities(source, target, matches, result.dt);
  result.flow = params_.reject_outliers ? rejectOutliers(target, matches, flow, result.stats) : std::move(flow);
  result.stats.kept = result.flow.size();
  return result;
}

}  // namespace action_flow
