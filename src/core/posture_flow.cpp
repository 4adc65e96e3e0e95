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
  // Grid coordinates centred on the person (x and z), as the geometry block keeps them.
  const Eigen::Vector3f centre(0.5f, 0.0f, 0.5f);
  // Posture: point counts per cell (divided by the total below).
  std::vector<Eigen::Vector3f> body;
  body.reserve(cloud.points.size());
  for (const auto& p : cloud.points)
  {
    const Eigen::Vector3f xyz = p.getVector3fMap();
    if (!xyz.allFinite() || !grid_.normalised(where.toLocal(xyz), where.height, uvw))
      continue;
    body.push_back(uvw - centre);
    for (int l = 0; l < kLevels; ++l)
      d[level_offset[l] + kPostureFlowValuesPerCell * cellAt(uvw, level_parts[l])] += 1.0f;
  }
  if (body.empty())
    return d;
  // Motion: each vector's components in grid axes, split by sign into the 6 direction bins.
  std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>> moving;  // centred position, velocity
  for (const auto& f : flow)
  {
    if (!f.position.allFinite() || !f.velocity.allFinite() ||
        !grid_.normalised(where.toLocal(f.position), where.height, uvw))
      continue;
    const Eigen::Vector3f v = where.axes.transpose() * f.velocity;
    moving.emplace_back(uvw - centre, v);
    for (int l = 0; l < kLevels; ++l)
    {
      const int at = level_offset[l] + kPostureFlowValuesPerCell * cellAt(uvw, level_parts[l]);
      for (int a = 0; a < 3; ++a)
        d[at + 1 + 2 * a + (v[a] < 0.0f ? 1 : 0)] += std::abs(v[a]);
    }
  }
  d /= static_cast<float>(body.size());
  computeGeometry(body, moving, d.tail(kGeometryValues));
  return d;
}

void PostureFlowDescriptor::computeGeometry(const std::vector<Eigen::Vector3f>& body,
                                            const std::vector<std::pair<Eigen::Vector3f, Eigen::Vector3f>>& moving,
                                            Eigen::Ref<Eigen::VectorXf> out) const
{
  const float n = static_cast<float>(body.size());
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  for (const auto& p : body)
    centroid += p;
  centroid /= n;
  out.segment<3>(0) = centroid;
  // The extremes along +x, -x, +y, +z, -z: the mean of the kExtremePoints points furthest that way.
  const std::array<Eigen::Vector3f, 5> directions = { Eigen::Vector3f::UnitX(), -Eigen::Vector3f::UnitX(),
                                                      Eigen::Vector3f::UnitY(), Eigen::Vector3f::UnitZ(),
                                                      -Eigen::Vector3f::UnitZ() };
  const std::size_t k = std::min<std::size_t>(kExtremePoints, body.size());
  std::vector<Eigen::Vector3f> sorted = body;
  for (std::size_t e = 0; e < directions.size(); ++e)
  {
    const Eigen::Vector3f dir = directions[e];
    std::nth_element(sorted.begin(), sorted.begin() + (k - 1), sorted.end(),
                     [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return a.dot(dir) > b.dot(dir); });
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    for (std::size_t i = 0; i < k; ++i)
      mean += sorted[i];
    out.segment<3>(3 + 3 * e) = mean / static_cast<float>(k);
  }
  // The flow's where (speed-weighted offset) and how it turns (r x v), per body point.
  Eigen::Vector3f offset = Eigen::Vector3f::Zero(), momentum = Eigen::Vector3f::Zero();
  for (const auto& [p, v] : moving)
  {
    const Eigen::Vector3f r = p - centroid;
    offset += v.norm() * r;
    momentum += r.cross(v);
  }
  out.segment<3>(18) = offset / n;
  out.segment<3>(21) = momentum / n;
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
  // Geometry: x changes sign; the +x and -x extremes swap; r x v keeps x and flips y and z.
  const int g = geometryOffset();
  for (int i = 0; i < 7; ++i)
    out.segment<3>(g + 3 * i) = in.segment<3>(g + 3 * i);
  out.segment<3>(g + 3) = in.segment<3>(g + 6);
  out.segment<3>(g + 6) = in.segment<3>(g + 3);
  for (int i = 0; i < 7; ++i)
    out[g + 3 * i] = -out[g + 3 * i];
  out.segment<3>(g + 21) = Eigen::Vector3f(in[g + 21], -in[g + 22], -in[g + 23]);
  return out;
}

}  // namespace action_flow
