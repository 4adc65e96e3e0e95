#include "tracker_detector.h"
#include "tracker_clustering.h"
#include "tracker_walls.h"

#include <action_flow/voxel_filter.h>

#include <pcl/people/head_based_subcluster.h>
#include <pcl/people/person_classifier.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <climits>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace action_flow
{
namespace
{
// The voxel a point falls in, as pcl::VoxelGrid computes it (floor of the coordinate over the
// leaf size: the grid is anchored at the origin), packed into one key.
std::uint64_t voxelKey(const PointT& p, float inverse_leaf)
{
  const auto part = [&](float v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v * inverse_leaf)) + (1 << 20)) & 0x1FFFFF;
  };
  return (part(p.x) << 42) | (part(p.y) << 21) | part(p.z);
}

// A person is a surface: its voxels have on average at least this many points (themselves
// included) within the clustering tolerance. A surface voxelised at half the tolerance gives about
// 12, scattered points 1-3.
constexpr int kSurfaceNeighbours = 5;
// Points higher than this above max_height are dropped before clustering (m).
constexpr float kAboveHeads = 0.5f;

// The head region of a person: its top this many metres.
constexpr float kHeadDepth = 0.25f;
// A top within this many rows of the image's top edge is the edge's, not a head's...
constexpr int kBorderRows = 2;
// ... when the cluster is cut there about as wide as it is anywhere (a wall, door or shelf cut by
// the image's edge). A raised hand or a head leaving the image is far narrower than the body below
// it: at least this much narrower, in pixels of the widest row.
constexpr float kCutSurfaceWidthRatio = 0.5f;
// ... or when one unbroken piece of it along an edge row is longer than a head or a hand, in
// metres: a side wall seen along its length is few pixels wide at the edge but a metre long there.
constexpr float kCutSurfaceLength = 0.35f;
// Neighbouring pixels of a row farther apart than this (m) break the piece (a depth step such as a
// hand's in front of the face; a wall's depth noise at 4 m is well below it).
constexpr float kCutSurfaceStep = 0.25f;

// Whether a candidate reaching the image's top edge is cut there like a surface: its widest row
// within kBorderRows of the edge has at least kCutSurfaceWidthRatio of its widest row's pixels, or
// one of those rows holds an unbroken piece kCutSurfaceLength long or longer (end to end in 3D).
bool cutByTopBorder(const Cloud& cloud, const PersonDetection& d)
{
  std::vector<int> per_row(cloud.height, 0);
  std::vector<std::vector<std::uint32_t>> edge_rows(std::min<std::uint32_t>(kBorderRows + 1, cloud.height));
  for (const auto i : d.indices)
  {
    const std::uint32_t row = static_cast<std::uint32_t>(i) / cloud.width;
    ++per_row[row];
    if (row < edge_rows.size())
      edge_rows[row].push_back(static_cast<std::uint32_t>(i));
  }
  const int widest = *std::max_element(per_row.begin(), per_row.end());
  const int at_border = *std::max_element(per_row.begin(), per_row.begin() + static_cast<long>(edge_rows.size()));
  if (at_border == 0)
    return false;
  if (static_cast<float>(at_border) >= kCutSurfaceWidthRatio * static_cast<float>(widest))
    return true;
  for (auto& row : edge_rows)
  {
    std::sort(row.begin(), row.end());
    for (std::size_t start = 0, k = 1; k <= row.size(); ++k)
    {
      const auto p = [&](std::size_t j) { return cloud.points[row[j]].getVector3fMap(); };
      if (k < row.size() && row[k] - row[k - 1] <= 2 && (p(k) - p(k - 1)).norm() < kCutSurfaceStep)
        continue;
      if ((p(k - 1) - p(start)).norm() >= kCutSurfaceLength)
        return true;
      start = k;
    }
  }
  return false;
}
// Weak candidates (see PersonDetection::weak) closer than this on the floor are parts of one body (m).
constexpr float kFragmentDistance = 0.45f;
// Points closer than this to a wall are the wall's (its depth noise at 4 m included; m).
constexpr float kWallMargin = 0.1f;
// A person's points lie within this horizontal distance of their head (arms spread, a kick; m).
constexpr float kReach = 0.7f;
// Beside a head, a wall this far behind it (in range) leaves the head free (m).
constexpr float kWallStep = 0.15f;
// The head-and-shoulders profile: the top slice, and the band below the top where the shoulders are (m).
constexpr float kHeadSlice = 0.15f, kShouldersFrom = 0.3f, kShouldersTo = 0.6f;

bool onAWall(const std::vector<Eigen::Vector4f>& walls, const Eigen::Vector3f& p)
{
  for (const auto& w : walls)
    if (std::abs(w.head<3>().dot(p) + w[3]) < kWallMargin)
      return true;
  return false;
}

// Width across the line of sight of the detection's top slice over that of the band below it where
// the shoulders are; NaN when the band holds no point (a short cluster).
float headRatio(const Cloud& cloud, const PersonDetection& d, const Eigen::Vector4f& ground, const Eigen::Vector3f& origin)
{
  const Eigen::Vector3f up = ground.head<3>();
  const Eigen::Vector3f view = onGround(d.centroid - origin, up);
  if (!(view.norm() > 1e-3f))
    return std::numeric_limits<float>::quiet_NaN();
  const Eigen::Vector3f across = up.cross(view).normalized();
  float head_lo = 1e9f, head_hi = -1e9f, body_lo = 1e9f, body_hi = -1e9f;
  for (const auto i : d.indices)
  {
    const Eigen::Vector3f p = cloud[i].getVector3fMap();
    const float below = d.height - heightAbove(ground, p), s = across.dot(p);
    if (below <= kHeadSlice)
    {
      head_lo = std::min(head_lo, s);
      head_hi = std::max(head_hi, s);
    }
    else if (below >= kShouldersFrom && below <= kShouldersTo)
    {
      body_lo = std::min(body_lo, s);
      body_hi = std::max(body_hi, s);
    }
  }
  if (!(body_hi > body_lo) || !(head_hi >= head_lo))
    return std::numeric_limits<float>::quiet_NaN();
  return (head_hi - head_lo) / (body_hi - body_lo);
}

