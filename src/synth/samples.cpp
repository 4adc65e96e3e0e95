// Actors, the sample lists of the datasets, and the per-sample renderer (placement of the actor in
// view, camera pose, room, streams' ground truth, MSR skeleton conversion and resampling, MSR
// streams and segments files).
#include <action_flow/synth/synth.h>
#include <action_flow/synth/clutter.h>

#include "motion.h"
#include "random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr double kStampBase = 1356998400.0;  // 2013-01-01 00:00:00 UTC
constexpr float kPi = 3.14159265358979f;

Rgb hsv(float h, float s, float v)
{
  h = h - std::floor(h);
  const float c = v * s, x = c * (1 - std::abs(std::fmod(h * 6, 2.0f) - 1)), m = v - c;
  Rgb r;
  switch (int(h * 6) % 6)
  {
    case 0: r = Rgb(c, x, 0); break;
    case 1: r = Rgb(x, c, 0); break;
    case 2: r = Rgb(0, c, x); break;
    case 3: r = Rgb(0, x, c); break;
    case 4: r = Rgb(x, 0, c); break;
    default: r = Rgb(c, 0, x); break;
  }
  return r + Rgb::Constant(m);
}

int idNumber(const std::string& id)
{
  static const std::regex re(R"([ps](\d{1,2}))");
  std::smatch m;
  if (!std::regex_match(id, m, re) || std::stoi(m[1]) < 1)
    throw std::invalid_argument("invalid person id '" + id + "' (expected p01..p99 or s01..s99)");
  return std::stoi(m[1]);
}

std::string twoDigits(const char* prefix, int n)
{
  char buf[16];
  std::snprintf(buf, sizeof buf, "%s%02d", prefix, n);
  return buf;
}

}  // namespace

const std::vector<std::string>& iasLabActions()
{
  static const std::vector<std::string> names = { "check_watch", "cross_arms",      "get_up",          "kick",
                                                  "pick_up",     "point",           "punch",           "scratch_head",
                                                  "sit_down",    "standing",        "throw_bottom_up", "throw_over_head",
                                                  "turn_around", "walk",            "wave" };
  return names;
}

std::string SampleSpec::name() const
{
  if (dataset == "msr")
  {
    const auto& acts = msrActions();
    const auto it = std::find(acts.begin(), acts.end(), action);
    const int a = it == acts.end() ? 0 : int(it - acts.begin()) + 1;
    const int s = person.size() > 1 ? std::atoi(person.c_str() + 1) : 0;
    char buf[32];
    std::snprintf(buf, sizeof buf, "a%02d_s%02d_e%02d", a, s, repetition);
    std::string n = buf;
    if (copy > 0)
    {
      n += "_c" + std::to_string(copy);
      if (copy_changes != kCopyAll)
      {
        n += "_";
        const char letters[] = "bptd";
        for (int b = 0; b < 4; ++b)
          if (copy_changes & (1u << b))
            n += letters[b];
      }
    }
    return n;
  }
  if (dataset == "stream")
    return person + "_stream_" + std::to_string(repetition);
  if (dataset == "crowd")
    return "crowd" + std::to_string(crowd_people) + "_" + std::to_string(repetition);
  if (dataset == "msr_stream")
  {
    if (segments_file.empty())
      return person + "_msr_stream_" + std::to_string(repetition);
    std::string stem = std::filesystem::path(skeleton_file).stem().string();
    for (char& c : stem)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-')
        c = '_';
    return stem;
  }
  if (dataset == "clutter")
  {
    char buf[32];
    std::snprintf(buf, sizeof buf, "_%02d", repetition);
    return scene + buf;
  }
  std::string n = person + "_" + action + "_" + std::to_string(repetition);
  if (dataset == "ias" && (facing != 0.0 || facing_spread != 30.0))
  {
    char buf[48];
    std::snprintf(buf, sizeof buf, "_f%gs%g", facing, facing_spread);
    n += buf;
  }
  return n;
}

std::vector<SampleSpec> iasLabSamples(int people, int repetitions, std::uint64_t seed)
{
  if (people < 1 || people > 99)
    throw std::invalid_argument("iasLabSamples: people must be 1..99, got " + std::to_string(people));
  if (repetitions < 1 || repetitions > 99)
    throw std::invalid_argument("iasLabSamples: repetitions must be 1..99, got " + std::to_string(repetitions));
  std::vector<SampleSpec> out;
  for (int p = 1; p <= people; ++p)
    for (const std::string& a : iasLabActions())
      for (int r = 1; r <= repetitions; ++r)
      {
        SampleSpec s;
        s.dataset = "ias";
        s.person = twoDigits("p", p);
        s.action = a;
        s.repetition = r;
        s.seed = seed;
        out.push_back(s);
      }
  return out;
}

