#include <action_flow/grid_descriptor.h>

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace action_flow
{
std::string toString(FlowAggregation a)
{
  return paramText(a);
}

FlowAggregation aggregationFromString(const std::string& name)
{
  FlowAggregation a;
  parseParam(name, a);
  return a;
}

PersonFrame PersonFrame::fromGround(const Eigen::Vector3f& centroid, const Eigen::Vector4f& ground, float height,
                                    const Eigen::Vector3f& view)
{
  const Eigen::Vector3f n = ground.head<3>();
  const float norm = n.norm();
  if (!(norm > 1e-6f) || !std::isfinite(ground[3]))
    throw std::invalid_argument("PersonFrame: degenerate ground plane");
  if (!(height > 0.0f) || !centroid.allFinite())
    throw std::invalid_argument("PersonFrame: height must be positive and the centroid finite");
  const Eigen::Vector3f up = n / norm;
  const float above = up.dot(centroid) + ground[3] / norm;  // signed height of the centroid
  PersonFrame f;
  f.origin = centroid - above * up;
  Eigen::Vector3f depth = view - view.dot(up) * up;
  if (!(depth.norm() > 1e-6f))
    throw std::invalid_argument("PersonFrame: viewing direction is parallel to the ground normal");
  depth.normalize();
  // x to the right in the camera image, y up, z toward the camera: a right-handed frame.
  const Eigen::Vector3f across = depth.cross(up);
  f.axes.col(0) = across;
  f.axes.col(1) = up;
  f.axes.col(2) = -depth;
  f.height = height;
  return f;
}

GridDescriptor::GridDescriptor(const GridParams& params) : params_(params)
{
  if (params_.parts_x < 1 || params_.parts_y < 1 || params_.parts_z < 1)
    throw std::invalid_argument("GridDescriptor: parts per axis must be at least 1");
  if (!(params_.width > 0) || !(params_.height > 0) || !(params_.depth > 0) || !(params_.reference_height > 0))
    throw std::invalid_argument("GridDescriptor: grid sizes must be positive");
}

bool GridDescriptor::normalised(const Eigen::Vector3f& local, float person_height, Eigen::Vector3f& uvw) const
{
  const float scale = person_height / params_.reference_height;
  // Normalised to [0,1) along each axis: x and z centred on the person, y from the ground up.
  uvw.x() = local.x() / (params_.width * scale) + 0.5f;
  uvw.y() = local.y() / (params_.height * scale);
  uvw.z() = local.z() / (params_.depth * scale) + 0.5f;
  return uvw.x() >= 0.0f && uvw.x() < 1.0f && uvw.y() >= 0.0f && uvw.y() < 1.0f && uvw.z() >= 0.0f &&
         uvw.z() < 1.0f;
}

int GridDescriptor::cellOf(const Eigen::Vector3f& local, float person_height) const
{
  Eigen::Vector3f uvw;
  if (!normalised(local, person_height, uvw))
    return -1;
  const int ix = std::min(static_cast<int>(uvw.x() * params_.parts_x), params_.parts_x - 1);
  const int iy = std::min(static_cast<int>(uvw.y() * params_.parts_y), params_.parts_y - 1);
  const int iz = std::min(static_cast<int>(uvw.z() * params_.parts_z), params_.parts_z - 1);
  return ix + params_.parts_x * (iy + params_.parts_y * iz);
}

PersonFrame PersonFrame::turned(float angle) const
{
  PersonFrame f = *this;
  const float c = std::cos(angle), s = std::sin(angle);
  f.axes.col(0) = c * axes.col(0) - s * axes.col(2);
  f.axes.col(2) = s * axes.col(0) + c * axes.col(2);
  return f;
}

Eigen::VectorXf GridDescriptor::compute(const FlowVectors& flow, const PersonFrame& person) const
{
  Eigen::VectorXf d = Eigen::VectorXf::Zero(size());
  if (!(person.height > 0.0f))
    return d;
  std::vector<int> count(params_.cells(), 0);
  for (const auto& f : flow)
  {
    if (!f.position.allFinite() || !f.velocity.allFinite())
      continue;
    const int c = cellOf(person.toLocal(f.position), person.height);
    if (c < 0)
      continue;
    d.segment<3>(3 * c) += person.axes.transpose() * f.velocity;
    ++count[c];
  }
  if (params_.aggregation == FlowAggregation::Mean)
  {
    for (int c = 0; c < params_.cells(); ++c)
      if (count[c] > 0)
        d.segment<3>(3 * c) /= static_cast<float>(count[c]);
  }
  const float norm = d.norm();
  if (norm > 0.0f && std::isfinite(norm))
    d /= norm;
  else
    d.setZero();
  return d;
}

}  // namespace action_flow
