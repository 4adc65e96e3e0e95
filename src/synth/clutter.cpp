// Cluttered rooms (dataset "clutter"): the camera, the room, labelled furniture and the actor's
// motion of one scene, drawn from its spec. See docs/synth.md, "Clutter".
#include <action_flow/synth/clutter.h>

#include "motion.h"
#include "random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr float kDeg = kPi / 180.0f;
// The camera's pitch range (down positive, CameraModel::tilt): 10 degrees up to 20 degrees down.
constexpr float kTiltLow = -10.0f * kDeg, kTiltHigh = 20.0f * kDeg;
constexpr int kFurnitureFrames = 30;
constexpr int kMaxPersonFrames = 90;

// Actions done on the spot (no chair, no walking); pick_up is drawn more often (bending bodies).
const std::vector<std::string>& onTheSpot()
{
  static const std::vector<std::string> a = { "standing", "kick",          "wave",         "point",
                                              "cross_arms", "check_watch", "scratch_head", "punch",
                                              "throw_bottom_up", "throw_over_head", "turn_around" };
  return a;
}

Material plain(const Rgb& base, float grain, std::uint32_t seed, Pattern pattern = Pattern::Plain, float period = 0.05f)
{
  Material m;
  m.base = base;
  m.second = base * 0.7f;
  m.pattern = pattern;
  m.period = period;
  m.grain = grain;
  m.seed = seed;
  return m;
}

Material wood(Rng& r)
{
  const float k = float(r.uniform(0.7, 1.2));
  return plain(Rgb(0.5f, 0.33f, 0.18f) * k, 0.1f, std::uint32_t(r.next()));
}

Box box(const Eigen::Vector3f& centre, const Eigen::Vector3f& half, float yaw, const Material& m)
{
  Box b;
  b.center = centre;
  b.half = half;
  b.yaw = yaw;
  b.material = m;
  return b;
}

// A point at forward fw and left lf of (x, y) in the frame turned by yaw, at height z.
Eigen::Vector3f at(const Eigen::Vector2f& xy, float yaw, float fw, float lf, float z)
{
  const Eigen::Vector2f f(std::cos(yaw), std::sin(yaw)), l(-std::sin(yaw), std::cos(yaw));
  const Eigen::Vector2f p = xy + fw * f + lf * l;
  return Eigen::Vector3f(p.x(), p.y(), z);
}

ClutterObject chair(const Eigen::Vector2f& xy, float yaw, Rng& r)
{
  return { "chair", Room::chair(xy.x(), xy.y(), yaw, float(r.uniform(0.42, 0.5)), wood(r)) };
}

ClutterObject table(const Eigen::Vector2f& xy, float yaw, float length, float depth, Rng& r)
{
  const Material m = wood(r);
  const float top = float(r.uniform(0.71, 0.77)), leg = 0.03f;
  ClutterObject o{ "table", { box(at(xy, yaw, 0, 0, top - 0.02f), Eigen::Vector3f(depth / 2, length / 2, 0.02f), yaw, m) } };
  for (int i = 0; i < 4; ++i)
  {
    const float fw = (i & 1 ? 1 : -1) * (depth / 2 - 0.05f), lf = (i & 2 ? 1 : -1) * (length / 2 - 0.05f);
    o.boxes.push_back(box(at(xy, yaw, fw, lf, (top - 0.04f) / 2), Eigen::Vector3f(leg, leg, (top - 0.04f) / 2), yaw, m));
  }
  return o;
}