std::vector<SampleSpec> msrSamples(const std::string& folder, std::uint64_t seed, bool cvpr12_only)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw std::runtime_error(folder + ": not a readable folder");
  std::set<std::string> used;
  const fs::path list = fs::path(folder) / "files_used_in_cvpr12_paper.txt";
  if (cvpr12_only && fs::exists(list))
  {
    std::ifstream in(list);
    std::string line;
    while (std::getline(in, line))
    {
      while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
        line.pop_back();
      if (!line.empty())
        used.insert(line);
    }
  }
  static const std::regex re(R"(a(\d\d)_s(\d\d)_e(\d\d)_skeleton3D\.txt)");
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder, ec))
    files.push_back(entry.path().filename().string());
  std::sort(files.begin(), files.end());
  std::vector<SampleSpec> out;
  for (const std::string& f : files)
  {
    std::smatch m;
    if (!std::regex_match(f, m, re))
      continue;
    if (!used.empty() && !used.count(f.substr(0, 11)))
      continue;
    const int a = std::stoi(m[1]);
    if (a < 1 || a > int(msrActions().size()))
      continue;
    SampleSpec s;
    s.dataset = "msr";
    s.person = "s" + std::string(m[2]);
    s.action = msrActions()[a - 1];
    s.repetition = std::stoi(m[3]);
    s.seed = seed;
    s.skeleton_file = (fs::path(folder) / f).string();
    out.push_back(s);
  }
  if (out.empty())
    throw std::runtime_error(folder + ": no aAA_sSS_eEE_skeleton3D.txt file");
  return out;
}

Actor makeActor(const std::string& id, std::uint64_t seed)
{
  const int n = idNumber(id);
  Rng r(hash64(seed, hashString(id), 0xac70));
  Actor a;
  a.id = id;
  // Heights spread over 1.55-1.95 m by the golden ratio, so that any number of people covers the range.
  const double spread = std::fmod((n - 1) * 0.6180339887 + std::fmod(double(seed % 1000) * 0.1, 1.0), 1.0);
  a.shape.height = float(1.55 + 0.4 * std::clamp(spread + r.uniform(-0.03, 0.03), 0.0, 1.0));
  a.shape.build = float(r.uniform(0.85, 1.25));
  a.left_handed = (n % 5) == 3;  // p03, p08, p13...: about one in five
  a.pace = float(r.uniform(0.8, 1.2));
  a.amplitude = float(r.uniform(0.85, 1.15));
  a.sway = float(r.uniform(0.5, 1.6));
  a.style_seed = r.next();

  Appearance& l = a.appearance;
  static const Rgb skins[] = { Rgb(0.96f, 0.80f, 0.69f), Rgb(0.90f, 0.72f, 0.58f), Rgb(0.78f, 0.57f, 0.42f),
                               Rgb(0.55f, 0.38f, 0.26f), Rgb(0.36f, 0.24f, 0.16f), Rgb(0.93f, 0.76f, 0.62f) };
  static const Rgb hairs[] = { Rgb(0.08f, 0.06f, 0.05f), Rgb(0.25f, 0.15f, 0.08f), Rgb(0.45f, 0.3f, 0.15f),
                               Rgb(0.8f, 0.65f, 0.35f),  Rgb(0.6f, 0.6f, 0.6f),    Rgb(0.55f, 0.22f, 0.08f) };
  l.skin.base = skins[r.integer(0, 5)];
  l.skin.grain = 0.04f;
  l.skin.seed = std::uint32_t(r.next());
  l.hair.base = hairs[r.integer(0, 5)];
  l.hair.second = l.hair.base * 0.6f;
  l.hair.pattern = Pattern::Print;
  l.hair.period = 0.015f;
  l.hair.grain = 0.25f;
  l.hair.seed = std::uint32_t(r.next());
  l.long_hair = r.chance(0.3);
  l.long_sleeves = r.chance(0.6);

  const float hue = float(r.uniform(0, 1));
  l.shirt.base = hsv(hue, float(r.uniform(0.3, 0.9)), float(r.uniform(0.35, 0.95)));
  l.shirt.second = r.chance(0.5) ? hsv(hue + float(r.uniform(0.3, 0.7)), float(r.uniform(0.2, 0.9)), float(r.uniform(0.3, 1.0)))
                                 : Rgb(0.95f, 0.95f, 0.93f);
  static const Pattern shirt_patterns[] = { Pattern::Plain, Pattern::HorizontalStripes, Pattern::VerticalStripes,
                                            Pattern::Checks, Pattern::Print };
  l.shirt.pattern = shirt_patterns[(n - 1 + r.integer(0, 4)) % 5];
  l.shirt.period = float(r.uniform(0.025, 0.09));
  l.shirt.grain = float(r.uniform(0.05, 0.14));
  l.shirt.seed = std::uint32_t(r.next());

  if (r.chance(0.5))
  {
    l.trousers.base = hsv(0.6f + float(r.uniform(-0.03, 0.03)), float(r.uniform(0.45, 0.75)), float(r.uniform(0.3, 0.6)));
    l.trousers.second = Rgb(0.8f, 0.82f, 0.88f);
    l.trousers.pattern = Pattern::Denim;
  }
  else
  {
    static const Rgb plain[] = { Rgb(0.1f, 0.1f, 0.11f), Rgb(0.35f, 0.35f, 0.37f), Rgb(0.6f, 0.52f, 0.38f), Rgb(0.22f, 0.28f, 0.18f) };
    l.trousers.base = plain[r.integer(0, 3)];
    l.trousers.second = l.trousers.base * 0.7f;
    l.trousers.pattern = Pattern::Print;
    l.trousers.period = 0.2f;
  }
  l.trousers.grain = 0.12f;
  l.trousers.seed = std::uint32_t(r.next());
  l.shoes.base = r.chance(0.3) ? Rgb(0.9f, 0.9f, 0.9f) : Rgb(0.12f, 0.1f, 0.09f);
  l.shoes.grain = 0.1f;
  l.shoes.seed = std::uint32_t(r.next());
  return a;
}

