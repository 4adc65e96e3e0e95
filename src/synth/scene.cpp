// The virtual Kinect: room ray-cast once per camera pose, body volumes ray-cast inside their image
// boxes each frame, then the sensor model (disparity noise and quantisation, projector shadow,
// edge dropout, range, colour noise).
#include <action_flow/synth/scene.h>

#include "random.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kPi = 3.14159265358979f;

float fract(float x) { return x - std::floor(x); }

// One round of mixing is plenty for texture lattices.
inline std::uint64_t hash3(std::uint64_t x, std::uint64_t y, std::uint64_t z, std::uint64_t seed)
{
  return mix64(x * 0x9e3779b97f4a7c15ULL + y * 0xc2b2ae3d27d4eb4fULL + z * 0x165667b19e3779f9ULL + seed);
}

float cellNoise(const Eigen::Vector3f& p, float cell, std::uint32_t seed)
{
  const auto i = [&](float v) { return std::uint64_t(std::int64_t(std::floor(v / cell))); };
  return unit(hash3(i(p.x()), i(p.y()), i(p.z()), seed));
}

// Trilinear value noise in [0,1], smooth at the scale of one cell.
float valueNoise(const Eigen::Vector3f& p, float cell, std::uint32_t seed)
{
  const Eigen::Vector3f q = p / cell;
  const float fx = std::floor(q.x()), fy = std::floor(q.y()), fz = std::floor(q.z());
  const float tx = q.x() - fx, ty = q.y() - fy, tz = q.z() - fz;
  const auto sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty), sz = tz * tz * (3 - 2 * tz);
  const std::int64_t ix = std::int64_t(fx), iy = std::int64_t(fy), iz = std::int64_t(fz);
  float v[8];
  for (int k = 0; k < 8; ++k)
    v[k] = unit(hash3(std::uint64_t(ix + (k & 1)), std::uint64_t(iy + ((k >> 1) & 1)), std::uint64_t(iz + (k >> 2)), seed));
  const float x00 = v[0] + (v[1] - v[0]) * sx, x10 = v[2] + (v[3] - v[2]) * sx;
  const float x01 = v[4] + (v[5] - v[4]) * sx, x11 = v[6] + (v[7] - v[6]) * sx;
  const float y0 = x00 + (x10 - x00) * sy, y1 = x01 + (x11 - x01) * sy;
  return y0 + (y1 - y0) * sz;
}

// Colour of a material at a point given in the surface's own frame (z along its main axis).
Rgb materialColor(const Material& m, const Eigen::Vector3f& p)
{
  Rgb c = m.base;
  const float per = std::max(m.period, 1e-3f);
  const float around = std::atan2(p.y(), p.x()) * 0.12f;  // arc length on a ~12 cm radius
  switch (m.pattern)
  {
    case Pattern::Plain:
      break;
    case Pattern::HorizontalStripes:
      if (fract(p.z() / per) < 0.5f)
        c = m.second;
      break;
    case Pattern::VerticalStripes:
      if (fract(around / per) < 0.5f)
        c = m.second;
      break;
    case Pattern::Checks:
      if ((int(std::floor(p.z() / per)) + int(std::floor(around / per))) & 1)
        c = m.second;
      break;
    case Pattern::Print:
      if (valueNoise(p, per, m.seed) > 0.62f)
        c = m.second;
      break;
    case Pattern::Denim: {
      const float fade = valueNoise(p, 0.12f, m.seed);
      c = m.base * (0.8f + 0.4f * fade);
      if (cellNoise(p, 0.006f, m.seed + 7) > 0.6f)
        c = 0.5f * (c + m.second);
      break;
    }
    case Pattern::Planks: {
      const float board = std::floor(p.y() / per);
      const float tone = unit(hash64(std::uint64_t(std::int64_t(board)), m.seed));
      const float grain = valueNoise(Eigen::Vector3f(p.x() * 0.08f, p.y() * 2.0f, 0), 0.01f, m.seed + 3);
      c = m.base * (0.8f + 0.3f * tone) + (m.second - m.base) * (0.5f * grain);
      if (fract(p.y() / per) < 0.04f)
        c *= 0.55f;
      break;
    }
    case Pattern::Tiles: {
      const float u = fract(p.x() / per), v = fract(p.y() / per);
      if (u < 0.03f || v < 0.03f)
        c = m.second;
      break;
    }
  }
  if (m.grain > 0)
    c *= 1.0f + m.grain * (2.0f * cellNoise(p, 0.005f, m.seed + 11) - 1.0f);
  return c;
}

// Lambert shading under a light above and behind the camera, plus ambient light.
float shading(const Eigen::Vector3f& normal, const Eigen::Vector3f& light)
{
  return 0.55f + 0.5f * std::max(0.0f, normal.dot(light));
}

std::uint8_t toByte(float v) { return std::uint8_t(std::clamp(v * 255.0f + 0.5f, 0.0f, 255.0f)); }

// Frame with z along @p axis and x toward @p forward (orthogonalised).
Eigen::Matrix3f axisFrame(const Eigen::Vector3f& axis, const Eigen::Vector3f& forward)
{
  Eigen::Vector3f z = axis.normalized();
  Eigen::Vector3f x = forward - forward.dot(z) * z;
  if (x.squaredNorm() < 1e-8f)
  {
    x = z.unitOrthogonal();
  }
  x.normalize();
  Eigen::Matrix3f r;
  r.col(0) = x;
  r.col(1) = z.cross(x);
  r.col(2) = z;
  return r;
}

