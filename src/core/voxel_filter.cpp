#include <action_flow/voxel_filter.h>

#include <pcl/filters/voxel_grid.h>

namespace action_flow
{
Cloud voxelFiltered(const Cloud& in, float leaf, const pcl::IndicesConstPtr& indices)
{
  Cloud out;
  if (in.empty() || (indices && indices->empty()))
  {
    out.header = in.header;
    return out;
  }
  pcl::VoxelGrid<PointT> grid;
  // VoxelGrid reads the cloud through a shared pointer; a non-owning one spares the copy.
  grid.setInputCloud(Cloud::ConstPtr(&in, [](const Cloud*) {}));
  if (indices)
    grid.setIndices(indices);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(out);
  out.header = in.header;
  return out;
}

}  // namespace action_flow