struct SampleRenderer::Impl
{
  SampleSpec spec;
  CameraModel camera;
  Actor actor;
  std::vector<Skeleton> world;
  std::vector<Eigen::Vector3f> forward;
  std::unique_ptr<SceneRenderer> scene;
  std::uint64_t noise_seed = 0;
  int frames = 0;
  std::string label;
  std::vector<StreamSegment> segments;
  int bodies = 1;

  void buildIas();
  void buildClutter();
  void buildStream();
  void buildMsr();
  void buildMsrCopy();
  void buildMsrStream();
  void drawCamera(Rng& r);
  bool visible(const std::vector<Skeleton>& joints, int step) const;
};

namespace
{
float jointRadius(int k, float sc)
{
  switch (Joint(k))
  {
    case Joint::Head: return 0.14f * sc;
    case Joint::LeftHand:
    case Joint::RightHand: return 0.09f * sc;
    case Joint::LeftFoot:
    case Joint::RightFoot: return 0.12f * sc;
    default: return 0.12f * sc;
  }
}

Skeleton transformed(const Skeleton& s, const Eigen::Isometry3f& t)
{
  Skeleton o;
  for (int k = 0; k < kJointCount; ++k)
    o.joints[k] = t * s.joints[k];
  return o;
}

Material chairWood(std::uint64_t seed)
{
  Material wood;
  wood.base = Rgb(0.45f, 0.28f, 0.15f);
  wood.grain = 0.1f;
  wood.seed = std::uint32_t(seed + 9);
  return wood;
}

// The chair by the right wall, where it stands when nobody sits on it.
void addSpareChair(Room& room, std::uint64_t seed)
{
  for (const Box& b : Room::chair(3.6f, 1.75f, -2.2f, 0.46f, chairWood(seed)))
    room.boxes.push_back(b);
}
}  // namespace

void SampleRenderer::Impl::drawCamera(Rng& r)
{
  camera.height_above_floor = 1.1 + r.uniform(-0.04, 0.04);
  camera.tilt = 0.08 + r.uniform(-0.03, 0.03);
}

bool SampleRenderer::Impl::visible(const std::vector<Skeleton>& joints, int step) const
{
  const Eigen::Isometry3f to_opt = camera.worldFromOptical().inverse();
  const float sc = actor.shape.height / 1.75f, margin = 4.0f;
  for (size_t f = 0; f < joints.size(); f += size_t(step))
    for (int k = 0; k < kJointCount; ++k)
    {
      const Eigen::Vector3f p = to_opt * joints[f].joints[k];
      const float r = jointRadius(k, sc);
      if (p.z() - r < camera.min_depth + 0.3)
        return false;
      for (int corner = 0; corner < 4; ++corner)
      {
        const Eigen::Vector3f q = p + Eigen::Vector3f((corner & 1) ? r : -r, (corner & 2) ? r : -r, 0);
        const double u = camera.fx * q.x() / q.z() + camera.cx, v = camera.fy * q.y() / q.z() + camera.cy;
        // The feet may reach the bottom of the image only if the floor there is visible, which it is.
        if (u < margin || u > camera.width - 1 - margin || v < margin || v > camera.height - 1 - margin)
          return false;
      }
    }
  return true;
}