enum class Part
{
  Head,
  Neck,
  Chest,
  Abdomen,
  Pelvis,
  UpperArm,
  Forearm,
  Hand,
  Thigh,
  Shin,
  Foot
};

// One volume of the body, in the camera's optical frame.
struct Prim
{
  bool capsule = true;
  Part part = Part::Chest;
  // capsule
  Eigen::Vector3f a = Eigen::Vector3f::Zero(), w = Eigen::Vector3f::UnitZ();  // start, unit axis
  float len = 0, r = 0;
  // ellipsoid
  Eigen::Vector3f c = Eigen::Vector3f::Zero(), inv_axes = Eigen::Vector3f::Ones(), o_scaled = Eigen::Vector3f::Zero();
  Eigen::Matrix3f m_scaled = Eigen::Matrix3f::Identity();  // diag(inv_axes) R^T
  // both: local frame for texture and shading
  Eigen::Matrix3f rot = Eigen::Matrix3f::Identity();  // columns: local axes in camera frame
  Eigen::Vector3f origin = Eigen::Vector3f::Zero();    // texture frame origin
  float sleeve = 0;          // forearm: shirt up to this distance along the axis
  const Appearance* look = nullptr;
  std::uint8_t id = 1;
  int u0 = 0, u1 = -1, v0 = 0, v1 = -1;  // image box (inclusive)
};

// A body's joints and axes in the camera's optical frame, and the list its volumes go to.
struct OpticalBody
{
  OpticalBody(const PosedBody& posed, std::vector<Prim>& out,
              const Eigen::Isometry3f& optical_from_world)
    : body(posed), prims(out)
  {
    for (int k = 0; k < kJointCount; ++k)
      s.joints[k] = optical_from_world * body.joints.joints[k];
    fwd = optical_from_world.linear() * body.forward;
    up_world = optical_from_world.linear() * Eigen::Vector3f::UnitZ();
    sc = body.shape.height / 1.75f;
    b = body.shape.build;
  }

  const PosedBody& body;
  std::vector<Prim>& prims;
  Skeleton s;
  Eigen::Vector3f fwd, up_world;
  float sc, b;  // size scale (height / 1.75 m), build
};

}  // namespace

Eigen::Isometry3f CameraModel::worldFromOptical() const
{
  const float s = float(std::sin(tilt)), c = float(std::cos(tilt));
  Eigen::Matrix3f r;
  r.col(0) = Eigen::Vector3f(0, -1, 0);  // optical x: right = world -y
  r.col(1) = Eigen::Vector3f(-s, 0, -c); // optical y: down, tilted
  r.col(2) = Eigen::Vector3f(c, 0, -s);  // optical z: forward, pitched down
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.linear() = r;
  t.translation() = Eigen::Vector3f(0, 0, float(height_above_floor));
  return t;
}

std::vector<Box> Room::chair(float x, float y, float yaw, float seat_height, const Material& m)
{
  std::vector<Box> boxes;
  const Eigen::Vector2f f(std::cos(yaw), std::sin(yaw)), l(-std::sin(yaw), std::cos(yaw));
  const auto at = [&](float fw, float lf, float z) {
    const Eigen::Vector2f p = Eigen::Vector2f(x, y) + fw * f + lf * l;
    return Eigen::Vector3f(p.x(), p.y(), z);
  };
  const float half = 0.22f, leg = 0.02f, seat_t = 0.025f;
  Box seat;
  seat.center = at(0, 0, seat_height - seat_t);
  seat.half = Eigen::Vector3f(half, half, seat_t);
  seat.yaw = yaw;
  seat.material = m;
  boxes.push_back(seat);
  for (int i = 0; i < 4; ++i)
  {
    Box b = seat;
    const float fw = (i & 1) ? half - leg : -(half - leg), lf = (i & 2) ? half - leg : -(half - leg);
    b.center = at(fw, lf, (seat_height - 2 * seat_t) / 2);
    b.half = Eigen::Vector3f(leg, leg, (seat_height - 2 * seat_t) / 2);
    boxes.push_back(b);
  }
  Box back = seat;
  back.center = at(-half + 0.015f, 0, seat_height + 0.25f);
  back.half = Eigen::Vector3f(0.015f, half, 0.22f);
  boxes.push_back(back);
  return boxes;
}