// Share of the image rows of the detection's head whose pixels just left and just right of the
// head's extent in that row both differ in range from the head by at least the step (or have no
// depth, or lie outside the image). A head stands free; a column cut out of a wall does not.
float freeFraction(const Cloud& cloud, const PersonDetection& d, const Eigen::Vector4f& ground,
                   const Eigen::Vector3f& origin, float step, const std::vector<Eigen::Vector4f>& walls)
{
  const int w = static_cast<int>(cloud.width);
  struct Row
  {
    int lo = 1 << 30, hi = -1;
    float range = 0.0f;
    int n = 0;
  };
  std::unordered_map<int, Row> rows;
  for (const auto i : d.indices)
  {
    const Eigen::Vector3f p = cloud[i].getVector3fMap();
    if (heightAbove(ground, p) < d.height - kHeadDepth)
      continue;
    Row& r = rows[static_cast<int>(i) / w];
    const int u = static_cast<int>(i) % w;
    r.lo = std::min(r.lo, u);
    r.hi = std::max(r.hi, u);
    r.range += (p - origin).norm();
    ++r.n;
  }
  if (rows.empty())
    return 0.0f;
  const auto free_at = [&](int u, int v, float range) {
    if (u < 0 || u >= w)
      return true;  // beyond the image: cannot tell, not held against the person
    const PointT& q = cloud[static_cast<std::size_t>(v) * w + u];
    if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
      return true;
    // A wall behind the head stands back less far than furniture must: the head itself is off
    // every wall (its points were kept), but a sliver of a side wall beside the back wall is not.
    const float behind = std::abs((q.getVector3fMap() - origin).norm() - range);
    return behind >= (onAWall(walls, q.getVector3fMap()) ? kWallStep : step);
  };
  int free_rows = 0;
  for (const auto& [v, r] : rows)
  {
    const float range = r.range / static_cast<float>(r.n);
    // A few pixels out: the silhouette's own edge pixels (mixed depth) are skipped.
    const int gap = 3;
    const bool left = free_at(r.lo - gap, v, range) && free_at(r.lo - 2 * gap, v, range);
    const bool right = free_at(r.hi + gap, v, range) && free_at(r.hi + 2 * gap, v, range);
    free_rows += left && right;
  }
  return static_cast<float>(free_rows) / static_cast<float>(rows.size());
}

void require(bool ok, const char* what)
{
  if (!ok)
    throw std::invalid_argument(std::string("PeopleTracker: bad parameter: ") + what);
}
}  // namespace

void validateTrackerParams(const TrackerParams& p)
{
  require(std::isfinite(p.detection_voxel_size) && p.detection_voxel_size >= 0.01f && p.detection_voxel_size <= 0.5f,
          "detection_voxel_size must be in [0.01, 0.5] m");
  require(std::isfinite(p.person_voxel_size) && p.person_voxel_size >= 0.005f && p.person_voxel_size <= 0.5f,
          "person_voxel_size must be in [0.005, 0.5] m");
  require(std::isfinite(p.max_range) && p.max_range > 0.5f, "max_range must exceed 0.5 m");
  // pcl::VoxelGrid refuses grids whose voxel count overflows an int.
  const double cells = 2.0 * p.max_range / p.detection_voxel_size + 1.0;
  require(cells * cells * cells < static_cast<double>(INT_MAX), "max_range is too large for detection_voxel_size");
  require(std::isfinite(p.min_height) && std::isfinite(p.max_height) && p.min_height > 0 && p.max_height > p.min_height,
          "need 0 < min_height < max_height");
  require(std::isfinite(p.min_width) && std::isfinite(p.max_width) && p.min_width >= 0 && p.max_width > p.min_width,
          "need 0 <= min_width < max_width");
  require(std::isfinite(p.ground_tolerance) && p.ground_tolerance > 0 && p.ground_tolerance < p.min_height,
          "ground_tolerance must be positive and below min_height");
  require(std::isfinite(p.cluster_tolerance) && p.cluster_tolerance > 0, "cluster_tolerance must be positive");
  require(p.min_points >= 1, "min_points must be at least 1");
  require(p.sampling_factor >= 1 && p.sampling_factor <= 8, "sampling_factor must be in [1, 8]");
  if (p.ground)
    require(p.ground->allFinite() && p.ground->head<3>().norm() > 1e-6f, "ground must be a finite plane with a normal");
  require(std::isfinite(p.gate) && p.gate > 0, "gate must be positive");
  require(std::isfinite(p.lost_after) && p.lost_after > 0, "lost_after must be positive");
  require(std::isfinite(p.hidden_lost_after) && p.hidden_lost_after >= p.lost_after,
          "hidden_lost_after must be at least lost_after");
  require(std::isfinite(p.reid_after) && p.reid_after >= 0, "reid_after must be finite and not negative");
  require(std::isfinite(p.low_lost_after) && p.low_lost_after >= 0, "low_lost_after must be finite and not negative");
  require(std::isfinite(p.weak_max_colour_distance) && p.weak_max_colour_distance >= 0 && p.weak_max_colour_distance <= 1,
          "weak_max_colour_distance must be in [0, 1]");
  require(std::isfinite(p.reid_max_colour_distance) && p.reid_max_colour_distance >= 0 && p.reid_max_colour_distance <= 1,
          "reid_max_colour_distance must be in [0, 1]");
  require(std::isfinite(p.reid_max_height_difference) && p.reid_max_height_difference >= 0,
          "reid_max_height_difference must be finite and not negative");
  require(std::isfinite(p.split_max_distance) && p.split_max_distance >= 0, "split_max_distance must be finite and not negative");
  require(p.confirm_after >= 1, "confirm_after must be at least 1");
  require(std::isfinite(p.facing_smoothing) && p.facing_smoothing >= 0, "facing_smoothing must be at least 0");
  require(p.up_hint.allFinite() && p.up_hint.norm() > 1e-6f, "up_hint must be a finite non-zero vector");
  require(std::isfinite(p.ground_max_angle) && p.ground_max_angle > 0 && p.ground_max_angle < 1.5f,
          "ground_max_angle must be in (0, 1.5) rad");
  require(std::isfinite(p.ground_min_area) && p.ground_min_area > 0, "ground_min_area must be positive");
  require(std::isfinite(p.min_head_distance) && p.min_head_distance > 0, "min_head_distance must be positive");
  require(std::isfinite(p.hog_min_confidence), "hog_min_confidence must be finite");
  require(std::isfinite(p.camera_height) && p.camera_height >= 0 && p.camera_height <= 5.0f,
          "camera_height must be in [0, 5] m (0 = unknown)");
  require(std::isfinite(p.camera_pitch) && std::abs(p.camera_pitch) < 1.5f, "camera_pitch must be in (-1.5, 1.5) rad");
  require(std::isfinite(p.min_free_fraction) && p.min_free_fraction >= 0 && p.min_free_fraction <= 1,
          "min_free_fraction must be in [0, 1]");
  require(std::isfinite(p.free_depth_step) && p.free_depth_step > 0, "free_depth_step must be positive");
  require(std::isfinite(p.tracked_min_height) && p.tracked_min_height > p.ground_tolerance &&
              p.tracked_min_height <= p.min_height,
          "tracked_min_height must be in (ground_tolerance, min_height]");
  require(std::isfinite(p.tracked_max_width) && p.tracked_max_width >= p.max_width,
          "tracked_max_width must be at least max_width");
  require(std::isfinite(p.max_head_ratio) && p.max_head_ratio >= 0 && p.max_head_ratio <= 10,
          "max_head_ratio must be in [0, 10] (0 = off)");
}