// An open bookshelf facing yaw: back panel, sides, top, plinth and boards (its compartments have depth).
ClutterObject shelf(const Eigen::Vector2f& xy, float yaw, float height, float width, Rng& r)
{
  const Material m = r.chance(0.5) ? wood(r) : plain(Rgb(0.85f, 0.85f, 0.82f), 0.04f, std::uint32_t(r.next()));
  const Material books = plain(Rgb(0.5f, 0.2f, 0.15f), 0.2f, std::uint32_t(r.next()), Pattern::VerticalStripes, 0.04f);
  const float depth = float(r.uniform(0.3, 0.4)), t = 0.02f;
  ClutterObject o{ "shelf", {} };
  o.boxes.push_back(box(at(xy, yaw, -depth / 2 + t / 2, 0, height / 2), Eigen::Vector3f(t / 2, width / 2, height / 2), yaw, m));
  for (const float s : { -1.0f, 1.0f })
    o.boxes.push_back(box(at(xy, yaw, 0, s * (width / 2 - t / 2), height / 2), Eigen::Vector3f(depth / 2, t / 2, height / 2), yaw, m));
  const int boards = std::max(2, int(height / 0.38f));
  for (int k = 0; k <= boards; ++k)
  {
    const float z = k == 0 ? 0.05f : std::min(height - t / 2, 0.05f + k * (height - 0.05f) / float(boards));
    const float half_z = k == 0 ? 0.05f : t / 2;
    o.boxes.push_back(box(at(xy, yaw, 0, 0, z), Eigen::Vector3f(depth / 2, width / 2 - t, half_z), yaw, m));
    // A row of books on every board but the top: shallower than the shelf, so the front is ragged.
    if (k < boards && r.chance(0.8))
    {
      const float book = float(r.uniform(0.18, 0.28)), fill = float(r.uniform(0.4, 0.95));
      const float lf = float(r.uniform(-0.5, 0.5)) * (1 - fill) * (width - 2 * t);
      o.boxes.push_back(box(at(xy, yaw, -depth / 2 + 0.02f + book / 2, lf, z + half_z + book * 0.6f),
                            Eigen::Vector3f(book / 2, fill * (width / 2 - t), book * 0.6f), yaw, books));
    }
  }
  return o;
}

ClutterObject cabinet(const Eigen::Vector2f& xy, float yaw, float height, Rng& r)
{
  const Material m = plain(Rgb(0.3f, 0.33f, 0.4f) * float(r.uniform(0.8, 1.6)), 0.05f, std::uint32_t(r.next()),
                           Pattern::HorizontalStripes, float(r.uniform(0.3, 0.45)));
  const Eigen::Vector3f half(float(r.uniform(0.2, 0.3)), float(r.uniform(0.3, 0.5)), height / 2);
  return { "cabinet", { box(at(xy, yaw, 0, 0, height / 2), half, yaw, m) } };
}

// A door in the back wall (x = wall) centred at lateral y, its frame flush with the wall and its
// leaf (0.85 x 2.0-2.1 m) swung open into the room by angle (0 = closed), hinged on the side s.
ClutterObject door(float wall, float y, float open, float s, Rng& r)
{
  const Material frame = plain(Rgb(0.92f, 0.92f, 0.9f), 0.03f, std::uint32_t(r.next()));
  const Material leaf = r.chance(0.5) ? wood(r) : plain(Rgb(0.75f, 0.75f, 0.72f), 0.04f, std::uint32_t(r.next()));
  const float h = float(r.uniform(2.0, 2.1)), w = 0.85f;
  ClutterObject o{ "door", {} };
  for (const float side : { -1.0f, 1.0f })  // the jambs, standing 2 cm out of the wall
    o.boxes.push_back(box(Eigen::Vector3f(wall - 0.02f, y + side * (w / 2 + 0.04f), (h + 0.05f) / 2),
                          Eigen::Vector3f(0.03f, 0.04f, (h + 0.05f) / 2), 0, frame));
  o.boxes.push_back(box(Eigen::Vector3f(wall - 0.02f, y, h + 0.05f), Eigen::Vector3f(0.03f, w / 2 + 0.08f, 0.04f), 0, frame));
  // The leaf: hinged at (wall, y + s w/2), turned into the room.
  const Eigen::Vector2f hinge(wall - 0.03f, y + s * w / 2);
  // Hinge to free edge: along the wall (0, -s) when closed, turned towards the camera (-x) when open.
  const Eigen::Vector2f dir = Eigen::Vector2f(-std::sin(open), -s * std::cos(open));
  const Eigen::Vector2f c = hinge + dir * (w / 2);
  // The box's own y axis (its width) along dir.
  o.boxes.push_back(box(Eigen::Vector3f(c.x(), c.y(), h / 2), Eigen::Vector3f(0.02f, w / 2, h / 2),
                        std::atan2(dir.y(), dir.x()) - kPi / 2, leaf));
  return o;
}

