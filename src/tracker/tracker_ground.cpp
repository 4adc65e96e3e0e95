#include "tracker_ground.h"

#include <pcl/sample_consensus/ransac.h>
#include <pcl/sample_consensus/sac_model_perpendicular_plane.h>
#include <pcl/sample_consensus/sac_model_plane.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <unordered_set>
#include <utility>
#include <vector>
#include <stdexcept>

namespace action_flow
{
namespace
{
// A non-owning pointer: PCL's models want a shared pointer, the caller keeps the cloud alive.
Cloud::ConstPtr borrow(const Cloud& cloud)
{
  return Cloud::ConstPtr(&cloud, [](const Cloud*) {});
}

// Unit normal, oriented so that the camera is on the positive (upper) side.
bool normalise(Eigen::Vector4f& plane, const Eigen::Vector3f& camera)
{
  const float n = plane.head<3>().norm();
  if (!(n > 1e-6f) || !plane.allFinite())
    return false;
  plane /= n;
  if (heightAbove(plane, camera) < 0.0f)
    plane = -plane;
  return true;
}

// Mean number of points per occupied cell of a 2 * spacing grid laid on the plane.
float pointsPerCell(const Cloud& cloud, const pcl::Indices& indices, const Eigen::Vector4f& plane, float spacing)
{
  const Eigen::Vector3f n = plane.head<3>(), a = n.unitOrthogonal(), b = n.cross(a);
  std::unordered_set<std::uint64_t> cells;
  const float inv = 1.0f / (2.0f * spacing);
  for (const auto i : indices)
  {
    const Eigen::Vector3f p = cloud[i].getVector3fMap();
    const auto u = static_cast<std::int64_t>(std::floor(a.dot(p) * inv)) & 0xFFFFFFFF;
    const auto v = static_cast<std::int64_t>(std::floor(b.dot(p) * inv)) & 0xFFFFFFFF;
    cells.insert((static_cast<std::uint64_t>(u) << 32) | static_cast<std::uint64_t>(v));
  }
  return cells.empty() ? 0.0f : static_cast<float>(indices.size()) / static_cast<float>(cells.size());
}

// Points RANSAC scores its plane hypotheses on.
constexpr std::size_t kRansacSample = 800;
// With an assumed ground (no floor seen), the plane search is retried only every this many updates.
constexpr int kAssumedRetry = 10;

float angleBetween(const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  return std::acos(std::max(-1.0f, std::min(1.0f, a.normalized().dot(b.normalized()))));
}
}  // namespace

GroundEstimator::GroundEstimator(const GroundParams& params) : params_(params)
{
  const GroundParams& p = params_;
  if (!(p.inlier_distance > 0) || p.min_inliers < 3 || !(p.max_angle > 0 && p.max_angle < 1.5f) ||
      !(p.min_camera_height >= 0 && p.max_camera_height > p.min_camera_height) || p.max_candidates < 1 ||
      !(p.max_step_angle > 0) || !(p.max_step_offset > 0))
    throw std::invalid_argument("GroundEstimator: bad parameters");
}

void GroundEstimator::reset()
{
  valid_ = has_prior_;
  source_ = has_prior_ ? Source::Prior : Source::None;
  plane_ = has_prior_ ? prior_ : Eigen::Vector4f::Zero();
  since_search_ = 0;
}

bool GroundEstimator::setPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera)
{
  Eigen::Vector4f p = plane;
  if (!camera.allFinite() || !normalise(p, camera))
    return false;
  prior_ = p;
  has_prior_ = true;
  if (!valid_ || source_ == Source::Assumed || source_ == Source::Prior)
  {
    plane_ = p;
    valid_ = true;
    source_ = Source::Prior;
  }
  return true;
}

bool GroundEstimator::close(const Eigen::Vector4f& a, const Eigen::Vector4f& b, const Eigen::Vector3f& camera) const
{
  return angleBetween(a.head<3>(), b.head<3>()) <= params_.max_step_angle &&
         std::abs(heightAbove(a, camera) - heightAbove(b, camera)) <= params_.max_step_offset;
}