std::string defaultHogClassifierFile()
{
  std::vector<std::string> candidates;
  if (const char* env = std::getenv("ACTION_FLOW_HOG_CLASSIFIER"))
    candidates.emplace_back(env);
#ifdef ACTION_FLOW_HOG_INSTALLED
  candidates.emplace_back(ACTION_FLOW_HOG_INSTALLED);
#endif
#ifdef ACTION_FLOW_HOG_SOURCE
  candidates.emplace_back(ACTION_FLOW_HOG_SOURCE);
#endif
  for (const auto& c : candidates)
    if (!c.empty() && std::ifstream(c).good())
      return c;
  return std::string();
}

Eigen::Vector4f groundFromCamera(float height, float pitch)
{
  // Optical frame: x right, y down, z ahead; pitched down by `pitch`, up is (0, -cos, -sin).
  return Eigen::Vector4f(0.0f, -std::cos(pitch), -std::sin(pitch), height);
}

bool fitProjection(const Cloud& cloud, Eigen::Matrix<float, 3, 4>& projection)
{
  if (cloud.height < 2 || cloud.width < 2 || cloud.size() != static_cast<std::size_t>(cloud.width) * cloud.height)
    return false;
  // Normalised coordinates (Hartley) keep the linear system well conditioned.
  std::vector<Eigen::Vector3d> X;
  std::vector<Eigen::Vector2d> uv;
  const int step = std::max(1, static_cast<int>(std::sqrt(cloud.size() / 2000.0)));
  for (std::uint32_t v = 0; v < cloud.height; v += step)
    for (std::uint32_t u = 0; u < cloud.width; u += step)
    {
      const PointT& p = cloud.at(u, v);
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      {
        X.emplace_back(p.x, p.y, p.z);
        uv.emplace_back(u, v);
      }
    }
  if (X.size() < 50)
    return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : X)
    mean += x;
  mean /= static_cast<double>(X.size());
  double spread = 0.0;
  for (const auto& x : X)
    spread += (x - mean).norm();
  spread /= static_cast<double>(X.size());
  if (!(spread > 1e-6))
    return false;
  const double s = std::sqrt(3.0) / spread;
  const double half_w = cloud.width / 2.0, scale_uv = 2.0 / cloud.width;
  Eigen::Matrix<double, 12, 12> AtA = Eigen::Matrix<double, 12, 12>::Zero();
  for (std::size_t k = 0; k < X.size(); ++k)
  {
    Eigen::Vector4d Xh;
    Xh << (X[k] - mean) * s, 1.0;
    const double un = (uv[k].x() - half_w) * scale_uv, vn = (uv[k].y() - cloud.height / 2.0) * scale_uv;
    Eigen::Matrix<double, 12, 1> r1 = Eigen::Matrix<double, 12, 1>::Zero(), r2 = r1;
    r1.segment<4>(0) = Xh;
    r1.segment<4>(8) = -un * Xh;
    r2.segment<4>(4) = Xh;
    r2.segment<4>(8) = -vn * Xh;
    AtA += r1 * r1.transpose() + r2 * r2.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> eig(AtA);
  const Eigen::Matrix<double, 12, 1> h = eig.eigenvectors().col(0);
  Eigen::Matrix<double, 3, 4> Pn;
  Pn << h.segment<4>(0).transpose(), h.segment<4>(4).transpose(), h.segment<4>(8).transpose();
  // Undo the normalisations: pixel = Tu^-1 * Pn * Tx * X.
  Eigen::Matrix4d Tx = Eigen::Matrix4d::Identity();
  Tx.topLeftCorner<3, 3>() *= s;
  Tx.topRightCorner<3, 1>() = -s * mean;
  Eigen::Matrix3d Tu_inv = Eigen::Matrix3d::Identity();
  Tu_inv(0, 0) = Tu_inv(1, 1) = 1.0 / scale_uv;
  Tu_inv(0, 2) = half_w;
  Tu_inv(1, 2) = cloud.height / 2.0;
  Eigen::Matrix<double, 3, 4> P = Tu_inv * Pn * Tx;
  // The eigenvector's sign is arbitrary: choose the one that puts the points in front of the camera.
  double w = 0.0;
  for (const auto& x : X)
    w += (P * x.homogeneous()).z();
  if (w < 0.0)
    P = -P;
  std::vector<double> err;
  err.reserve(X.size());
  for (std::size_t k = 0; k < X.size(); ++k)
  {
    const Eigen::Vector3d q = P * X[k].homogeneous();
    if (!(std::abs(q.z()) > 1e-12))
      return false;
    err.push_back((q.hnormalized() - uv[k]).norm());
  }
  std::nth_element(err.begin(), err.begin() + err.size() / 2, err.end());
  if (!(err[err.size() / 2] < 2.0))
    return false;
  projection = P.cast<float>();
  return true;
}