// Horizontal footprint radius of an object (its boxes' extent around their mean).
float footprint(const ClutterObject& o, Eigen::Vector2f& centre)
{
  centre = Eigen::Vector2f::Zero();
  for (const Box& b : o.boxes)
    centre += b.center.head<2>();
  centre /= float(o.boxes.size());
  float r = 0;
  for (const Box& b : o.boxes)
    r = std::max(r, (b.center.head<2>() - centre).norm() + b.half.head<2>().norm());
  return r;
}

Skeleton moved(const Skeleton& s, const Eigen::Isometry3f& t)
{
  Skeleton o;
  for (int k = 0; k < kJointCount; ++k)
    o.joints[k] = t * s.joints[k];
  return o;
}

struct Builder
{
  const SampleSpec& spec;
  Rng r;
  ClutterLayout out;
  Performance perf;
  int first = 0;  // first frame of the performance used
  Eigen::Vector2f person = Eigen::Vector2f::Zero(), radial = Eigen::Vector2f::UnitX(), lateral = Eigen::Vector2f::UnitY();

  Builder(const SampleSpec& s, const CameraModel& camera)
    : spec(s), r(hash64(s.seed, hashString("clutter/" + s.name()), 0xc1a7))
  {
    out.kind = s.scene;
    out.camera = camera;
  }

  void drawRoom()
  {
    const Room lab = Room::lab(std::uint32_t(r.next()));
    out.room.floor_material = lab.floor_material;
    out.room.wall_material = lab.wall_material;
    out.room.wall_material.base *= float(r.uniform(0.8, 1.1));
    out.room.ceiling_material = lab.ceiling_material;
    out.room.back_wall = float(r.uniform(3.8, 4.8));
    out.room.left_wall = float(r.uniform(1.8, 2.8));
    out.room.right_wall = -float(r.uniform(1.8, 2.8));
    out.room.ceiling = float(r.uniform(2.5, 2.9));
  }

  // The actor's performance and where it stands; the camera's pitch drawn so that it sees them as
  // the kind wants (whole, or cut by a side or the bottom of the image for "border").
  bool placePerson(float dist_lo, float dist_hi, float bearing_lo, float bearing_hi, bool cut)
  {
    const bool cut_bottom = cut && r.chance(0.4);
    for (int attempt = 0; attempt < 400; ++attempt)
    {
      out.camera.height_above_floor = r.uniform(cut_bottom ? 1.1 : 0.5, 1.8);
      out.camera.tilt = r.uniform(kTiltLow, kTiltHigh);
      const float d = cut_bottom ? float(r.uniform(1.2, 2.0)) : float(r.uniform(dist_lo, dist_hi));
      float b = float(r.uniform(bearing_lo, bearing_hi));
      if (cut && !cut_bottom)  // near a side edge of the view (the horizontal half-angle is 31 degrees)
        b = (r.chance(0.5) ? 1.0f : -1.0f) * float(r.uniform(0.50, 0.58));
      const float facing = float(r.uniform(-0.8, 0.8));
      Eigen::Isometry3f root = Eigen::Isometry3f::Identity();
      root.linear() = Eigen::AngleAxisf(b + kPi + facing, Eigen::Vector3f::UnitZ()).toRotationMatrix();
      root.translation() = Eigen::Vector3f(d * std::cos(b), d * std::sin(b), 0);
      std::vector<Skeleton> placed;
      for (int f = first; f < first + out.frames; ++f)
        placed.push_back(moved(perf.joints[size_t(f)], root));
      bool ok = true, cut_seen = false;
      for (size_t f = 0; f < placed.size() && ok; f += 3)
      {
        const JointsInView p = jointsInView(out.camera, placed[f], 4.0f);
        ok = cut ? p.head_inside && p.inside >= 8 : p.inside == kJointCount;
        cut_seen = cut_seen || p.inside < kJointCount;
      }
      if (!ok || (cut && !cut_seen))
        continue;
      out.joints = std::move(placed);
      out.forward.clear();
      for (int f = first; f < first + out.frames; ++f)
        out.forward.push_back(root.linear() * perf.forward[size_t(f)]);
      person = root.translation().head<2>();
      radial = person.normalized();
      lateral = Eigen::Vector2f(-radial.y(), radial.x());
      return true;
    }
    return false;
  }