bool GroundEstimator::update(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up_hint)
{
  if (cloud.size() < static_cast<std::size_t>(params_.min_inliers) || !camera.allFinite() ||
      !(up_hint.norm() > 1e-6f) || !up_hint.allFinite())
    return false;
  const bool kept = valid_ && (source_ == Source::Measured || source_ == Source::Prior);
  if (kept && refine(cloud, camera))
  {
    // A prior that the visible floor agrees with becomes a measured ground.
    source_ = Source::Measured;
    since_search_ = 0;
    return true;
  }
  // Not confirmed: search at once (the camera may have moved), then only every kAssumedRetry-th
  // update while nothing confirms the plane (a full search per frame costs too much).
  const bool retry = source_ == Source::None || since_search_ % kAssumedRetry == 0;
  ++since_search_;
  if (retry)
  {
    Eigen::Vector4f found;
    std::size_t support = 0;
    // The plausible tilt is judged around the best knowledge of up: the current plane's normal.
    const Eigen::Vector3f up = kept ? Eigen::Vector3f(plane_.head<3>()) : up_hint.normalized();
    if (search(cloud, camera, up, found, support))
    {
      // An assumption yields to any floor seen; a measured or given ground only to a floor that
      // agrees with it or is strongly supported.
      const bool strong = static_cast<float>(support) >= params_.strong_support * params_.min_inliers;
      if (!kept || close(found, plane_, camera) || strong)
      {
        plane_ = found;
        valid_ = true;
        source_ = Source::Measured;
        since_search_ = 0;
        return true;
      }
    }
  }
  if (kept)
    return false;  // the floor is hidden: the measured or given ground stays
  if (!params_.assume_below_points)
    return false;
  // Keep the orientation of a floor seen before (the camera's tilt), else trust the hint.
  return assumeBelow(cloud, camera, valid_ ? Eigen::Vector3f(plane_.head<3>()) : up_hint.normalized());
}

bool GroundEstimator::assumeBelow(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up)
{
  const std::size_t n = cloud.size();
  const std::size_t need = static_cast<std::size_t>(params_.min_support);
  if (n < need)
    return false;
  std::vector<std::pair<float, std::size_t>> h(n);
  for (std::size_t i = 0; i < n; ++i)
    h[i] = {up.dot(cloud[i].getVector3fMap()), i};
  std::sort(h.begin(), h.end());
  // The lowest level with enough points in a band above it (single stray points are ignored).
  const float band = 2.0f * params_.inlier_distance;
  std::size_t lo = 0, hi = 0;
  for (; lo + need <= n; ++lo)
  {
    hi = std::max(hi, lo);
    while (hi < n && h[hi].first <= h[lo].first + band)
      ++hi;
    if (hi - lo >= need)
      break;
  }
  if (lo + need > n)
    return false;
  // They must be spread out: the bottom of one object is no floor.
  const Eigen::Vector3f a = up.unitOrthogonal(), b = up.cross(a);
  float amin = 1e9f, amax = -1e9f, bmin = 1e9f, bmax = -1e9f;
  for (std::size_t k = lo; k < hi; ++k)
  {
    const Eigen::Vector3f p = cloud[h[k].second].getVector3fMap();
    amin = std::min(amin, a.dot(p));
    amax = std::max(amax, a.dot(p));
    bmin = std::min(bmin, b.dot(p));
    bmax = std::max(bmax, b.dot(p));
  }
  if (std::hypot(amax - amin, bmax - bmin) < params_.min_support_spread)
    return false;
  Eigen::Vector4f plane;
  plane << up, -h[lo].first;
  const float height = heightAbove(plane, camera);
  if (height < params_.min_camera_height || height > params_.max_camera_height)
    return false;
  plane_ = plane;
  valid_ = true;
  source_ = Source::Assumed;
  return true;
}

bool GroundEstimator::refine(const Cloud& cloud, const Eigen::Vector3f& camera)
{
  auto model = pcl::make_shared<pcl::SampleConsensusModelPlane<PointT>>(borrow(cloud));
  pcl::Indices inliers;
  const Eigen::VectorXf old = plane_;
  model->selectWithinDistance(old, params_.inlier_distance, inliers);
  if (inliers.size() < static_cast<std::size_t>(params_.min_inliers))
    return false;
  Eigen::VectorXf refined;
  model->optimizeModelCoefficients(inliers, old, refined);
  Eigen::Vector4f plane = refined.head<4>();
  if (!normalise(plane, camera))
    return false;
  const float h = heightAbove(plane, camera);
  if (angleBetween(plane.head<3>(), plane_.head<3>()) > params_.max_step_angle ||
      std::abs(h - heightAbove(plane_, camera)) > params_.max_step_offset || h < params_.min_camera_height ||
      h > params_.max_camera_height)
    return false;
  plane_ = plane;
  return true;
}