struct PeopleDetector::Impl
{
  explicit Impl(const GroundParams& g) : ground(g) {}
  GroundEstimator ground;
  RadiusGrid grid;
  std::unique_ptr<pcl::people::PersonClassifier<pcl::RGB>> classifier;
  pcl::Indices valid;
  pcl::Indices sampled;
  VoxelFilter voxel_filter;
  Cloud voxels;
};

PeopleDetector::PeopleDetector(const TrackerParams& params) : params_(params)
{
  validateTrackerParams(params_);
  GroundParams g;
  g.inlier_distance = std::max(0.06f, params_.detection_voxel_size);
  g.min_inliers = std::max(10, static_cast<int>(params_.ground_min_area /
                                                (params_.detection_voxel_size * params_.detection_voxel_size)));
  g.max_angle = params_.ground_max_angle;
  g.assume_below_points = params_.assume_ground_below_points;
  impl_ = std::make_unique<Impl>(g);
  if (params_.camera_height > 0.0f)
    impl_->ground.setPrior(groundFromCamera(params_.camera_height, params_.camera_pitch));
  const std::string hog_file =
      params_.hog_classifier_file == "default" ? defaultHogClassifierFile() : params_.hog_classifier_file;
  if (!hog_file.empty())
  {
    if (!std::ifstream(hog_file).good())
      throw std::invalid_argument("PeopleTracker: cannot read HOG classifier file '" + hog_file + "'");
    impl_->classifier = std::make_unique<pcl::people::PersonClassifier<pcl::RGB>>();
    if (!impl_->classifier->loadSVMFromFile(hog_file))
      throw std::invalid_argument("PeopleTracker: '" + hog_file + "' is not a HOG+SVM classifier file");
  }
}

PeopleDetector::~PeopleDetector() = default;

void PeopleDetector::reset()
{
  impl_->ground.reset();
}

bool PeopleDetector::setGroundPrior(const Eigen::Vector4f& plane, const Eigen::Vector3f& camera)
{
  return impl_->ground.setPrior(plane, camera);
}

namespace
{
// ---- the steps of PeopleDetector::detect, in order ----

// The finite points of an organized cloud's top rows (every other pixel), within range: where a wall
// that goes on above the view is cut (findWalls). None for an unorganized cloud.
std::vector<Eigen::Vector3f> imageTopEdge(const Cloud& cloud, const Eigen::Vector3f& origin, float max_range)
{
  std::vector<Eigen::Vector3f> top;
  if (cloud.height <= 1)
    return top;
  for (std::uint32_t v = 0; v <= std::min<std::uint32_t>(kBorderRows, cloud.height - 1); ++v)
    for (std::uint32_t u = 0; u < cloud.width; u += 2)
    {
      const Eigen::Vector3f p = cloud.points[static_cast<std::size_t>(v) * cloud.width + u].getVector3fMap();
      if (p.allFinite() && (p - origin).norm() <= max_range)
        top.push_back(p);
    }
  return top;
}

// The level frame: y down along the ground normal, z the mean horizontal viewing direction, origin
// at the camera (rows: its axes in input coordinates). pcl::people reads heights and head maxima
// along a camera's y and x axes, so its classes get the cloud in this frame whatever the camera's
// tilt or the input frame.
Eigen::Matrix3f levelFrame(const Cloud& voxels, const Eigen::Vector3f& origin, const Eigen::Vector3f& up)
{
  Eigen::Vector3f mean_view = Eigen::Vector3f::Zero();
  for (const auto& p : voxels.points)
    mean_view += p.getVector3fMap() - origin;
  Eigen::Vector3f ahead = onGround(mean_view, up);
  if (!(ahead.norm() > 1e-3f))
    ahead = up.unitOrthogonal();
  ahead.normalize();
  Eigen::Matrix3f R;  // rows: level x, y, z in input coordinates
  const Eigen::Vector3f down = -up;
  R.row(0) = down.cross(ahead).transpose();
  R.row(1) = down.transpose();
  R.row(2) = ahead.transpose();
  return R;
}

// The detection voxels above the ground (and below the heads' reach: not ceilings, upper walls), in
// the input frame (@p above) and the level frame (@p level), without those on a wall (@p walls).
// False when too few are left for a person.
bool pointsAboveGround(const Cloud& voxels, const Eigen::Vector4f& ground, const Eigen::Vector3f& origin,
                       const Eigen::Matrix3f& R, const TrackerParams& params, const std::vector<Eigen::Vector3f>& image_top,
                       Cloud& above, Cloud& level, std::vector<Eigen::Vector4f>& walls)
{
  above.reserve(voxels.size());
  level.reserve(voxels.size());
  for (const auto& p : voxels.points)
  {
    // Far above any head (ceilings, upper walls) nothing can be a person; cut there, the height
    // limits still reject whatever reaches the cut.
    const float h = heightAbove(ground, p.getVector3fMap());
    if (h <= params.ground_tolerance || h > params.max_height + kAboveHeads)
      continue;
    above.push_back(p);
    PointT q = p;
    q.getVector3fMap() = R * (p.getVector3fMap() - origin);
    level.push_back(q);
  }
  if (above.size() < static_cast<std::size_t>(params.min_points))
    return false;

  // Walls: their points go before clustering (a person close in front of one would join it).
  if (params.remove_walls)
  {
    WallParams wp;
    wp.voxel = params.detection_voxel_size;
    wp.inlier_distance = std::max(0.06f, params.detection_voxel_size);
    walls = findWalls(above, ground, origin, wp, image_top);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < above.size(); ++i)
      if (!onAWall(walls, above[i].getVector3fMap()))
      {
        above[kept] = above[i];
        level[kept++] = level[i];
      }
    above.resize(kept);
    level.resize(kept);
    if (above.size() < static_cast<std::size_t>(params.min_points))
      return false;
  }
  return true;
}