  bool freeSpot(const ClutterObject& o, float keep_from_person) const
  {
    Eigen::Vector2f c;
    const float rad = footprint(o, c);
    if (c.x() + rad > out.room.back_wall || c.y() + rad > out.room.left_wall || c.y() - rad < out.room.right_wall ||
        c.norm() - rad < 0.9f)
      return false;
    if (out.person)
    {
      if ((c - person).norm() - rad < keep_from_person)
        return false;
      // Not between the camera and the person (that is what the kinds themselves do).
      const float along = c.dot(radial), across = std::abs(c.dot(lateral));
      if (keep_from_person > 0 && along < person.norm() && across < rad + 0.5f)
        return false;
    }
    for (const ClutterObject& other : out.objects)
    {
      Eigen::Vector2f oc;
      const float orad = footprint(other, oc);
      if ((oc - c).norm() < orad + rad)
        return false;
    }
    return true;
  }

  // A random piece of furniture somewhere in view, away from the person and the other pieces.
  void addBackgroundPiece()
  {
    for (int attempt = 0; attempt < 60; ++attempt)
    {
      const float d = float(r.uniform(1.4, 4.4)), b = float(r.uniform(-0.55, 0.55)), yaw = float(r.uniform(-kPi, kPi));
      const Eigen::Vector2f xy(d * std::cos(b), d * std::sin(b));
      ClutterObject o;
      switch (r.integer(0, 4))
      {
        case 0: o = chair(xy, yaw, r); break;
        case 1: o = table(xy, yaw, float(r.uniform(0.9, 1.5)), float(r.uniform(0.6, 0.8)), r); break;
        case 2: o = shelf(xy, yaw, float(r.uniform(1.4, 2.1)), float(r.uniform(0.6, 1.0)), r); break;
        case 3: o = cabinet(xy, yaw, float(r.uniform(0.7, 1.95)), r); break;
        default: o = chair(xy, yaw, r); break;
      }
      if (freeSpot(o, 1.0f))
      {
        out.objects.push_back(std::move(o));
        return;
      }
    }
  }

  // The kind's object next to the person: beside them (lateral offset) or in front (between the
  // camera and them), at a distance drawn from [lo, hi] m from the body's centre to the object's.
  Eigen::Vector2f nearPerson(bool in_front, float lo, float hi, float& yaw_to_camera)
  {
    const float gap = float(r.uniform(lo, hi));
    yaw_to_camera = std::atan2(-radial.y(), -radial.x());
    if (in_front)
      return person - radial * gap;
    return person + lateral * (r.chance(0.5) ? gap : -gap) + radial * float(r.uniform(-0.2, 0.3));
  }

