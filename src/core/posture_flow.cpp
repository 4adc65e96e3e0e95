#include <action_flow/posture_flow.h>

#include <algorithm>
#include <stdexcept>

namespace action_flow
{
PostureFlowDescriptor::PostureFlowDescriptor(const GridParams& params) : grid_(params)
{
}

std::array<int, 3> PostureFlowDescriptor::parts(int level) const
{
  // Level kLevels-1 is the finest (the grid's parts); each coarser level halves it.
  const int shift = kLevels - 1 - level;
  const GridParams& g = grid_.params();
  return { std::max(1, g.parts_x >> shift), std::max(1, g.parts_y >> shift), std::max(1, g.parts_z >> shift) };
}

int PostureFlowDescriptor::cells(int level) const
{
  const auto p = parts(level);
  return p[0] * p[1] * p[2];
}

int PostureFlowDescriptor::offset(int level) const
{
  int at = 0;
  for (int l = 0; l < level; ++l)
    at += kPostureFlowValuesPerCell * cells(l);
  return at;
}

namespace
{
int cellAt(const Eigen::Vector3f& uvw, const std::array<int, 3>& p)
{
  const int ix = std::min(static_cast<int>(uvw.x() * p[0]), p[0] - 1);
  const int iy = std::min(static_cast<int>(uvw.y() * p[1]), p[1] - 1);
  const int iz = std::min(static_cast<int>(uvw.z() * p[2]), p[2] - 1);
  return ix + p[0] * (iy + p[1] * iz);
}
}  // namespace

Eigen::VectorXf PostureFlowDescriptor::compute(const Cloud& cloud, const FlowVectors& flow,
                                               const PersonFrame& where) const
{
  Eigen::VectorXf d = Eigen::VectorXf::Zero(size());
  if (!(where.height > 0.0f))
    return d;
  std::array<std::array<int, 3>, kLevels> level_parts;
  std::array<int, kLevels> level_offset;
  for (int l = 0; l < kLevels; ++l)
  {
    level_parts[l] = parts(l);
    level_offset[l] = offset(l);
  }
  Eigen::Vector3f uvw;
  // Posture: point counts per cell (divided by the total below).
  int inside = 0;
  for (const auto& p : cloud.points)
  {
    const Eigen::Vector3f xyz = p.getVector3fMap();
    if (!xyz.allFinite() || !grid_.normalised(where.toLocal(xyz), where.height, uvw))
      continue;
    ++inside;
    for (int l = 0; l < kLevels; ++l)
      d[level_offset[l] + kPostureFlowValuesPerCell * cellAt(uvw, level_parts[l])] += 1.0f;
  }
  if (inside == 0)
    return d;
  // Motion: each vector's components in grid axes, split by sign into the 6 direction bins.
  for (const auto& f : flow)
  {
    if (!f.position.allFinite() || !f.velocity.allFinite() ||
        !grid_.normalised(where.toLocal(f.position), where.height, uvw))
      continue;
    const Eigen::Vector3f v = where.axes.transpose() * f.velocity;
    for (int l = 0; l < kLevels; ++l)
    {
      const int at = level_offset[l] + kPostureFlowValuesPerCell * cellAt(uvw, level_parts[l]);
      for (int a = 0; a < 3; ++a)
        d[at + 1 + 2 * a + (v[a] < 0.0f ? 1 : 0)] += std::abs(v[a]);
    }
  }
  d /= static_cast<float>(inside);
  return d;
}

float PostureFlowDescriptor::postureChange(const Eigen::VectorXf& a, const Eigen::VectorXf& b) const
{
  if (a.size() != size() || b.size() != size())
    throw std::invalid_argument("PostureFlowDescriptor::postureChange: descriptors of length " +
                                std::to_string(a.size()) + " and " + std::to_string(b.size()) + ", expected " +
                                std::to_string(size()));
  const int finest = kLevels - 1;
  float change = 0.0f;
  for (int c = 0; c < cells(finest); ++c)
  {
    const int at = offset(finest) + kPostureFlowValuesPerCell * c;
    change += std::abs(a[at] - b[at]);
  }
  return change;
}

Eigen::VectorXf PostureFlowDescriptor::mirrored(const Eigen::VectorXf& in) const
{
  if (in.size() != size())
    throw std::invalid_argument("PostureFlowDescriptor::mirrored: descriptor of length " + std::to_string(in.size()) +
                                ", expected " + std::to_string(size()));
  Eigen::VectorXf out(in.size());
  for (int l = 0; l < kLevels; ++l)
  {
    const auto p = parts(l);
    for (int iz = 0; iz < p[2]; ++iz)
      for (int iy = 0; iy < p[1]; ++iy)
        for (int ix = 0; ix < p[0]; ++ix)
        {
          const int from = offset(l) + kPostureFlowValuesPerCell * (ix + p[0] * (iy + p[1] * iz));
          const int to = offset(l) + kPostureFlowValuesPerCell * ((p[0] - 1 - ix) + p[0] * (iy + p[1] * iz));
          out.segment<kPostureFlowValuesPerCell>(to) = in.segment<kPostureFlowValuesPerCell>(from);
          std::swap(out[to + 1], out[to + 2]);  // +x <-> -x
        }
  }
  return out;
}

}  // namespace action_flow