// pcl::people's head-based sub-clustering: merges parts close on the floor (a head cut off from its
// body), splits clusters with several head maxima (people side by side), and keeps clusters whose
// top lies between the height limits (down to the tracked limit: a bending person may continue a
// track, judged later). @p level: the points in the level frame (y down along the ground normal).
// (PCL's classes take non-const arguments, hence the plain references here and below.)
std::vector<pcl::people::PersonCluster<PointT>> headSubclusters(Cloud::Ptr level, std::vector<pcl::PointIndices>& clusters,
                                                                float camera_height, const TrackerParams& params)
{
  std::vector<pcl::people::PersonCluster<PointT>> people;
  {
    pcl::people::HeadBasedSubclustering<PointT> sub;
    Eigen::VectorXf level_ground(4);
    level_ground << 0.0f, -1.0f, 0.0f, camera_height;
    sub.setInputCloud(level);
    sub.setGround(level_ground);
    sub.setInitialClusters(clusters);
    // Down to the tracked limit: a bending person may continue a track (judged below).
    sub.setHeightLimits(params.tracked_min_height, params.max_height);
    sub.setDimensionLimits(params.min_points, std::numeric_limits<int>::max());
    sub.setMinimumDistanceBetweenHeads(params.min_head_distance);
    sub.setSensorPortraitOrientation(false);
    sub.subcluster(people);
  }

  return people;
}

// pcl::people hands a point between two heads to the first head within min_head_distance (the
// taller one): each point goes to the nearest head on the floor instead, so that each person's cloud
// holds none of a neighbour's shoulder; points beyond a body's reach from its head (furniture it
// touches) go to none. Returns each sub-cluster's voxels (indices into @p level).
std::vector<pcl::Indices> assignToNearestHead(std::vector<pcl::people::PersonCluster<PointT>>& people,
                                              const Cloud& level, float camera_height, const TrackerParams& params)
{
  std::vector<pcl::Indices> members(people.size());
  {
    std::vector<Eigen::Vector2f> heads(people.size(), Eigen::Vector2f::Zero());
    std::vector<char> tall(people.size(), 0);  // top above min_height: only those exchange points
    for (std::size_t k = 0; k < people.size(); ++k)
    {
      const auto& idx = people[k].getIndices().indices;
      float top_y = 1e9f;
      for (const auto i : idx)
        top_y = std::min(top_y, level[i].y);
      tall[k] = camera_height - top_y >= params.min_height;
      int n = 0;
      for (const auto i : idx)
        if (level[i].y < top_y + 0.2f)
        {
          heads[k] += Eigen::Vector2f(level[i].x, level[i].z);
          ++n;
        }
      heads[k] /= static_cast<float>(std::max(1, n));
    }
    for (std::size_t k = 0; k < people.size(); ++k)
      for (const auto i : people[k].getIndices().indices)
      {
        const Eigen::Vector2f q(level[i].x, level[i].z);
        std::size_t best = k;
        for (std::size_t m = 0; m < people.size(); ++m)
          if (tall[m] == tall[k] && (heads[m] - q).squaredNorm() < (heads[best] - q).squaredNorm())
            best = m;
        // Only between neighbours: a far-away head never takes points.
        if (best != k && (heads[best] - q).norm() > params.min_head_distance)
          best = k;
        // Beyond a body's reach from its head: furniture it touches (a table in front, a shelf beside).
        if ((heads[best] - q).norm() <= kReach)
          members[best].push_back(i);
      }
  }

  return members;
}

