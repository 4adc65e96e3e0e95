/**
 * @file tracker_clustering.h
 * @brief Fixed-radius neighbours and Euclidean clustering on a uniform grid (the people tracker's
 *        clustering, ROS-free).
 *
 * The detector clusters a voxelised room (10-20 thousand points at 0.06 m) with a tolerance of
 * two voxels every frame. pcl::EuclideanClusterExtraction answers the same question with one
 * kd-tree radius search per point; each search allocates its result vectors and enters an OpenMP
 * region, which made clustering about three quarters of the tracker's time. A grid whose cell is
 * the radius answers each query from the 27 cells around it, exactly, with no allocation.
 * test_tracker checks that the clusters are the ones PCL finds.
 */
#pragma once

#include <action_flow/types.h>

#include <pcl/PointIndices.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace action_flow
{
/**
 * @brief Points of a cloud sorted into cubic cells of one radius, for exact "all points within
 *        the radius" queries. Rebuilding reuses the memory of the previous build.
 */
class RadiusGrid
{
public:
  /**
   * @brief Indexes the finite points of @p cloud (kept by pointer: it must outlive the queries and
   *        not change). @p radius must be positive.
   */
  void build(const Cloud& cloud, float radius);

  /** @brief Calls @p visit(index) for every indexed point p with |p - q| <= radius. */
  template <class Visit>
  void forEachWithin(const Eigen::Vector3f& q, Visit&& visit) const;

  /** @brief How many indexed points lie within the radius of @p q (itself included), counting at most @p cap. */
  int countWithin(const Eigen::Vector3f& q, int cap) const;

private:
  bool cellOf(const Eigen::Vector3f& p, Eigen::Vector3i& cell) const;

  const Cloud* cloud_ = nullptr;
  float radius2_ = 0.0f;
  float inverse_cell_ = 0.0f;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  std::vector<std::uint32_t> start_;  ///< per cell (x fastest), its first entry in order_; one past the end last
  std::vector<std::uint32_t> order_;  ///< point indices sorted by cell
};

/**
 * @brief Connected components of the graph "closer than @p tolerance", as
 *        pcl::EuclideanClusterExtraction gives them: components of @p min_size to @p max_size
 *        points, largest first, each one's indices ascending. Non-finite points are skipped.
 *        @p grid is (re)built on @p cloud with the tolerance as radius and can be queried after.
 */
std::vector<pcl::PointIndices> euclideanClusters(const Cloud& cloud, float tolerance, int min_size, int max_size,
                                                 RadiusGrid& grid);

// ---- implementation of the template ----

template <class Visit>
void RadiusGrid::forEachWithin(const Eigen::Vector3f& q, Visit&& visit) const
{
  if (dims_.minCoeff() <= 0 || !q.allFinite())
    return;
  // The cell the query falls in, clamped: a query outside the grid still finds the points within
  // the radius of it, which lie in the border cells.
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a)
  {
    const float f = (q[a] - origin_[a]) * inverse_cell_;
    c[a] = f < 0.0f ? -1 : (f >= dims_[a] ? dims_[a] : static_cast<int>(f));
  }
  const int x0 = std::max(c.x() - 1, 0), x1 = std::min(c.x() + 1, dims_.x() - 1);
  const int y0 = std::max(c.y() - 1, 0), y1 = std::min(c.y() + 1, dims_.y() - 1);
  const int z0 = std::max(c.z() - 1, 0), z1 = std::min(c.z() + 1, dims_.z() - 1);
  for (int z = z0; z <= z1; ++z)
    for (int y = y0; y <= y1; ++y)
    {
      // Cells x0..x1 of one row are contiguous in order_.
      const std::size_t row = (static_cast<std::size_t>(z) * dims_.y() + y) * dims_.x();
      const std::uint32_t end = start_[row + x1 + 1];
      for (std::uint32_t k = start_[row + x0]; k < end; ++k)
      {
        const std::uint32_t i = order_[k];
        if (((*cloud_)[i].getVector3fMap() - q).squaredNorm() <= radius2_)
          visit(i);
      }
    }
}

}  // namespace action_flow
