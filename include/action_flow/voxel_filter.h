/**
 * @file voxel_filter.h
 * @brief A person's cloud at one voxel size, as the people tracker makes it: PCL's VoxelGrid, one
 *        centroid per occupied voxel, colours averaged. The tracker, the benchmarks and the tests'
 *        hand-built clouds all voxelise through this one function.
 */
#pragma once

#include <action_flow/types.h>

#include <pcl/pcl_base.h>

namespace action_flow
{
/**
 * @brief The points of @p in (only those at @p indices, when given) filtered to one centroid per
 *        occupied cube of side @p leaf (metres). The result keeps @p in's header.
 */
Cloud voxelFiltered(const Cloud& in, float leaf, const pcl::IndicesConstPtr& indices = nullptr);

}  // namespace action_flow