void SampleRenderer::Impl::buildIas()
{
  const auto& acts = iasLabActions();
  if (std::find(acts.begin(), acts.end(), spec.action) == acts.end())
    throw std::invalid_argument("unknown IAS-Lab action '" + spec.action + "'");
  if (spec.repetition < 1)
    throw std::invalid_argument("repetition must be >= 1");
  if (!(std::abs(spec.facing) <= 180.0) || !(spec.facing_spread >= 0.0 && spec.facing_spread <= 180.0))
    throw std::invalid_argument("facing must be in -180..180 degrees and facing_spread in 0..180");
  actor = makeActor(spec.person, spec.seed);
  SampleSpec base = spec;  // the performance does not depend on where the actor faces
  base.facing = 0.0;
  base.facing_spread = 30.0;
  const std::uint64_t rep_seed = hash64(spec.seed, hashString(base.name()), 0x4e9);
  Rng r(hash64(rep_seed, 0x91ace));
  drawCamera(r);
  const Performance perf = perform(actor, spec.action, rep_seed, camera.fps);

  // Place the actor: 2.5-3.5 m away, facing the camera within +-30 degrees (walkers cross the
  // view) or as the spec says, whole body in view for the whole sample; redraw until it fits.
  const float side = spec.facing == 0.0 ? 0.0f : ((hashString(base.name()) & 1) ? 1.0f : -1.0f);
  const float facing_centre = side * float(spec.facing) * kPi / 180.0f;
  const float spread = float(spec.facing_spread / 30.0);  // 1: the default draw, +-0.52 rad
  Eigen::Isometry3f root = Eigen::Isometry3f::Identity();
  std::vector<Skeleton> placed(perf.joints.size());
  const auto place = [&](float dist, float bearing, float facing) {
    float yaw = bearing + kPi + facing;
    Eigen::Vector3f pos(dist * std::cos(bearing), dist * std::sin(bearing), 0);
    if (perf.walks)
    {
      yaw += (r.chance(0.5) ? 1.0f : -1.0f) * kPi / 2;
      const Eigen::Vector3f dir(std::cos(yaw), std::sin(yaw), 0);
      const float len = perf.joints.back()[Joint::Torso].x() - perf.joints.front()[Joint::Torso].x();
      pos -= dir * (0.5f * len);
    }
    root = Eigen::Isometry3f::Identity();
    root.linear() = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
    root.translation() = pos;
    for (size_t f = 0; f < perf.joints.size(); ++f)
      placed[f] = transformed(perf.joints[f], root);
  };
  bool ok = false;
  for (int attempt = 0; attempt < 40 && !ok; ++attempt)
  {
    const float dist = float(r.uniform(2.5, 3.5)), bearing = float(r.uniform(-0.22, 0.22));
    const float facing = facing_centre + float(r.uniform(-0.52, 0.52)) * spread * (perf.walks ? 0.6f : 1.0f);
    place(dist, bearing, facing);
    ok = visible(placed, 2);
  }
  for (float dist = 2.5f; !ok && dist <= 4.21f; dist += 0.1f)
  {
    place(dist, 0.0f, facing_centre);
    ok = visible(placed, 2);
  }
  if (!ok)
    place(3.5f, 0.0f, facing_centre);  // cannot fit every frame: keep the nominal distance
  world = placed;
  forward.resize(perf.forward.size());
  for (size_t f = 0; f < perf.forward.size(); ++f)
    forward[f] = root.linear() * perf.forward[f];

  Room room = Room::lab(std::uint32_t(spec.seed));
  if (perf.uses_chair)
  {
    const Eigen::Vector3f c = root * Eigen::Vector3f(perf.chair.x(), perf.chair.y(), 0);
    const float yaw = std::atan2(root.linear()(1, 0), root.linear()(0, 0));
    for (const Box& b : Room::chair(c.x(), c.y(), yaw, perf.chair.z(), chairWood(spec.seed)))
      room.boxes.push_back(b);
  }
  else
    addSpareChair(room, spec.seed);
  scene.reset(new SceneRenderer(camera, room));
  segments = { { spec.action, 0, int(world.size()) - 1 } };
}

void SampleRenderer::Impl::buildStream()
{
  const std::vector<std::string> actions = streamActions(spec);  // validates the spec
  actor = makeActor(spec.person, spec.seed);
  const std::uint64_t stream_seed = hash64(spec.seed, hashString(spec.name()), 0x4e9);
  Rng r(hash64(stream_seed, 0x91ace));
  drawCamera(r);
  StreamMotion motion = composeStream(actor, actions, stream_seed, camera.fps);
  world = std::move(motion.joints);
  forward = std::move(motion.forward);
  segments = std::move(motion.segments);
  label = "stream";

  // Every chair sat on stands in the room from the start (behind the actor while they do other
  // things there).
  Room room = Room::lab(std::uint32_t(spec.seed));
  for (const Eigen::Vector4f& c : motion.chairs)
    for (const Box& b : Room::chair(c.x(), c.y(), c.w(), c.z(), chairWood(spec.seed)))
      room.boxes.push_back(b);
  if (motion.chairs.empty())
    addSpareChair(room, spec.seed);
  scene.reset(new SceneRenderer(camera, room));
}

