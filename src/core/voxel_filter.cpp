#include <action_flow/voxel_filter.h>

#include <pcl/common/point_tests.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

namespace action_flow
{
namespace
{
// A stable least-significant-digit radix sort of @p entries by voxel index (all below 2^bits),
// kBits at a time through @p spare: points of one voxel stay in the order they came.
template <typename Entry>
void sortByVoxel(std::vector<Entry>& entries, std::vector<Entry>& spare, int bits)
{
  constexpr int kBits = 11;
  constexpr unsigned kMask = (1u << kBits) - 1u;
  spare.resize(entries.size());
  for (int shift = 0; shift < bits; shift += kBits)
  {
    std::array<unsigned, kMask + 1> start{};
    for (const Entry& e : entries)
      ++start[(e.idx >> shift) & kMask];
    unsigned sum = 0;
    for (unsigned& s : start)
      sum += std::exchange(s, sum);
    for (const Entry& e : entries)
      spare[start[(e.idx >> shift) & kMask]++] = e;
    entries.swap(spare);
  }
}
}  // namespace

// pcl::VoxelGrid<PointT>::applyFilter's steps (PCL 1.13) with the same arithmetic: the same bounding
// box, voxel indices, output order and averaging. PCL sorts with boost's spreadsort, which is not
// stable, so the order in which a voxel's points are summed, and with it a centroid's last bit, can
// differ; here they are summed in the order they come. The tests VoxelFilter.* compare the two.
void VoxelFilter::filter(const Cloud& in, float leaf, const pcl::Indices* indices, Cloud& out)
{
  if (!std::isfinite(leaf) || leaf <= 0.0f)
    throw std::invalid_argument("VoxelFilter: the leaf size must be a positive finite length");
  out.header = in.header;
  out.sensor_origin_ = in.sensor_origin_;
  out.sensor_orientation_ = in.sensor_orientation_;
  out.height = 1;
  out.is_dense = true;
  out.clear();
  const std::size_t n = indices ? indices->size() : in.size();
  const auto at = [&](std::size_t k) { return indices ? static_cast<std::size_t>((*indices)[k]) : k; };
  const auto usable = [&](const PointT& p) { return in.is_dense || pcl::isXYZFinite(p); };

  // The bounding box of the usable points, in voxels.
  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::max());
  Eigen::Array3f hi = Eigen::Array3f::Constant(std::numeric_limits<float>::lowest());
  for (std::size_t k = 0; k < n; ++k)
  {
    const PointT& p = in[at(k)];
    if (!usable(p))
      continue;
    lo = lo.min(p.getArray3fMap());
    hi = hi.max(p.getArray3fMap());
  }
  if (!(lo <= hi).all())
  {
    out.width = 0;
    return;
  }
  const float inverse = 1.0f / leaf;
  const std::int64_t dx = static_cast<std::int64_t>((hi[0] - lo[0]) * inverse) + 1;
  const std::int64_t dy = static_cast<std::int64_t>((hi[1] - lo[1]) * inverse) + 1;
  const std::int64_t dz = static_cast<std::int64_t>((hi[2] - lo[2]) * inverse) + 1;
  Eigen::Array3i min_b, div;
  for (int a = 0; a < 3; ++a)
  {
    min_b[a] = static_cast<int>(std::floor(lo[a] * inverse));
    div[a] = static_cast<int>(std::floor(hi[a] * inverse)) - min_b[a] + 1;
  }
  // PCL checks dx * dy * dz; the voxel indices run up to div's product, which can be larger (a box
  // 2047.2 voxels long from 0.9 of a voxel spans 2049). Both in double: at a tiny leaf they overflow
  // even 64 bits.
  const double cells = static_cast<double>(div[0]) * static_cast<double>(div[1]) * static_cast<double>(div[2]);
  if (static_cast<double>(dx) * static_cast<double>(dy) * static_cast<double>(dz) >
          static_cast<double>(std::numeric_limits<std::int32_t>::max()) ||
      cells > static_cast<double>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("VoxelFilter: the leaf size is too small for the cloud's extent");
  const int mul_y = div[0], mul_z = div[0] * div[1];

  // Each usable point with its voxel's linear index, sorted by that index.
  entries_.clear();
  entries_.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
  {
    const std::size_t i = at(k);
    const PointT& p = in[i];
    if (!usable(p))
      continue;
    const int ijk0 = static_cast<int>(std::floor(p.x * inverse) - static_cast<float>(min_b[0]));
    const int ijk1 = static_cast<int>(std::floor(p.y * inverse) - static_cast<float>(min_b[1]));
    const int ijk2 = static_cast<int>(std::floor(p.z * inverse) - static_cast<float>(min_b[2]));
    entries_.push_back({ static_cast<unsigned int>(ijk0 + ijk1 * mul_y + ijk2 * mul_z), static_cast<unsigned int>(i) });
  }
  const auto last_cell = static_cast<std::uint64_t>(cells) - 1;
  int bits = 0;
  while (bits < 32 && (last_cell >> bits) != 0)
    ++bits;
  sortByVoxel(entries_, spare_, bits);

  // One centroid per run of equal indices, averaged as pcl::CentroidPoint does (float sums; each
  // colour channel's mean truncated).
  for (std::size_t first = 0; first < entries_.size();)
  {
    Eigen::Vector3f xyz = Eigen::Vector3f::Zero();
    float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
    std::size_t last = first;
    for (; last < entries_.size() && entries_[last].idx == entries_[first].idx; ++last)
    {
      const PointT& q = in[entries_[last].point];
      xyz += q.getVector3fMap();
      r += static_cast<float>(q.r);
      g += static_cast<float>(q.g);
      b += static_cast<float>(q.b);
      a += static_cast<float>(q.a);
    }
    const float n = static_cast<float>(last - first);
    PointT p;
    p.getVector3fMap() = xyz / n;
    p.rgba = static_cast<std::uint32_t>(a / n) << 24 | static_cast<std::uint32_t>(r / n) << 16 |
             static_cast<std::uint32_t>(g / n) << 8 | static_cast<std::uint32_t>(b / n);
    out.push_back(p);
    first = last;
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
}

Cloud voxelFiltered(const Cloud& in, float leaf, const pcl::IndicesConstPtr& indices)
{
  Cloud out;
  VoxelFilter().filter(in, leaf, indices.get(), out);
  return out;
}

}  // namespace action_flow