Room Room::lab(std::uint32_t seed)
{
  Room room;
  room.floor_material.base = Rgb(0.55f, 0.38f, 0.22f);
  room.floor_material.second = Rgb(0.35f, 0.22f, 0.12f);
  room.floor_material.pattern = Pattern::Planks;
  room.floor_material.period = 0.14f;
  room.floor_material.grain = 0.06f;
  room.floor_material.seed = seed;
  room.wall_material.base = Rgb(0.82f, 0.8f, 0.72f);
  room.wall_material.grain = 0.04f;
  room.wall_material.seed = seed + 1;
  room.ceiling_material.base = Rgb(0.9f, 0.9f, 0.9f);
  room.ceiling_material.seed = seed + 2;
  Box cabinet;
  cabinet.center = Eigen::Vector3f(3.9f, -1.55f, 0.55f);
  cabinet.half = Eigen::Vector3f(0.3f, 0.45f, 0.55f);
  cabinet.material.base = Rgb(0.3f, 0.33f, 0.4f);
  cabinet.material.second = Rgb(0.2f, 0.2f, 0.25f);
  cabinet.material.pattern = Pattern::HorizontalStripes;
  cabinet.material.period = 0.37f;
  cabinet.material.seed = seed + 3;
  room.boxes.push_back(cabinet);
  Box poster;
  poster.center = Eigen::Vector3f(4.29f, 0.6f, 1.5f);
  poster.half = Eigen::Vector3f(0.01f, 0.35f, 0.25f);
  poster.material.base = Rgb(0.85f, 0.3f, 0.2f);
  poster.material.second = Rgb(0.15f, 0.35f, 0.7f);
  poster.material.pattern = Pattern::Print;
  poster.material.period = 0.08f;
  poster.material.seed = seed + 4;
  room.boxes.push_back(poster);
  Box door;
  door.center = Eigen::Vector3f(3.2f, 2.29f, 1.0f);
  door.half = Eigen::Vector3f(0.45f, 0.02f, 1.0f);
  door.material.base = Rgb(0.6f, 0.45f, 0.3f);
  door.material.seed = seed + 5;
  room.boxes.push_back(door);
  return room;
}

struct SceneRenderer::Impl
{
  CameraModel cam;
  Eigen::Isometry3f world_from_optical, optical_from_world;
  std::vector<float> room_depth;       // noise-free, +inf where nothing
  std::vector<float> room_disp;        // f*b / room_depth, 0 where nothing
  std::vector<float> depth_of_step;    // reported depth (m, NaN outside the range) of k disparity steps
  std::vector<std::uint8_t> room_rgb;  // shaded
  Eigen::Vector3f light_world;

  void castRoom(const Room& room);
  void buildPrims(const PosedBody& body, std::vector<Prim>& prims) const;
  // Steps of buildPrims; the capsule's pointer stays valid while prims has room reserved.
  Prim* addCapsule(OpticalBody& ob, Part part, const Eigen::Vector3f& from,
                   const Eigen::Vector3f& to, float radius) const;
  void addEllipsoid(OpticalBody& ob, Part part, const Eigen::Vector3f& center,
                    const Eigen::Matrix3f& rot, const Eigen::Vector3f& axes,
                    const Eigen::Vector3f& tex_origin) const;
  Eigen::Matrix3f addTrunkAndHead(OpticalBody& ob) const;  // returns the hips' frame
  void addLimbs(OpticalBody& ob, int side, const Eigen::Matrix3f& hips) const;
  void drawPrim(const Prim& p, std::vector<float>& depth, std::vector<std::uint8_t>& rgb,
                std::vector<std::uint8_t>& mask) const;
  Rgb primColor(const Prim& p, const Eigen::Vector3f& hit, const Eigen::Vector3f& normal) const;
  // Steps of render: the exact images, then the sensor model on depth and on colour.
  void drawBodies(const std::vector<PosedBody>& bodies, std::vector<float>& exact,
                  FrameImages& out) const;
  void sensorDepth(const std::vector<float>& exact, const std::vector<std::uint8_t>& mask,
                   std::uint64_t frame_key, std::vector<float>& depth) const;
  void addColorNoise(std::uint64_t frame_key, std::vector<std::uint8_t>& rgb) const;
  void setBox(Prim& p) const;
};

SceneRenderer::SceneRenderer(const CameraModel& camera, const Room& room) : impl_(new Impl)
{
  if (camera.width <= 0 || camera.height <= 0 || camera.fx <= 0 || camera.fy <= 0 || camera.fps <= 0 ||
      camera.min_depth <= 0 || camera.max_depth <= camera.min_depth || camera.baseline <= 0 ||
      camera.disparity_step <= 0)
    throw std::invalid_argument("SceneRenderer: invalid camera model");
  impl_->cam = camera;
  impl_->world_from_optical = camera.worldFromOptical();
  impl_->optical_from_world = impl_->world_from_optical.inverse();
  impl_->light_world = Eigen::Vector3f(-0.5f, 0.3f, 1.0f).normalized();
  impl_->castRoom(room);
  // Depth of each quantised disparity, as the driver reports it: millimetres, NaN out of range.
  const double fb = camera.fx * camera.baseline;
  const int steps = int(fb / (camera.min_depth * camera.disparity_step)) + 2;
  impl_->depth_of_step.assign(size_t(steps) + 1, kNaN);
  for (int k = 1; k <= steps; ++k)
  {
    const double z = std::round(fb / (k * camera.disparity_step) * 1000.0) / 1000.0;
    if (z >= camera.min_depth && z <= camera.max_depth)
      impl_->depth_of_step[size_t(k)] = float(z);
  }
  impl_->room_disp.resize(impl_->room_depth.size());
  for (size_t i = 0; i < impl_->room_depth.size(); ++i)
    impl_->room_disp[i] = std::isfinite(impl_->room_depth[i]) ? float(fb) / impl_->room_depth[i] : 0.0f;
}

SceneRenderer::~SceneRenderer() = default;
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;

const CameraModel& SceneRenderer::camera() const { return impl_->cam; }
const std::vector<float>& SceneRenderer::roomDepth() const { return impl_->room_depth; }