  void addKindObject()
  {
    const std::string& k = out.kind;
    float toward = 0;
    const bool bending = spec.action == "pick_up" || spec.action == "kick";
    if (k == "wall")
    {
      const float gap = float(r.uniform(0.2, 1.0));
      if (r.chance(0.65))
        out.room.back_wall = person.x() + gap;
      else if (person.y() > 0)
        out.room.left_wall = person.y() + gap;
      else
        out.room.right_wall = person.y() - gap;
    }
    else if (k == "chair")
    {
      const bool front = !bending && r.chance(0.5);
      const Eigen::Vector2f c = nearPerson(front, front ? 0.45f : 0.5f, front ? 0.7f : 0.85f, toward);
      out.objects.push_back(chair(c, front ? toward + kPi + float(r.uniform(-0.6, 0.6)) : float(r.uniform(-kPi, kPi)), r));
      if (r.chance(0.4))
        out.objects.push_back(chair(nearPerson(false, 0.6f, 1.0f, toward), float(r.uniform(-kPi, kPi)), r));
    }
    else if (k == "table")
    {
      const bool front = !bending && r.chance(0.6);
      const float length = float(r.uniform(1.0, 1.6)), depth = float(r.uniform(0.6, 0.8));
      // In front: across the view (its length lateral); beside: along it (its depth lateral).
      const Eigen::Vector2f c = nearPerson(front, depth / 2 + (front ? 0.2f : 0.3f), depth / 2 + (front ? 0.45f : 0.55f), toward);
      out.objects.push_back(table(c, front ? toward : toward + kPi / 2, length, depth, r));
    }
    else if (k == "shelf")
    {
      const float width = float(r.uniform(0.7, 1.0));
      const Eigen::Vector2f c = nearPerson(false, width / 2 + 0.3f, width / 2 + 0.8f, toward);
      out.objects.push_back(shelf(c, toward + float(r.uniform(-0.5, 0.5)), float(r.uniform(1.5, 2.1)), width, r));
    }
    else if (k == "door")
    {
      out.room.back_wall = person.x() + float(r.uniform(0.3, 1.0));
      const float side = r.chance(0.5) ? 1.0f : -1.0f;
      // The door beside the person, its leaf swung open towards them or away.
      const float y = person.y() + side * float(r.uniform(0.7, 1.2));
      out.objects.push_back(door(out.room.back_wall, y, float(r.uniform(0.5, 1.4)), r.chance(0.5) ? side : -side, r));
    }
  }

  void build()
  {
    const auto& kinds = clutterKinds();
    if (std::find(kinds.begin(), kinds.end(), spec.scene) == kinds.end())
      throw std::invalid_argument("unknown clutter scene type '" + spec.scene + "'");
    if (spec.repetition < 1)
      throw std::invalid_argument("a clutter scene's number must be >= 1");
    drawRoom();
    out.person = spec.scene != "furniture";
    if (!out.person)
    {
      out.camera.height_above_floor = r.uniform(0.5, 1.8);
      out.camera.tilt = r.uniform(kTiltLow, kTiltHigh);
      out.frames = kFurnitureFrames;
      const int pieces = r.integer(3, 5);
      for (int k = 0; k < pieces; ++k)
        addBackgroundPiece();
      if (r.chance(0.5))
        out.objects.push_back(door(out.room.back_wall, float(r.uniform(-1.0, 1.0)), float(r.uniform(0.3, 1.4)),
                                   r.chance(0.5) ? 1.0f : -1.0f, r));
      finish();
      return;
    }
    const auto& spot = onTheSpot();
    if (spec.action != "pick_up" && std::find(spot.begin(), spot.end(), spec.action) == spot.end())
      throw std::invalid_argument("clutter: action '" + spec.action + "' is not one done on the spot");
    out.actor = makeActor(spec.person, spec.seed);
    perf = perform(out.actor, spec.action, hash64(spec.seed, hashString(spec.name()), 0x4e9), out.camera.fps);
    first = std::max(0, perf.core_first - 10);
    out.frames = std::min(kMaxPersonFrames, int(perf.joints.size()) - first);
    const bool border = spec.scene == "border";
    if (!placePerson(2.0f, 3.6f, -0.3f, 0.3f, border) && !placePerson(2.4f, 3.2f, -0.1f, 0.1f, border))
      throw std::runtime_error("clutter scene " + spec.name() + ": no camera pose shows the person");
    addKindObject();
    const int pieces = r.integer(1, 3);
    for (int k = 0; k < pieces; ++k)
      addBackgroundPiece();
    finish();
  }

  void finish()
  {
    for (const ClutterObject& o : out.objects)
      out.room.boxes.insert(out.room.boxes.end(), o.boxes.begin(), o.boxes.end());
  }
};

float segmentDistance(const Eigen::Vector3f& p, const Eigen::Vector3f& a, const Eigen::Vector3f& b)
{
  const Eigen::Vector3f ab = b - a;
  const float t = std::clamp((p - a).dot(ab) / std::max(1e-9f, ab.squaredNorm()), 0.0f, 1.0f);
  return (p - (a + t * ab)).norm();
}
}  // namespace