namespace
{
// The file's skeletons in the MSR camera's frame; untracked frames interpolated between the
// nearest tracked ones, held at the ends. @p tracked receives the tracked frames' indices.
std::vector<Skeleton> msrCameraSkeletons(const MsrSkeletonFile& file, std::vector<int>& tracked)
{
  const int n = int(file.frames.size());
  std::vector<Skeleton> cam(n);
  for (int f = 0; f < n; ++f)
    if (file.tracked[f])
      cam[f] = msrToOpenNi(file.frames[f]);
  for (int f = 0; f < n; ++f)
    if (file.tracked[f])
      tracked.push_back(f);
  for (int f = 0; f < n; ++f)
  {
    if (file.tracked[f])
      continue;
    const auto hi = std::upper_bound(tracked.begin(), tracked.end(), f);
    if (hi == tracked.begin())
      cam[f] = cam[*hi];
    else if (hi == tracked.end())
      cam[f] = cam[tracked.back()];
    else
    {
      const int a = *(hi - 1), b = *hi;
      const float t = float(f - a) / float(b - a);
      for (int k = 0; k < kJointCount; ++k)
        cam[f].joints[k] = cam[a].joints[k] + t * (cam[b].joints[k] - cam[a].joints[k]);
    }
  }
  return cam;
}

// The rotation that undoes the recording camera's pitch: people start upright, so the mean
// trunk of the first tracked frames gives "up".
Eigen::Matrix3f msrLevelling(const std::vector<Skeleton>& cam, const std::vector<int>& tracked)
{
  Eigen::Vector3f up = Eigen::Vector3f::Zero();
  for (size_t k = 0; k < std::min<size_t>(5, tracked.size()); ++k)
  {
    const Skeleton& s = cam[tracked[k]];
    up += (s[Joint::Neck] - 0.5f * (s[Joint::LeftHip] + s[Joint::RightHip])).normalized();
  }
  up.x() = 0;
  Eigen::Matrix3f level = Eigen::Matrix3f::Identity();
  if (up.norm() > 1e-3f)
    level = Eigen::Quaternionf::FromTwoVectors(up.normalized(), Eigen::Vector3f::UnitY())
                .toRotationMatrix();
  return level;
}

// Levelled camera skeletons in our world, the feet on the floor; @p height receives the body's
// height estimated from them.
std::vector<Skeleton> msrWorldOnFloor(const std::vector<Skeleton>& cam,
                                      const Eigen::Matrix3f& level, float& height)
{
  // MSR camera (x right, y up, z away) to our world (x away, y left, z up).
  const int n = int(cam.size());
  std::vector<Skeleton> w(n);
  std::vector<float> foot_z, head_h;
  for (int f = 0; f < n; ++f)
  {
    for (int k = 0; k < kJointCount; ++k)
    {
      const Eigen::Vector3f p = level * cam[f].joints[k];
      w[f].joints[k] = Eigen::Vector3f(p.z(), -p.x(), p.y());
    }
    const float fz = std::min(w[f][Joint::LeftFoot].z(), w[f][Joint::RightFoot].z());
    foot_z.push_back(fz);
    head_h.push_back(w[f][Joint::Head].z() - fz);
  }
  std::vector<float> sorted = foot_z;
  std::sort(sorted.begin(), sorted.end());
  const float floor_z = sorted[sorted.size() / 20];
  std::sort(head_h.begin(), head_h.end());
  height = std::clamp(head_h[head_h.size() / 2] / 0.89f, 1.45f, 2.05f);
  const float ankle = 0.039f * height;
  for (auto& s : w)
    for (auto& p : s.joints)
      p.z() += ankle - floor_z;
  return w;
}

// @p w (15 fps) to the camera's rate, linearly, with each frame's facing.
void resampleMsr(const std::vector<Skeleton>& w, double fps, MsrMotion& out)
{
  const int n = int(w.size());
  const double ratio = 15.0 / fps;
  const int out_n = std::max(1, int(std::floor((n - 1) / ratio)) + 1);
  out.joints.resize(out_n);
  out.forward.resize(out_n);
  for (int i = 0; i < out_n; ++i)
  {
    const double src = i * ratio;
    const int a = std::min(n - 1, int(std::floor(src))), b = std::min(n - 1, a + 1);
    const float t = float(src - a);
    for (int k = 0; k < kJointCount; ++k)
      out.joints[i].joints[k] = w[a].joints[k] + t * (w[b].joints[k] - w[a].joints[k]);
    const Skeleton& s = out.joints[i];
    const Eigen::Vector3f left = (s[Joint::LeftShoulder] - s[Joint::RightShoulder]) +
                                 (s[Joint::LeftHip] - s[Joint::RightHip]);
    Eigen::Vector3f fwd = left.cross(Eigen::Vector3f::UnitZ());
    fwd.z() = 0;
    out.forward[i] =
        fwd.norm() > 1e-4f ? Eigen::Vector3f(fwd.normalized()) : Eigen::Vector3f(-1, 0, 0);
  }
}

}  // namespace

