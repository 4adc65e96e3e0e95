#include "tracker_clustering.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace
{
// Above this many cells the grid's cells grow (a query still looks at 27 cells, each at least the
// radius wide, so it stays exact); 4 M cells is 16 MB of offsets.
constexpr double kMaxCells = 4.0e6;
}  // namespace

void RadiusGrid::build(const Cloud& cloud, float radius)
{
  if (!(radius > 0.0f) || !std::isfinite(radius))
    throw std::invalid_argument("RadiusGrid: the radius must be positive and finite");
  cloud_ = &cloud;
  radius2_ = radius * radius;
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  std::size_t finite = 0;
  for (const auto& p : cloud.points)
    if (p.getVector3fMap().allFinite())
    {
      lo = lo.cwiseMin(p.getVector3fMap());
      hi = hi.cwiseMax(p.getVector3fMap());
      ++finite;
    }
  order_.clear();
  if (finite == 0)
  {
    dims_.setZero();
    start_.assign(1, 0);
    return;
  }
  float cell = radius;
  const Eigen::Vector3d extent = (hi - lo).cast<double>();
  const auto cells = [&](float c) { return ((extent / c).array().floor() + 1.0).prod(); };
  while (cells(cell) > kMaxCells)
    cell *= 2.0f;
  origin_ = lo;
  inverse_cell_ = 1.0f / cell;
  for (int a = 0; a < 3; ++a)
    dims_[a] = static_cast<int>(std::floor(extent[a] / cell)) + 1;
  const std::size_t n_cells = static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z();

  // Counting sort of the points by cell.
  std::vector<std::uint32_t> cell_of(cloud.size(), std::uint32_t(-1));
  start_.assign(n_cells + 1, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i)
  {
    Eigen::Vector3i c;
    if (!cellOf(cloud[i].getVector3fMap(), c))
      continue;
    cell_of[i] = static_cast<std::uint32_t>((static_cast<std::size_t>(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x());
    ++start_[cell_of[i] + 1];
  }
  for (std::size_t c = 0; c < n_cells; ++c)
    start_[c + 1] += start_[c];
  order_.resize(finite);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t i = 0; i < cloud.size(); ++i)
    if (cell_of[i] != std::uint32_t(-1))
      order_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
}

bool RadiusGrid::cellOf(const Eigen::Vector3f& p, Eigen::Vector3i& cell) const
{
  if (!p.allFinite())
    return false;
  for (int a = 0; a < 3; ++a)
    cell[a] = std::min(static_cast<int>((p[a] - origin_[a]) * inverse_cell_), dims_[a] - 1);
  return true;
}

int RadiusGrid::countWithin(const Eigen::Vector3f& q, int cap) const
{
  int n = 0;
  // Counting on past the cap costs little (27 cells); the cap keeps the result comparable with a
  // capped radius search.
  forEachWithin(q, [&](std::uint32_t) { ++n; });
  return std::min(n, cap);
}

std::vector<pcl::PointIndices> euclideanClusters(const Cloud& cloud, float tolerance, int min_size, int max_size,
                                                 RadiusGrid& grid)
{
  grid.build(cloud, tolerance);
  std::vector<pcl::PointIndices> clusters;
  std::vector<char> seen(cloud.size(), 0);
  std::vector<std::uint32_t> queue;
  for (std::size_t seed = 0; seed < cloud.size(); ++seed)
  {
    if (seen[seed] || !cloud[seed].getVector3fMap().allFinite())
      continue;
    // Breadth-first over the neighbours: the component of the seed.
    queue.assign(1, static_cast<std::uint32_t>(seed));
    seen[seed] = 1;
    for (std::size_t head = 0; head < queue.size(); ++head)
      grid.forEachWithin(cloud[queue[head]].getVector3fMap(), [&](std::uint32_t j) {
        if (!seen[j])
        {
          seen[j] = 1;
          queue.push_back(j);
        }
      });
    if (static_cast<int>(queue.size()) < min_size || static_cast<int>(queue.size()) > max_size)
      continue;
    pcl::PointIndices c;
    c.indices.assign(queue.begin(), queue.end());
    std::sort(c.indices.begin(), c.indices.end());
    clusters.push_back(std::move(c));
  }
  std::stable_sort(clusters.begin(), clusters.end(), [](const pcl::PointIndices& a, const pcl::PointIndices& b) {
    return a.indices.size() > b.indices.size();
  });
  return clusters;
}

}  // namespace action_flow