// The candidates' size limits, and a surface: a person's voxels have neighbours all around
// (scattered points have one or two within the clustering tolerance). Clusters within the tracked_*
// limits only are weak: they may continue a track, never start one. Also gives each kept voxel's
// candidate (by voxel key) and the box around all of their points.
struct Candidates
{
  std::vector<PersonDetection> people;
  std::unordered_map<std::uint64_t, int> label_of_voxel;
  Eigen::Array3f lo = Eigen::Array3f::Constant(1e30f), hi = Eigen::Array3f::Constant(-1e30f);
};
Candidates sizedCandidates(const std::vector<pcl::Indices>& members, const Cloud& level, const Cloud& above,
                           const Eigen::Vector4f& ground, const RadiusGrid& grid, const TrackerParams& params)
{
  Candidates out;
  std::unordered_map<std::uint64_t, int>& label_of_voxel = out.label_of_voxel;
  Eigen::Array3f& people_lo = out.lo;
  Eigen::Array3f& people_hi = out.hi;
  std::vector<PersonDetection>& candidates = out.people;
  const float inverse_leaf = 1.0f / params.detection_voxel_size;
  for (const auto& idx : members)
  {
    if (static_cast<int>(idx.size()) < params.min_points)
      continue;
    // Counting stops at twice the threshold: enough to tell, and the searches stay short.
    std::size_t around = 0;
    for (const auto i : idx)
      around += static_cast<std::size_t>(grid.countWithin(level[i].getVector3fMap(), 2 * kSurfaceNeighbours));
    if (around < static_cast<std::size_t>(kSurfaceNeighbours) * idx.size())
      continue;
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e9f), hi = -lo, sum = Eigen::Vector3f::Zero();
    float top = -1e9f;
    for (const auto i : idx)
    {
      const Eigen::Vector3f q = level[i].getVector3fMap();
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
      sum += above[i].getVector3fMap();
      top = std::max(top, heightAbove(ground, above[i].getVector3fMap()));
    }
    const float width = std::max(hi.x() - lo.x(), hi.z() - lo.z());
    if (top < params.tracked_min_height || top > params.max_height || width < params.min_width ||
        width > params.tracked_max_width)
      continue;
    PersonDetection d;
    d.centroid = sum / static_cast<float>(idx.size());
    d.height = top;
    d.width = width;
    d.voxels = static_cast<int>(idx.size());
    d.weak = top < params.min_height || width > params.max_width;
    const int label = static_cast<int>(candidates.size());
    for (const auto i : idx)
    {
      label_of_voxel.emplace(voxelKey(above[i], inverse_leaf), label);
      people_lo = people_lo.min(above[i].getArray3fMap());
      people_hi = people_hi.max(above[i].getArray3fMap());
    }
    candidates.push_back(std::move(d));
  }

  return out;
}

// Each candidate's points at full resolution: those of @p valid falling in its detection voxels,
// above the ground.
void collectFullResolution(const Cloud& cloud, const pcl::Indices& valid, const Eigen::Vector4f& ground,
                           const TrackerParams& params, Candidates& found)
{
  std::vector<PersonDetection>& candidates = found.people;
  const auto& label_of_voxel = found.label_of_voxel;
  const Eigen::Array3f& people_lo = found.lo;
  const Eigen::Array3f& people_hi = found.hi;
  const float inverse_leaf = 1.0f / params.detection_voxel_size;
  if (!candidates.empty())
  {
    // Most of the room lies outside the people's voxels: a box test spares those the hash lookup.
    const float leaf = params.detection_voxel_size;
    const Eigen::Array3f lo = (people_lo * inverse_leaf).floor() * leaf - 1e-3f;
    const Eigen::Array3f hi = ((people_hi * inverse_leaf).floor() + 1.0f) * leaf + 1e-3f;
    for (const auto i : valid)
    {
      const PointT& p = cloud[i];
      if (!(p.getArray3fMap() >= lo).all() || !(p.getArray3fMap() <= hi).all())
        continue;
      const auto it = label_of_voxel.find(voxelKey(p, inverse_leaf));
      if (it != label_of_voxel.end() && heightAbove(ground, p.getVector3fMap()) > params.ground_tolerance)
        candidates[it->second].indices.push_back(i);
    }
  }

}

// Person-likeness in the image (organized clouds): a top that is a head, not the image's edge; a
// head that stands free of what is behind it.
void keepFreeStanding(const Cloud& cloud, const Eigen::Vector4f& ground, const Eigen::Vector3f& origin,
                      const std::vector<Eigen::Vector4f>& walls, const TrackerParams& params,
                      std::vector<PersonDetection>& candidates)
{
  if (cloud.height > 1)
  {
    std::vector<PersonDetection> kept;
    for (auto& d : candidates)
    {
      if (d.indices.empty())
        continue;
      std::uint32_t top_row = cloud.height;
      for (const auto i : d.indices)
        top_row = std::min(top_row, static_cast<std::uint32_t>(i / cloud.width));
      d.top_row = static_cast<int>(top_row);
      d.free_fraction = freeFraction(cloud, d, ground, origin, params.free_depth_step, walls);
      if (params.reject_top_at_border && d.top_row <= kBorderRows && cutByTopBorder(cloud, d))
        continue;
      // Only a new person must show a free head: one that does not (a hand at the head, a column of a
      // wall or shelf) may only continue a track, in the track's colours (weak), as a bending body,
      // whose back is on top, does.
      if (!(d.free_fraction >= params.min_free_fraction))
        d.weak = true;
      kept.push_back(std::move(d));
    }
    candidates.swap(kept);
  }

}