namespace
{
// A room box with its axes in the world frame.
struct BoxFrame
{
  Eigen::Matrix3f rot;  // box axes in world
  const Box* box;
};

// The nearest room surface along a camera ray so far.
struct RoomHit
{
  float t = kInf;  // optical depth
  Eigen::Vector3f normal = Eigen::Vector3f(0, 0, 1), local = Eigen::Vector3f(0, 0, 0);
  const Material* mat = nullptr;
};

// The ray o + t d against the plane x[axis] = value facing @p sign.
void hitPlane(const Eigen::Vector3f& o, const Eigen::Vector3f& d, int axis, float value, float sign,
              const Material& m, RoomHit& hit)
{
  if (std::abs(d[axis]) < 1e-9f)
    return;
  const float t = (value - o[axis]) / d[axis];
  if (t > 0 && t < hit.t)
  {
    hit.t = t;
    hit.normal = Eigen::Vector3f::Zero();
    hit.normal[axis] = sign;
    hit.local = o + t * d;
    hit.mat = &m;
  }
}

// The ray o + t d against a box: slab test in the box's frame.
void hitBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, const BoxFrame& bf, RoomHit& hit)
{
  const Eigen::Vector3f lo = bf.rot.transpose() * (o - bf.box->center);
  const Eigen::Vector3f ld = bf.rot.transpose() * d;
  float t0 = 0, t1 = hit.t;
  int axis = -1;
  float sign = 1;
  bool overlap = true;
  for (int k = 0; k < 3 && overlap; ++k)
  {
    const float hk = bf.box->half[k];
    if (std::abs(ld[k]) < 1e-12f)
    {
      overlap = std::abs(lo[k]) <= hk;
      continue;
    }
    float ta = (-hk - lo[k]) / ld[k], tb = (hk - lo[k]) / ld[k];
    float s = -1;
    if (ta > tb)
    {
      std::swap(ta, tb);
      s = 1;
    }
    if (ta > t0)
    {
      t0 = ta;
      axis = k;
      sign = s;
    }
    t1 = std::min(t1, tb);
    overlap = t0 <= t1;
  }
  if (overlap && axis >= 0 && t0 < hit.t)
  {
    hit.t = t0;
    Eigen::Vector3f n = Eigen::Vector3f::Zero();
    n[axis] = sign;
    hit.normal = bf.rot * n;
    hit.local = lo + t0 * ld;
    hit.mat = &bf.box->material;
  }
}

// The nearest of the room's floor, walls, ceiling and boxes along the ray o + t d.
RoomHit castRoomRay(const Room& room, const std::vector<BoxFrame>& boxes, const Eigen::Vector3f& o,
                    const Eigen::Vector3f& d)
{
  RoomHit hit;
  if (room.floor)
    hitPlane(o, d, 2, 0.0f, 1.0f, room.floor_material, hit);
  if (room.walls)
  {
    hitPlane(o, d, 0, room.back_wall, -1.0f, room.wall_material, hit);
    hitPlane(o, d, 1, room.left_wall, -1.0f, room.wall_material, hit);
    hitPlane(o, d, 1, room.right_wall, 1.0f, room.wall_material, hit);
    hitPlane(o, d, 2, room.ceiling, -1.0f, room.ceiling_material, hit);
  }
  for (const BoxFrame& bf : boxes)
    hitBox(o, d, bf, hit);
  return hit;
}

}  // namespace