MsrMotion msrMotion(const MsrSkeletonFile& file, double fps)
{
  if (file.trackedFrames() == 0)
    throw std::runtime_error(file.path + ": no tracked frame (all joints zero)");
  std::vector<int> tracked;
  const std::vector<Skeleton> cam = msrCameraSkeletons(file, tracked);
  const Eigen::Matrix3f level = msrLevelling(cam, tracked);
  MsrMotion out;
  const std::vector<Skeleton> w = msrWorldOnFloor(cam, level, out.height);
  resampleMsr(w, fps, out);
  return out;
}

namespace
{
/**
 * The truth of a continuous MSR-format file: rows "action,first_frame,last_frame" in the file's
 * frames (0..source_frames-1), an optional header line; frames f become f / ratio at the camera's rate.
 */
std::vector<StreamSegment> readSegmentsFile(const std::string& path, int source_frames, double ratio)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path + ": cannot open");
  std::vector<StreamSegment> out;
  std::string line;
  int line_no = 0, previous_last = -1;
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + what);
  };
  const auto frame = [&](const std::string& field) {
    size_t pos = 0;
    int v = -1;
    try
    {
      v = std::stoi(field, &pos);
    }
    catch (const std::exception&)
    {
      pos = 0;
    }
    if (pos == 0 || pos != field.size())
      fail("expected a frame number, got '" + field + "'");
    return v;
  };
  while (std::getline(in, line))
  {
    ++line_no;
    while (!line.empty() && (line.back() == '\r' || line.back() == ' '))
      line.pop_back();
    if (line.empty() || (line_no == 1 && line == "action,first_frame,last_frame"))
      continue;
    std::vector<std::string> fields;
    std::istringstream ls(line);
    for (std::string f; std::getline(ls, f, ',');)
      fields.push_back(f);
    if (fields.size() != 3 || fields[0].empty())
      fail("expected 'action,first_frame,last_frame', got '" + line + "'");
    const int first = frame(fields[1]), last = frame(fields[2]);
    if (first < 0 || last < first || last >= source_frames)
      fail("frames " + fields[1] + ".." + fields[2] + " are not an interval of the skeleton file's 0.." +
           std::to_string(source_frames - 1));
    if (first <= previous_last)
      fail("segment " + fields[1] + ".." + fields[2] + " starts before the previous one ends");
    previous_last = last;
    out.push_back({ fields[0], int(std::lround(first / ratio)), int(std::lround(last / ratio)) });
  }
  return out;
}
}  // namespace

void SampleRenderer::Impl::buildMsr()
{
  if (spec.copy < 0 || spec.copy > 99)
    throw std::invalid_argument("a training copy's number must be 0..99, got " + std::to_string(spec.copy));
  if (spec.copy > 0 && (spec.copy_changes == 0 || spec.copy_changes > kCopyAll))
    throw std::invalid_argument("a training copy must make some of the changes 1..15, got " +
                                std::to_string(spec.copy_changes));
  if (spec.copy > 0)
  {
    buildMsrCopy();
    return;
  }
  MsrMotion motion = msrMotion(parseMsrSkeletonFile(spec.skeleton_file), camera.fps);
  actor = makeActor(spec.person, spec.seed);
  actor.shape.height = motion.height;
  world = std::move(motion.joints);
  forward = std::move(motion.forward);
  Room room = Room::lab(std::uint32_t(spec.seed));
  addSpareChair(room, spec.seed);
  scene.reset(new SceneRenderer(camera, room));
  segments = { { spec.action, 0, int(world.size()) - 1 } };
}