// A new person's body, as the clutter scenes measured it (evaluate --protocol detection --seed 2,
// non-weak candidates on a person / on anything else): it reaches at least this far down from its top
// (m; people 0.82 and more, a table hiding their legs included; a raised hand split off its body, or
// a shelf board, 0.3-0.5) ...
constexpr float kNewPersonExtent = 0.7f;
// ... and is at least this wide (m; people 0.33 and more but in 2 of 4000 frames, side-on too; a sliver of a
// shelf's side 0.13-0.16, a shelf seen between a person's arm and body 0.28),
constexpr float kNewPersonWidth = 0.3f;
// ... and this large, in detection voxels (people 125 and more in 99 % of frames; a raised hand split off
// its body 30-70, with what lies below it within reach: a shelf's side, a table's edge).
constexpr int kNewPersonVoxels = 100;
// A head whose top slice touches the image's left or right edge cannot be seen to stand free on that
// side: it must then be clearly narrower than the shoulders (people cut by the edge 0.33-0.50; the
// columns of shelves, cabinets and doors cut there 0.67-0.73).
constexpr float kHeadRatioAtSideEdge = 0.6f;
constexpr int kSideEdgeColumns = 3;

// Whether the detection's head (its top kHeadDepth) reaches the image's left or right edge.
bool headAtSideEdge(const Cloud& cloud, const PersonDetection& d, const Eigen::Vector4f& ground)
{
  const int w = static_cast<int>(cloud.width);
  for (const auto i : d.indices)
  {
    const int u = static_cast<int>(i) % w;
    if ((u < kSideEdgeColumns || u >= w - kSideEdgeColumns) &&
        heightAbove(ground, cloud[i].getVector3fMap()) >= d.height - kHeadDepth)
      return true;
  }
  return false;
}

// A head above shoulders: cabinets, shelves, doors and chair backs are as wide at the top as below.
// A body reaching down toward the floor, not a hand or a board in the air; not a sliver. A candidate
// failing these may still continue a track (weak), as one failing HOG.
void markWideTops(const Cloud& cloud, const Eigen::Vector4f& ground, const Eigen::Vector3f& origin,
                  const TrackerParams& params, std::vector<PersonDetection>& candidates)
{
  for (auto& d : candidates)
  {
    d.head_ratio = headRatio(cloud, d, ground, origin);
    const bool at_edge = cloud.height > 1 && headAtSideEdge(cloud, d, ground);
    const float max_ratio = at_edge ? std::min(params.max_head_ratio, kHeadRatioAtSideEdge) : params.max_head_ratio;
    if (params.max_head_ratio > 0.0f && d.head_ratio > max_ratio)  // NaN: cannot tell, kept
      d.weak = true;
    float lowest = d.height;
    for (const auto i : d.indices)
      lowest = std::min(lowest, heightAbove(ground, cloud[i].getVector3fMap()));
    if (d.height - lowest < kNewPersonExtent || d.width < kNewPersonWidth || d.voxels < kNewPersonVoxels)
      d.weak = true;
  }
}

// HOG confirmation (organized clouds only: it needs the image). A person failing it may still
// continue a track (weak): HOG wants upright people, a bending one fails. Returns whether it ran.
bool confirmWithHog(const Cloud& cloud, const Eigen::Vector4f& ground, pcl::people::PersonClassifier<pcl::RGB>* classifier,
                    const TrackerParams& params, std::vector<PersonDetection>& candidates)
{
  const Eigen::Vector3f up = ground.head<3>();
  Eigen::Matrix<float, 3, 4> P;
  if (classifier && !candidates.empty() && fitProjection(cloud, P))
  {
    auto image = pcl::make_shared<pcl::PointCloud<pcl::RGB>>(cloud.width, cloud.height);
    for (std::size_t i = 0; i < cloud.size(); ++i)
    {
      (*image)[i].r = cloud[i].r;
      (*image)[i].g = cloud[i].g;
      (*image)[i].b = cloud[i].b;
    }
    for (auto& d : candidates)
    {
      if (d.weak)
        continue;
      const Eigen::Vector3f foot = d.centroid - heightAbove(ground, d.centroid) * up;
      const Eigen::Vector3f head = foot + d.height * up;
      const Eigen::Vector3f a = P * foot.homogeneous(), b = P * head.homogeneous(),
                            c = P * (0.5f * (foot + head)).homogeneous();
      if (!(a.z() > 0 && b.z() > 0 && c.z() > 0))
        continue;  // behind the camera's image plane: cannot be judged, kept
      const float pixel_height = (a.hnormalized() - b.hnormalized()).norm();
      d.hog_confidence = classifier->evaluate(pixel_height, c.x() / c.z(), c.y() / c.z(), image);
      if (d.hog_confidence < params.hog_min_confidence)
        d.weak = true;
    }
    return true;
  }
  return false;
}

}  // namespace

void joinDetection(PersonDetection& into, const PersonDetection& part, float apart)
{
  const float wp = static_cast<float>(into.voxels), wq = static_cast<float>(part.voxels);
  into.centroid = (wp * into.centroid + wq * part.centroid) / (wp + wq);
  into.height = std::max(into.height, part.height);
  into.width = std::max({ into.width, part.width, apart });
  into.voxels += part.voxels;
  into.indices.insert(into.indices.end(), part.indices.begin(), part.indices.end());
}