const std::vector<std::string>& clutterKinds()
{
  static const std::vector<std::string> k = { "wall", "chair", "table", "shelf", "door", "border", "furniture" };
  return k;
}

std::vector<SampleSpec> clutterSamples(int per_kind, std::uint64_t seed)
{
  if (per_kind < 1 || per_kind > 999)
    throw std::invalid_argument("clutterSamples: scenes per kind must be 1..999, got " + std::to_string(per_kind));
  std::vector<SampleSpec> out;
  int n = 0;
  for (const std::string& kind : clutterKinds())
    for (int k = 1; k <= per_kind; ++k, ++n)
    {
      SampleSpec s;
      s.dataset = "clutter";
      s.scene = kind;
      s.repetition = k;
      s.seed = seed;
      if (kind == "furniture")
        s.person = s.action = "none";
      else
      {
        char id[8];
        std::snprintf(id, sizeof id, "p%02d", n % 12 + 1);
        s.person = id;
        Rng r(hash64(seed, hashString(s.name()), 0xac7));
        s.action = r.chance(0.35) ? "pick_up" : onTheSpot()[size_t(r.integer(0, int(onTheSpot().size()) - 1))];
      }
      out.push_back(s);
    }
  return out;
}

ClutterLayout clutterLayout(const SampleSpec& spec, const CameraModel& camera)
{
  if (spec.dataset != "clutter")
    throw std::invalid_argument("clutterLayout: '" + spec.name() + "' is not a clutter scene");
  Builder b(spec, camera);
  b.build();
  return b.out;
}

std::string objectAt(const ClutterLayout& layout, int frame, const Eigen::Vector3f& p, float tolerance)
{
  if (layout.person && frame >= 0 && frame < int(layout.joints.size()))
  {
    const Skeleton& s = layout.joints[size_t(frame)];
    static const int bones[][2] = { { 0, 1 },  { 1, 2 },  { 1, 3 },  { 3, 4 },  { 4, 5 },   { 1, 6 },   { 6, 7 }, { 7, 8 },
                                    { 2, 9 },  { 9, 10 }, { 10, 11 }, { 2, 12 }, { 12, 13 }, { 13, 14 } };
    for (const auto& bone : bones)
      if (segmentDistance(p, s.joints[bone[0]], s.joints[bone[1]]) < 0.25f)
        return "person";
  }
  for (const ClutterObject& o : layout.objects)
    for (const Box& b : o.boxes)
    {
      const Eigen::Vector3f q =
          Eigen::AngleAxisf(-b.yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix() * (p - b.center);
      if ((q.cwiseAbs() - b.half).maxCoeff() < tolerance)
        return o.kind;
    }
  if (distanceToWall(layout.room, p) < tolerance)
    return "wall";
  if (layout.room.floor && p.z() < tolerance)
    return "floor";
  return "other";
}

JointsInView jointsInView(const CameraModel& cam, const Skeleton& world, float margin)
{
  const Eigen::Isometry3f to_opt = cam.worldFromOptical().inverse();
  JointsInView out;
  const auto inside = [&](const Eigen::Vector3f& w) {
    const Eigen::Vector3f p = to_opt * w;
    const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
    return p.z() > cam.min_depth && u >= margin && u <= cam.width - 1 - margin && v >= margin &&
           v <= cam.height - 1 - margin;
  };
  for (int k = 0; k < kJointCount; ++k)
    out.inside += inside(world.joints[k]);
  // The head joint is its centre: the top of the head (0.12 m above) too.
  const Eigen::Vector3f head = world[Joint::Head];
  out.head_inside = inside(head) && inside(head + Eigen::Vector3f(0, 0, 0.12f));
  return out;
}

float distanceToWall(const Room& room, const Eigen::Vector3f& p)
{
  if (!room.walls)
    return std::numeric_limits<float>::infinity();
  return std::min({ std::abs(room.back_wall - p.x()), std::abs(room.left_wall - p.y()), std::abs(p.y() - room.right_wall) });
}

}  // namespace synth
}  // namespace action_flow