void SampleRenderer::Impl::buildMsrCopy()
{
  // Every draw is made whichever changes are, so that a change draws the same value without the others.
  SampleSpec all = spec;
  all.copy_changes = kCopyAll;
  Rng r(hash64(spec.seed, hashString(all.name()), 0xc0b1));
  const unsigned changes = spec.copy_changes;
  const double pace_drawn = r.uniform(0.8, 1.2);
  const double pace = (changes & kCopyPace) ? pace_drawn : 1.0;
  // Resampled for a camera pace times slower, played at the camera's rate: pace times as fast.
  MsrMotion motion = msrMotion(parseMsrSkeletonFile(spec.skeleton_file), camera.fps / pace);
  actor = makeActor(spec.person,
                    (changes & kCopyBody) ? hash64(spec.seed, std::uint64_t(spec.copy), 0xb0d1) : spec.seed);
  actor.shape.height = motion.height;
  // Turned about the vertical through the first frame's torso, then moved along its bearing.
  const Eigen::Vector3f centre(motion.joints.front()[Joint::Torso].x(), motion.joints.front()[Joint::Torso].y(), 0.0f);
  const double turn_drawn = r.uniform(-30.0, 30.0);
  const float turn = (changes & kCopyTurn) ? float(turn_drawn) * kPi / 180.0f : 0.0f;
  const Eigen::Vector3f bearing = centre.norm() > 1e-3f ? Eigen::Vector3f(centre.normalized()) : Eigen::Vector3f::UnitX();
  const auto place = [&](float distance) {
    Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
    t.translate(bearing * distance);
    t.rotate(Eigen::AngleAxisf(turn, Eigen::Vector3f::UnitZ()));
    t.translate(-centre);
    world.resize(motion.joints.size());
    for (size_t f = 0; f < motion.joints.size(); ++f)
      world[f] = transformed(motion.joints[f], t);
    forward.resize(motion.forward.size());
    for (size_t f = 0; f < motion.forward.size(); ++f)
      forward[f] = t.linear() * motion.forward[f];
  };
  const double distance_drawn = r.uniform(1.5, 4.5);
  float distance = (changes & kCopyDistance) ? float(distance_drawn) : centre.norm();
  place(distance);
  // Moved back to fit only where the copy is turned or moved anyway: otherwise it stays where it was recorded.
  while ((changes & (kCopyTurn | kCopyDistance)) && !visible(world, 2) && distance < 4.5f)
  {
    distance = std::min(4.5f, distance + 0.1f);
    place(distance);
  }
  Room room = Room::lab(std::uint32_t(spec.seed));
  addSpareChair(room, spec.seed);
  scene.reset(new SceneRenderer(camera, room));
  segments = { { spec.action, 0, int(world.size()) - 1 } };
}

void SampleRenderer::Impl::buildMsrStream()
{
  std::vector<float> heights;
  StreamMotion motion;
  if (spec.segments_file.empty())
  {
    std::vector<MsrMotion> sequences;
    std::vector<std::string> actions;
    for (const SampleSpec& s : msrStreamSequences(spec))  // validates the spec
    {
      sequences.push_back(msrMotion(parseMsrSkeletonFile(s.skeleton_file), camera.fps));
      actions.push_back(s.action);
      heights.push_back(sequences.back().height);
    }
    motion = composeMsrStream(sequences, actions, hash64(spec.seed, hashString(spec.name()), 0x4e9), camera.fps);
  }
  else
  {
    if (!spec.action.empty() && spec.action != "stream")
      throw std::invalid_argument("a stream's action must be 'stream', got '" + spec.action + "'");
    const MsrSkeletonFile file = parseMsrSkeletonFile(spec.skeleton_file);
    MsrMotion m = msrMotion(file, camera.fps);
    heights.push_back(m.height);
    motion.joints = std::move(m.joints);
    motion.forward = std::move(m.forward);
    motion.segments = readSegmentsFile(spec.segments_file, int(file.frames.size()), 15.0 / camera.fps);
  }
  // One body for the whole stream: the median of the recordings' height estimates.
  std::sort(heights.begin(), heights.end());
  actor = makeActor(spec.person.empty() ? "s01" : spec.person, spec.seed);
  actor.shape.height = heights[heights.size() / 2];
  world = std::move(motion.joints);
  forward = std::move(motion.forward);
  segments = std::move(motion.segments);
  label = "stream";
  Room room = Room::lab(std::uint32_t(spec.seed));
  addSpareChair(room, spec.seed);
  scene.reset(new SceneRenderer(camera, room));
}

void SampleRenderer::Impl::buildClutter()
{
  ClutterLayout layout = clutterLayout(spec, camera);
  camera = layout.camera;
  bodies = layout.person ? 1 : 0;
  if (layout.person)
  {
    actor = layout.actor;
    world = std::move(layout.joints);
    forward = std::move(layout.forward);
  }
  else
  {
    world.assign(size_t(layout.frames), Skeleton());
    forward.assign(size_t(layout.frames), Eigen::Vector3f::UnitX());
  }
  scene.reset(new SceneRenderer(camera, layout.room));
  segments = { { spec.action, 0, int(world.size()) - 1 } };
}