bool GroundEstimator::dense(const Cloud& cloud, const pcl::Indices& inliers, const Eigen::Vector4f& plane) const
{
  return pointsPerCell(cloud, inliers, plane, params_.inlier_distance) >= params_.min_density;
}

bool GroundEstimator::search(const Cloud& cloud, const Eigen::Vector3f& camera, const Eigen::Vector3f& up,
                             Eigen::Vector4f& found_plane, std::size_t& support)
{
  ++searches_;
  const Cloud::ConstPtr ptr = borrow(cloud);
  pcl::Indices remaining(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
    remaining[i] = static_cast<pcl::index_t>(i);

  bool found = false;
  Eigen::Vector4f best = Eigen::Vector4f::Zero();
  float best_height = 0.0f;
  for (int k = 0; k < params_.max_candidates && remaining.size() >= static_cast<std::size_t>(params_.min_inliers); ++k)
  {
    // RANSAC scores its hypotheses on an even subsample (scoring is its whole cost); the winner's
    // inliers are then taken from all remaining points.
    pcl::Indices sample;
    const std::size_t stride = std::max<std::size_t>(1, remaining.size() / kRansacSample);
    for (std::size_t i = 0; i < remaining.size(); i += stride)
      sample.push_back(remaining[i]);
    auto model = pcl::make_shared<pcl::SampleConsensusModelPerpendicularPlane<PointT>>(ptr, sample);
    model->setAxis(up);
    model->setEpsAngle(params_.max_angle);
    pcl::RandomSampleConsensus<PointT> ransac(model, params_.inlier_distance);
    ransac.setMaxIterations(500);
    ransac.setNumberOfThreads(1);  // the nodelets share the cores; no OpenMP pool per frame
    if (!ransac.computeModel())
      break;
    Eigen::VectorXf coeffs, refined;
    ransac.getModelCoefficients(coeffs);
    auto all = pcl::make_shared<pcl::SampleConsensusModelPlane<PointT>>(ptr, remaining);
    pcl::Indices inliers;
    all->selectWithinDistance(coeffs, params_.inlier_distance, inliers);
    if (inliers.size() < static_cast<std::size_t>(params_.min_inliers))
      break;
    all->optimizeModelCoefficients(inliers, coeffs, refined);
    Eigen::Vector4f plane = refined.head<4>();
    // The candidate's points leave the pool whether or not it qualifies, so the next round finds another plane.
    std::vector<char> used(cloud.size(), 0);
    for (const auto i : inliers)
      used[i] = 1;
    pcl::Indices rest;
    rest.reserve(remaining.size() - inliers.size());
    for (const auto i : remaining)
      if (!used[i])
        rest.push_back(i);
    remaining.swap(rest);

    if (!normalise(plane, camera) || angleBetween(plane.head<3>(), up) > params_.max_angle)
      continue;
    const float h = heightAbove(plane, camera);
    if (h < params_.min_camera_height || h > params_.max_camera_height)
      continue;
    // A floor is a surface: its voxels cover the area they span (a slab cut through scattered
    // points is sparse). Counted on cells of twice the inlier distance (about four voxels each).
    if (!dense(cloud, inliers, plane))
      continue;
    // Nothing stands below a floor: a table top has chair legs and feet below it, and a plane
    // RANSAC strung through clutter has clutter on both sides.
    std::size_t below = 0;
    for (const auto& p : cloud.points)
      if (heightAbove(plane, p.getVector3fMap()) < -2.0f * params_.inlier_distance)
        ++below;
    if (below > std::max<std::size_t>(params_.min_inliers / 4, cloud.size() / 100))
      continue;
    // The lowest supported horizontal plane is the floor.
    if (!found || h > best_height)
    {
      found = true;
      best = plane;
      best_height = h;
      support = inliers.size();
    }
  }
  if (found)
    found_plane = best;
  return found;
}

}  // namespace action_flow
