/**
 * @file voxel_filter.h
 * @brief A cloud at one voxel size, as the people tracker makes it: one centroid per occupied voxel,
 *        colours averaged. The tracker, the benchmarks and the tests' hand-built clouds all voxelise
 *        through this one filter.
 */
#pragma once

#include <action_flow/types.h>

#include <pcl/pcl_base.h>

#include <cstdint>
#include <vector>

namespace action_flow
{
/**
 * @brief pcl::VoxelGrid's result (the same voxels, in the same order, with the same centroids and
 *        colours up to a float's last bit), from buffers kept from call to call.
 *
 * PCL's filter allocates its work lists afresh on every call (at 640x480 they are megabytes, and
 * their page faults cost) and sorts them with a general sort; this one keeps its lists and sorts
 * by radix. It takes under half of PCL's time on the tracker's frames (`bench`, benchmarks/results.md).
 * Keep one filter per stream and call it each frame. Not thread-safe: one filter per thread.
 */
class VoxelFilter
{
public:
  /**
   * @brief The points of @p in (only those at @p indices, when given; non-finite points skipped
   *        unless @p in is dense) into @p out, one centroid per occupied cube of side @p leaf
   *        (metres). @p out keeps @p in's header and sensor pose.
   * @throws std::invalid_argument when @p leaf is not a positive finite size.
   */
  void filter(const Cloud& in, float leaf, const pcl::Indices* indices, Cloud& out);

private:
  struct Entry  // as pcl::VoxelGrid's work list: voxel index, point index
  {
    unsigned int idx;
    unsigned int point;
  };
  std::vector<Entry> entries_, spare_;
};

/**
 * @brief The points of @p in (only those at @p indices, when given) filtered to one centroid per
 *        occupied cube of side @p leaf (metres). The result keeps @p in's header. A one-off
 *        VoxelFilter.
 */
Cloud voxelFiltered(const Cloud& in, float leaf, const pcl::IndicesConstPtr& indices = nullptr);

}  // namespace action_flow