SampleRenderer::SampleRenderer(const SampleSpec& spec, const CameraModel& camera) : impl_(new Impl)
{
  impl_->spec = spec;
  impl_->camera = camera;
  impl_->label = spec.action;
  if (spec.copy != 0 && spec.dataset != "msr")
    throw std::invalid_argument("training copies are rendered of msr samples only, not of " + spec.dataset + " '" +
                                spec.name() + "'");
  if (spec.dataset == "ias")
    impl_->buildIas();
  else if (spec.dataset == "stream")
    impl_->buildStream();
  else if (spec.dataset == "msr")
  {
    if (spec.skeleton_file.empty())
      throw std::invalid_argument("msr sample '" + spec.name() + "' without a skeleton file");
    impl_->buildMsr();
  }
  else if (spec.dataset == "msr_stream")
  {
    if (spec.skeleton_file.empty())
      throw std::invalid_argument("msr_stream sample '" + spec.name() + "' without an MSR folder or skeleton file");
    impl_->buildMsrStream();
  }
  else if (spec.dataset == "clutter")
    impl_->buildClutter();
  else
    throw std::invalid_argument("unknown dataset '" + spec.dataset + "' (expected ias, stream, msr, msr_stream or clutter" +
                                (spec.dataset == "crowd" ? "; a crowd scene is rendered by CrowdRenderer)" : ")"));
  impl_->noise_seed = hash64(spec.seed, hashString(spec.dataset + "/" + spec.name()), 0x4015e);
  impl_->frames = int(impl_->world.size());
  if (spec.max_frames > 0)
    impl_->frames = std::min(impl_->frames, spec.max_frames);
  // Ground truth of the frames kept: segments past the end dropped, the one cut clipped.
  auto& segs = impl_->segments;
  segs.erase(std::remove_if(segs.begin(), segs.end(), [&](const StreamSegment& s) { return s.first >= impl_->frames; }),
             segs.end());
  for (StreamSegment& s : segs)
    s.last = std::min(s.last, impl_->frames - 1);
}

SampleRenderer::~SampleRenderer() = default;

const SampleSpec& SampleRenderer::spec() const { return impl_->spec; }
const std::string& SampleRenderer::label() const { return impl_->label; }
int SampleRenderer::frames() const { return impl_->frames; }
int SampleRenderer::bodies() const { return impl_->bodies; }
const std::vector<StreamSegment>& SampleRenderer::segments() const { return impl_->segments; }

std::string SampleRenderer::actionAt(int i) const
{
  if (i < 0 || i >= impl_->frames)
    throw std::out_of_range("frame " + std::to_string(i) + " outside [0, " + std::to_string(impl_->frames) + ")");
  const auto& segs = impl_->segments;
  // The first segment ending at or after i holds it if it starts at or before i.
  const auto it = std::lower_bound(segs.begin(), segs.end(), i, [](const StreamSegment& s, int f) { return s.last < f; });
  return it != segs.end() && it->first <= i ? it->action : std::string();
}
double SampleRenderer::stamp(int i) const { return kStampBase + i / impl_->camera.fps; }
const CameraModel& SampleRenderer::camera() const { return impl_->camera; }
const SceneRenderer& SampleRenderer::scene() const { return *impl_->scene; }

const Skeleton& SampleRenderer::worldSkeleton(int i) const
{
  if (i < 0 || i >= impl_->frames)
    throw std::out_of_range("frame " + std::to_string(i) + " outside [0, " + std::to_string(impl_->frames) + ")");
  return impl_->world[size_t(i)];
}

Skeleton SampleRenderer::skeleton(int i) const
{
  return transformed(worldSkeleton(i), impl_->camera.worldFromOptical().inverse());
}

PosedBody SampleRenderer::posedBody(int i, std::uint8_t id) const
{
  PosedBody body;
  body.shape = impl_->actor.shape;
  body.appearance = &impl_->actor.appearance;
  body.joints = worldSkeleton(i);
  body.forward = impl_->forward[size_t(i)];
  body.id = id;
  return body;
}

void SampleRenderer::renderImages(int i, FrameImages& out) const
{
  if (impl_->bodies == 0)
    impl_->scene->render({}, impl_->noise_seed, i, out);
  else
    impl_->scene->render({ posedBody(i, 1) }, impl_->noise_seed, i, out);
}

void SampleRenderer::render(int i, Cloud& out, std::vector<std::uint8_t>* mask) const
{
  thread_local FrameImages im;  // reused: see SceneRenderer::render
  renderImages(i, im);
  impl_->scene->toFrameCloud(im, stamp(i), i, out, mask);
}

}  // namespace synth
}  // namespace action_flow