void SceneRenderer::Impl::castRoom(const Room& room)
{
  const int w = cam.width, h = cam.height;
  room_depth.assign(size_t(w) * h, kInf);
  room_rgb.assign(size_t(w) * h * 3, 0);
  const Eigen::Matrix3f r = world_from_optical.linear();
  const Eigen::Vector3f o = world_from_optical.translation();
  std::vector<BoxFrame> boxes;
  for (const Box& b : room.boxes)
    boxes.push_back({ Eigen::AngleAxisf(b.yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix(), &b });
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
    {
      const Eigen::Vector3f d_opt(float((u - cam.cx) / cam.fx), float((v - cam.cy) / cam.fy), 1.0f);
      const Eigen::Vector3f d = r * d_opt;  // t along d is the optical depth
      const RoomHit hit = castRoomRay(room, boxes, o, d);
      const size_t i = size_t(v) * w + u;
      if (!hit.mat)
        continue;
      room_depth[i] = hit.t;
      const Rgb c = materialColor(*hit.mat, hit.local) * shading(hit.normal, light_world);
      room_rgb[3 * i] = toByte(c.x());
      room_rgb[3 * i + 1] = toByte(c.y());
      room_rgb[3 * i + 2] = toByte(c.z());
    }
}

void SceneRenderer::Impl::setBox(Prim& p) const
{
  // Image box of the volume's axis-aligned bounding box (camera frame).
  Eigen::Vector3f lo, hi;
  if (p.capsule)
  {
    const Eigen::Vector3f b = p.a + p.len * p.w;
    lo = p.a.cwiseMin(b).array() - p.r;
    hi = p.a.cwiseMax(b).array() + p.r;
  }
  else
  {
    const Eigen::Vector3f axes = p.inv_axes.cwiseInverse();
    Eigen::Vector3f ext;
    for (int k = 0; k < 3; ++k)
      ext[k] = (p.rot.row(k).transpose().cwiseProduct(axes)).norm();
    lo = p.c - ext;
    hi = p.c + ext;
  }
  if (lo.z() < 0.05f)
  {
    p.u1 = -1;  // behind or at the camera: not drawn
    return;
  }
  float umin = kInf, umax = -kInf, vmin = kInf, vmax = -kInf;
  for (int k = 0; k < 8; ++k)
  {
    const Eigen::Vector3f q((k & 1) ? hi.x() : lo.x(), (k & 2) ? hi.y() : lo.y(), (k & 4) ? hi.z() : lo.z());
    const float u = float(cam.fx) * q.x() / q.z() + float(cam.cx), v = float(cam.fy) * q.y() / q.z() + float(cam.cy);
    umin = std::min(umin, u);
    umax = std::max(umax, u);
    vmin = std::min(vmin, v);
    vmax = std::max(vmax, v);
  }
  p.u0 = std::max(0, int(std::floor(umin)));
  p.u1 = std::min(cam.width - 1, int(std::ceil(umax)));
  p.v0 = std::max(0, int(std::floor(vmin)));
  p.v1 = std::min(cam.height - 1, int(std::ceil(vmax)));
}

void SceneRenderer::Impl::buildPrims(const PosedBody& body, std::vector<Prim>& prims) const
{
  if (!body.appearance)
    throw std::invalid_argument("SceneRenderer: a body without appearance");
  OpticalBody ob(body, prims, optical_from_world);
  const Eigen::Matrix3f hips = addTrunkAndHead(ob);
  for (int side = 0; side < 2; ++side)
    addLimbs(ob, side, hips);
}

Prim* SceneRenderer::Impl::addCapsule(OpticalBody& ob, Part part, const Eigen::Vector3f& from,
                                      const Eigen::Vector3f& to, float radius) const
{
  Prim p;
  p.capsule = true;
  p.part = part;
  p.a = from;
  const Eigen::Vector3f ab = to - from;
  p.len = ab.norm();
  p.w = p.len > 1e-6f ? Eigen::Vector3f(ab / p.len) : ob.up_world;
  p.r = radius;
  p.rot = axisFrame(p.w, ob.fwd);
  p.origin = from;
  p.look = ob.body.appearance;
  p.id = ob.body.id;
  setBox(p);
  ob.prims.push_back(p);
  return &ob.prims.back();
}

void SceneRenderer::Impl::addEllipsoid(OpticalBody& ob, Part part, const Eigen::Vector3f& center,
                                       const Eigen::Matrix3f& rot, const Eigen::Vector3f& axes,
                                       const Eigen::Vector3f& tex_origin) const
{
  Prim p;
  p.capsule = false;
  p.part = part;
  p.c = center;
  p.rot = rot;
  p.inv_axes = axes.cwiseInverse();
  p.m_scaled = p.inv_axes.asDiagonal() * rot.transpose();
  p.o_scaled = p.m_scaled * (-center);
  p.origin = tex_origin;
  p.look = ob.body.appearance;
  p.id = ob.body.id;
  setBox(p);
  ob.prims.push_back(p);
}

Eigen::Matrix3f SceneRenderer::Impl::addTrunkAndHead(OpticalBody& ob) const
{
  const Skeleton& s = ob.s;
  const float sc = ob.sc, b = ob.b;
  const Eigen::Vector3f head = s[Joint::Head], neck = s[Joint::Neck], torso = s[Joint::Torso];
  const Eigen::Vector3f lh = s[Joint::LeftHip], rh = s[Joint::RightHip];
  const Eigen::Vector3f pelvis = 0.5f * (lh + rh);
  // Trunk frame: up from the pelvis to the neck, forward = the body's facing made orthogonal.
  const Eigen::Matrix3f trunk = axisFrame(neck - pelvis, ob.fwd);
  const Eigen::Matrix3f hips = axisFrame(torso - pelvis, ob.fwd);
  const float trunk_len = (neck - pelvis).norm();
  // Chest: the upper part of the trunk, abdomen between, pelvis block around the hips.
  addEllipsoid(ob, Part::Chest,
               neck - trunk.col(2) * (0.34f * trunk_len) - trunk.col(0) * (0.005f * sc), trunk,
               Eigen::Vector3f(0.105f * b * sc, 0.175f * b * sc, 0.42f * trunk_len), neck);
  addEllipsoid(ob, Part::Abdomen, pelvis + trunk.col(2) * (0.38f * trunk_len), trunk,
               Eigen::Vector3f(0.1f * b * b * sc, 0.155f * b * sc, 0.28f * trunk_len), neck);
  addEllipsoid(ob, Part::Pelvis, pelvis + hips.col(2) * (0.03f * sc), hips,
               Eigen::Vector3f(0.105f * b * sc, 0.175f * b * sc, 0.13f * sc), pelvis);
  // Shoulder girdle: fills the line between the shoulders, textured in the trunk's frame so the
  // shirt's pattern runs on from the chest.
  Prim* girdle =
      addCapsule(ob, Part::Chest, s[Joint::LeftShoulder], s[Joint::RightShoulder], 0.06f * b * sc);
  girdle->rot = trunk;
  girdle->origin = neck;
  const Eigen::Matrix3f head_rot = axisFrame(head - neck, ob.fwd);
  addEllipsoid(ob, Part::Head, head + head_rot.col(2) * (0.01f * sc), head_rot,
               Eigen::Vector3f(0.1f * sc, 0.08f * sc, 0.115f * sc), head);
  addCapsule(ob, Part::Neck, neck - trunk.col(2) * (0.03f * sc),
             head - head_rot.col(2) * (0.06f * sc), 0.05f * sc * std::sqrt(b));
  return hips;
}

void SceneRenderer::Impl::addLimbs(OpticalBody& ob, int side, const Eigen::Matrix3f& hips) const
{
  const Skeleton& s = ob.s;
  const Eigen::Vector3f& fwd = ob.fwd;
  const Eigen::Vector3f& up_world = ob.up_world;
  const float sc = ob.sc, b = ob.b;
  const LimbJoints limb = limbJoints(side);
  const Joint sh = limb.shoulder, el = limb.elbow, ha = limb.hand;
  const Joint hp = limb.hip, kn = limb.knee, ft = limb.foot;
  addCapsule(ob, Part::UpperArm, s[sh], s[el], 0.046f * b * sc);
  const Eigen::Vector3f fa = s[ha] - s[el];
  const float fa_len = fa.norm();
  const Eigen::Vector3f fa_dir = fa_len > 1e-6f ? Eigen::Vector3f(fa / fa_len) : -up_world;
  Prim* forearm =
      addCapsule(ob, Part::Forearm, s[el], s[ha] - fa_dir * (0.05f * sc), 0.037f * b * sc);
  forearm->sleeve = ob.body.appearance->long_sleeves ? 1.0f : 0.0f;
  const Eigen::Matrix3f hand_rot = axisFrame(fa_dir, fwd);
  addEllipsoid(ob, Part::Hand, s[ha], hand_rot,
               Eigen::Vector3f(0.045f * sc, 0.022f * sc, 0.07f * sc), s[ha]);
  addCapsule(ob, Part::Thigh, s[hp], s[kn], 0.068f * b * sc);
  addCapsule(ob, Part::Shin, s[kn], s[ft], 0.05f * b * sc);
  // The foot lies along the horizontal facing, its sole near the floor.
  Eigen::Vector3f foot_fwd = fwd - fwd.dot(up_world) * up_world;
  if (foot_fwd.squaredNorm() < 1e-6f)
    foot_fwd = hips.col(0);
  foot_fwd.normalize();
  const Eigen::Matrix3f foot_rot = axisFrame(up_world, foot_fwd);
  addEllipsoid(ob, Part::Foot, s[ft] + foot_fwd * (0.06f * sc) - up_world * (0.03f * sc), foot_rot,
               Eigen::Vector3f(0.13f * sc, 0.05f * sc, 0.045f * sc), s[ft]);
}

Rgb SceneRenderer::Impl::primColor(const Prim& p, const Eigen::Vector3f& hit, const Eigen::Vector3f& normal) const
{
  const Appearance& look = *p.look;
  const Eigen::Vector3f local = p.rot.transpose() * (hit - p.origin);
  const Material* m = &look.shirt;
  switch (p.part)
  {
    case Part::Head: {
      // Hair on the top and back; long hair reaches lower at the back.
      const float hair_line = look.long_hair ? -0.09f : 0.02f;
      const bool back = local.x() < -0.02f && local.z() > hair_line;
      m = (local.z() > 0.045f || back) ? &look.hair : &look.skin;
      // Eyes and mouth: darker spots on the face.
      if (m == &look.skin && local.x() > 0.06f)
      {
        const bool eye = std::abs(local.z() - 0.02f) < 0.012f && std::abs(std::abs(local.y()) - 0.032f) < 0.012f;
        const bool mouth = std::abs(local.z() + 0.045f) < 0.007f && std::abs(local.y()) < 0.022f;
        if (eye || mouth)
          return Rgb(0.15f, 0.1f, 0.1f) * shading(normal, optical_from_world.linear() * light_world);
      }
      break;
    }
    case Part::Neck:
    case Part::Hand:
      m = &look.skin;
      break;
    case Part::Chest:
    case Part::Abdomen:
    case Part::UpperArm:
      m = &look.shirt;
      break;
    case Part::Forearm:
      m = local.z() < (p.sleeve > 0 ? 1e3f : 0.04f) ? &look.shirt : &look.skin;
      break;
    case Part::Pelvis:
    case Part::Thigh:
    case Part::Shin:
      m = &look.trousers;
      break;
    case Part::Foot:
      m = &look.shoes;
      break;
  }
  return materialColor(*m, local) * shading(normal, optical_from_world.linear() * light_world);
}

void SceneRenderer::Impl::drawPrim(const Prim& p, std::vector<float>& depth, std::vector<std::uint8_t>& rgb,
                                   std::vector<std::uint8_t>& mask) const
{
  const float ifx = float(1.0 / cam.fx), ify = float(1.0 / cam.fy), cx = float(cam.cx), cy = float(cam.cy);
  const int w = cam.width;
  // Capsule constants: q = origin - a = -a, and its part perpendicular to the axis.
  const Eigen::Vector3f q = -p.a;
  const float qw = q.dot(p.w);
  const Eigen::Vector3f q_perp = q - qw * p.w;
  const float c_cyl = q_perp.squaredNorm() - p.r * p.r;
  const float oo = p.o_scaled.squaredNorm() - 1.0f;
  for (int v = p.v0; v <= p.v1; ++v)
    for (int u = p.u0; u <= p.u1; ++u)
    {
      const Eigen::Vector3f d((u - cx) * ifx, (v - cy) * ify, 1.0f);
      float t;
      Eigen::Vector3f normal;
      const size_t i = size_t(v) * w + u;
      if (p.capsule)
      {
        const float dw = d.dot(p.w);
        const Eigen::Vector3f d_perp = d - dw * p.w;
        const float a = d_perp.squaredNorm(), bq = q_perp.dot(d_perp);
        const float disc = bq * bq - a * c_cyl;
        if (disc < 0 || a < 1e-12f)
          continue;
        t = (-bq - std::sqrt(disc)) / a;
        const float s = t * dw + qw;  // position along the axis of the hit
        if (s < 0 || s > p.len)
        {
          const Eigen::Vector3f cap = s < 0 ? p.a : Eigen::Vector3f(p.a + p.len * p.w);
          const float dd = d.squaredNorm(), dc = d.dot(cap), disc2 = dc * dc - dd * (cap.squaredNorm() - p.r * p.r);
          if (disc2 < 0)
            continue;
          t = (dc - std::sqrt(disc2)) / dd;
          if (t <= 0 || t >= depth[i])
            continue;
          normal = (t * d - cap) / p.r;
        }
        else
        {
          if (t <= 0 || t >= depth[i])
            continue;
          normal = (t * d - p.a - s * p.w) / p.r;
        }
      }
      else
      {
        const Eigen::Vector3f ds = p.m_scaled * d;
        const float a = ds.squaredNorm(), bq = p.o_scaled.dot(ds);
        const float disc = bq * bq - a * oo;
        if (disc < 0)
          continue;
        t = (-bq - std::sqrt(disc)) / a;
        if (t <= 0 || t >= depth[i])
          continue;
        const Eigen::Vector3f ps = p.o_scaled + t * ds;
        normal = (p.rot * ps.cwiseProduct(p.inv_axes)).normalized();
      }
      depth[i] = t;
      mask[i] = p.id;
      const Rgb c = primColor(p, t * d, normal);
      rgb[3 * i] = toByte(c.x());
      rgb[3 * i + 1] = toByte(c.y());
      rgb[3 * i + 2] = toByte(c.z());
    }
}

void SceneRenderer::Impl::drawBodies(const std::vector<PosedBody>& bodies,
                                     std::vector<float>& exact, FrameImages& out) const
{
  exact = room_depth;
  out.rgb = room_rgb;
  out.mask.assign(size_t(cam.width) * cam.height, 0);
  std::vector<Prim> prims;
  prims.reserve(24 * bodies.size());  // 18 a body; addCapsule() hands out pointers into it
  for (const PosedBody& body : bodies)
    buildPrims(body, prims);
  for (const Prim& p : prims)
    if (p.u1 >= p.u0 && p.v1 >= p.v0)
      drawPrim(p, exact, out.rgb, out.mask);
}

void SceneRenderer::Impl::sensorDepth(const std::vector<float>& exact,
                                      const std::vector<std::uint8_t>& mask,
                                      std::uint64_t frame_key, std::vector<float>& depth) const
{
  const int w = cam.width, h = cam.height;
  const size_t n = size_t(w) * h;
  // Sensor model in disparity space, where the Kinect's error is constant: sigma_z = k z^2
  // means sigma_d = k f b. Quantisation to 1/8 px supplies part of it; noise supplies the rest.
  const float fb = float(cam.fx * cam.baseline), step = float(cam.disparity_step);
  const float sigma_total = float(cam.noise_coefficient) * fb;
  const float sigma_noise =
      std::sqrt(std::max(0.0f, sigma_total * sigma_total - step * step / 12.0f));
  // Disparity: the room's is fixed, only body pixels need a division.
  thread_local std::vector<float> disp;  // per-thread scratch, as in render()
  disp.resize(n);
  for (size_t i = 0; i < n; ++i)
    disp[i] = mask[i] ? fb / exact[i] : room_disp[i];
  const float drop = float(cam.edge_dropout);
  const int nb = std::max(1, cam.noise_block);
  const float inv_step = 1.0f / step;
  const int max_k = int(depth_of_step.size()) - 1;
  thread_local std::vector<float> block_noise;
  block_noise.resize(size_t(w / nb + 1));
  for (int v = 0; v < h; ++v)
  {
    // The Kinect matches the speckle pattern over a window, so neighbouring pixels share their
    // error: one noise value per block of noise_block x noise_block pixels.
    if (v % nb == 0)
      for (size_t b = 0; b < block_noise.size(); ++b)
        block_noise[b] = sigma_noise * gauss(mix64(frame_key ^ ((size_t(v / nb) * size_t(w) + b) * 0xd1b54a32d192ed03ULL)));
    // The projector sits beside the camera: a near edge hides the pattern from the surface to its
    // left over a width equal to the disparity difference (right-to-left sweep).
    float shadow = -kInf;
    for (int u = w - 1; u >= 0; --u)
    {
      const size_t i = size_t(v) * w + u;
      const bool shadowed = shadow > disp[i] + 0.25f;
      shadow = std::max(shadow, disp[i]) - 1.0f;
      const float z = exact[i];
      if (!(z < kInf) || shadowed)
      {
        depth[i] = kNaN;
        continue;
      }
      // Depth edges: the neighbour right or below at a clearly different depth.
      const float tol = 0.04f + 0.02f * z;
      const bool edge = (u + 1 < w && std::abs(exact[i + 1] - z) > tol) || (u > 0 && std::abs(exact[i - 1] - z) > tol) ||
                        (v + 1 < h && std::abs(exact[i + w] - z) > tol) || (v > 0 && std::abs(exact[i - w] - z) > tol);
      if (edge && unit(mix64(frame_key + i * 0x9e3779b97f4a7c15ULL)) < drop)
      {
        depth[i] = kNaN;
        continue;
      }
      // Quantised disparity k steps -> depth in millimetres, in range or NaN (table).
      const int k = int((disp[i] + block_noise[size_t(u / nb)]) * inv_step + 0.5f);
      depth[i] = depth_of_step[size_t(std::clamp(k, 0, max_k))];
    }
  }
}

void SceneRenderer::Impl::addColorNoise(std::uint64_t frame_key,
                                        std::vector<std::uint8_t>& rgb) const
{
  const size_t n = size_t(cam.width) * cam.height;
  const float cs = float(cam.color_noise) / 0.408f;  // the triangular variable's std is 0.408
  // A channel's noise is cs * (a + b - 255) / 255 for two random bytes a and b: it takes one of 511
  // values, tabled here by a + b (the same float operations, so the same images, without a division
  // a channel: this was a tenth of the evaluation's descriptor time).
  std::array<float, 511> noise;
  for (int s = 0; s < 511; ++s)
    noise[size_t(s)] = cs * ((float(s) - 255.0f) / 255.0f);
  for (size_t i = 0; i < n; ++i)
  {
    const std::uint64_t hsh = mix64((frame_key ^ 0xc0104ULL) + i * 0x9e3779b97f4a7c15ULL);
    for (int c = 0; c < 3; ++c)
    {
      const unsigned s = unsigned((hsh >> (16 * c)) & 0xff) + unsigned((hsh >> (16 * c + 8)) & 0xff);
      const float val = float(rgb[3 * i + c]) + noise[s];
      rgb[3 * i + c] = std::uint8_t(std::clamp(val + 0.5f, 0.0f, 255.0f));  // truncation after +0.5 rounds
    }
  }
}

void SceneRenderer::render(const std::vector<PosedBody>& bodies, std::uint64_t noise_seed, int frame,
                           FrameImages& out) const
{
  const Impl& m = *impl_;
  const CameraModel& cam = m.cam;
  const size_t n = size_t(cam.width) * cam.height;
  out.width = cam.width;
  out.height = cam.height;
  // Per-thread scratch: fresh multi-megabyte buffers every frame cost more in page faults than the
  // rendering itself.
  thread_local std::vector<float> exact;
  m.drawBodies(bodies, exact, out);

  out.depth.resize(n);
  const float min_d = float(cam.min_depth), max_d = float(cam.max_depth);
  if (!cam.noise)
  {
    for (size_t i = 0; i < n; ++i)
      out.depth[i] = (exact[i] >= min_d && exact[i] <= max_d) ? exact[i] : kNaN;
    return;
  }
  const std::uint64_t frame_key = hash64(noise_seed, std::uint64_t(frame), 0x6b696e656374ULL);
  m.sensorDepth(exact, out.mask, frame_key, out.depth);
  m.addColorNoise(frame_key, out.rgb);
}

void SceneRenderer::toFrameCloud(const FrameImages& images, double stamp, int frame, Cloud& cloud,
                                 std::vector<std::uint8_t>* mask) const
{
  toCloud(images, cloud);
  cloud.header.stamp = std::uint64_t(std::llround(stamp * 1e6));
  cloud.header.seq = std::uint32_t(frame);
  if (mask)
    *mask = images.mask;
}

void SceneRenderer::toCloud(const FrameImages& im, Cloud& cloud) const
{
  const CameraModel& cam = impl_->cam;
  cloud.width = std::uint32_t(im.width);
  cloud.height = std::uint32_t(im.height);
  cloud.is_dense = false;
  cloud.points.resize(size_t(im.width) * im.height);
  // Padding bytes too: clouds are compared and serialised byte by byte (determinism).
  std::memset(static_cast<void*>(cloud.points.data()), 0, cloud.points.size() * sizeof(PointT));
  cloud.header.frame_id = kOpticalFrame;
  const float ifx = float(1.0 / cam.fx), ify = float(1.0 / cam.fy), cx = float(cam.cx), cy = float(cam.cy);
  for (int v = 0; v < im.height; ++v)
    for (int u = 0; u < im.width; ++u)
    {
      const size_t i = size_t(v) * im.width + u;
      PointT& p = cloud.points[i];
      const float z = im.depth[i];
      if (std::isfinite(z))
      {
        p.x = (u - cx) * ifx * z;
        p.y = (v - cy) * ify * z;
        p.z = z;
      }
      else
      {
        p.x = p.y = p.z = kNaN;
      }
      p.r = im.rgb[3 * i];
      p.g = im.rgb[3 * i + 1];
      p.b = im.rgb[3 * i + 2];
      p.a = 255;
      p.data[3] = 1.0f;
    }
}

}  // namespace synth
}  // namespace action_flow