namespace
{
// A bending body often falls apart into two low clusters (back and head, legs and arms): weak
// candidates this close on the floor are one body.
void mergeFragments(const Eigen::Vector3f& up, std::vector<PersonDetection>& candidates)
{
  for (std::size_t a = 0; a < candidates.size(); ++a)
  {
    if (!candidates[a].weak)
      continue;
    for (std::size_t b = a + 1; b < candidates.size();)
    {
      PersonDetection& p = candidates[a];
      const PersonDetection& q = candidates[b];
      const Eigen::Vector3f d = q.centroid - p.centroid;
      if (!q.weak || onGround(d, up).norm() > kFragmentDistance)
      {
        ++b;
        continue;
      }
      joinDetection(p, q, onGround(d, up).norm());
      candidates.erase(candidates.begin() + static_cast<std::ptrdiff_t>(b));
    }
  }
}
/**
 * Every usable point of @p cloud (finite, within max_range of @p origin) into @p valid (for the
 * person clouds), and of those every sampling_factor-th in each direction of an organised cloud into
 * @p sampled (what feeds the detection voxels).
 */
void usablePoints(const Cloud& cloud, const Eigen::Vector3f& origin, const TrackerParams& params,
                  pcl::Indices& valid, pcl::Indices& sampled)
{
  const float range2 = params.max_range * params.max_range;
  valid.clear();
  sampled.clear();
  const std::size_t step = cloud.height > 1 ? static_cast<std::size_t>(params.sampling_factor) : 1;
  for (std::size_t r = 0, i = 0; r < cloud.height; ++r)
  {
    const bool sampled_row = r % step == 0;
    for (std::size_t c = 0, phase = 0; c < cloud.width; ++c, ++i, phase = phase + 1 == step ? 0 : phase + 1)
    {
      const PointT& p = cloud[i];
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
          (p.getVector3fMap() - origin).squaredNorm() <= range2)
      {
        valid.push_back(static_cast<pcl::index_t>(i));
        if (sampled_row && phase == 0)
          sampled.push_back(static_cast<pcl::index_t>(i));
      }
    }
  }
}

/**
 * The ground into @p out (unit normal, the camera at @p origin above it): the fixed params.ground, or
 * @p estimator's after it has seen @p voxels (nullptr: too few points this frame, not updated).
 * False while there is none.
 */
bool groundPlane(const Cloud* voxels, const Eigen::Vector3f& origin, const TrackerParams& params,
                 GroundEstimator& estimator, DetectionResult& out)
{
  if (params.ground)
  {
    out.ground = *params.ground / params.ground->head<3>().norm();
    if (out.ground.head<3>().dot(origin) + out.ground[3] < 0.0f)
      out.ground = -out.ground;
  }
  else
  {
    if (voxels)
      estimator.update(*voxels, origin, params.up_hint);
    if (!estimator.valid())
      return false;
    out.ground = estimator.plane();
    out.ground_assumed = estimator.assumed();
  }
  out.ground_valid = true;
  return true;
}
}  // namespace

DetectionResult PeopleDetector::detect(const Cloud& cloud, const Eigen::Vector3f& origin)
{
  DetectionResult out;
  if (cloud.empty() || cloud.size() != static_cast<std::size_t>(cloud.width) * cloud.height || !origin.allFinite())
    return out;

  // ---- finite points in range, voxelised; the ground ----
  // The index lists are kept from frame to frame: a 640x480 frame's are megabytes, and allocating
  // them afresh each frame costs page faults.
  usablePoints(cloud, origin, params_, impl_->valid, impl_->sampled);
  if (impl_->sampled.size() < 3)
  {
    groundPlane(nullptr, origin, params_, impl_->ground, out);
    return out;
  }
  const Cloud& voxels = impl_->voxels;
  impl_->voxel_filter.filter(cloud, params_.detection_voxel_size, &impl_->sampled, impl_->voxels);
  if (!groundPlane(&voxels, origin, params_, impl_->ground, out))
    return out;
  const Eigen::Vector4f ground = out.ground;
  const Eigen::Vector3f up = ground.head<3>();
  const float camera_height = heightAbove(ground, origin);

  const Eigen::Matrix3f R = levelFrame(voxels, origin, up);

  // ---- ground removal (also what lies below it: noise, reflections), then walls ----
  auto above = pcl::make_shared<Cloud>();  // input frame
  auto level = pcl::make_shared<Cloud>();  // the same points in the level frame
  std::vector<Eigen::Vector4f> walls;
  if (!pointsAboveGround(voxels, ground, origin, R, params_, imageTopEdge(cloud, origin, params_.max_range), *above,
                         *level, walls))
    return out;

  // ---- Euclidean clusters ----
  RadiusGrid& grid = impl_->grid;
  std::vector<pcl::PointIndices> clusters =
      euclideanClusters(*level, params_.cluster_tolerance, params_.min_points, std::numeric_limits<int>::max(), grid);
  if (clusters.empty())
    return out;

  // ---- heads: sub-clusters, each voxel with its nearest head ----
  std::vector<pcl::people::PersonCluster<PointT>> heads = headSubclusters(level, clusters, camera_height, params_);
  const std::vector<pcl::Indices> members = assignToNearestHead(heads, *level, camera_height, params_);

  // ---- the candidates and what makes them people (or weak: able to continue a track only) ----
  Candidates found = sizedCandidates(members, *level, *above, ground, grid, params_);
  collectFullResolution(cloud, impl_->valid, ground, params_, found);
  std::vector<PersonDetection>& candidates = found.people;
  keepFreeStanding(cloud, ground, origin, walls, params_, candidates);
  markWideTops(cloud, ground, origin, params_, candidates);
  out.hog_applied = confirmWithHog(cloud, ground, impl_->classifier.get(), params_, candidates);
  mergeFragments(up, candidates);
  out.people.swap(candidates);
  return out;
}

boost::shared_ptr<Cloud> PeopleDetector::personCloud(const Cloud& cloud, const PersonDetection& person) const
{
  auto out = boost::make_shared<Cloud>(
      voxelFiltered(cloud, params_.person_voxel_size, pcl::make_shared<const pcl::Indices>(person.indices)));
  out->width = static_cast<std::uint32_t>(out->size());
  out->height = 1;
  out->is_dense = true;
  return out;
}

}  // namespace action_flow
