// Scenes of several people at once (dataset "crowd"): who is in the scene, each person's motion
// piece by piece (walking in, actions facing any way, walks across the view, walking out), kept
// apart from the people composed before them, and the truth of what the camera shows of each.
#include <action_flow/synth/crowd.h>

#include "motion.h"
#include "random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr double kStampBase = 1356998400.0;  // 2013-01-01 00:00:00 UTC, as SampleRenderer
constexpr int kMaxScene = 999;

// Where people stand and walk (world: floor below the camera, x away from it, y to its left).
constexpr double kNearest = 1.0, kFarthest = 5.0;  // distance of the spots from the camera (m)
constexpr float kSideMargin = 0.35f;   // spots stay this far inside the edge of the view (m)
constexpr float kOutside = 0.9f;       // walks in start (walks out end) this far outside the edge (m)
constexpr float kMinWalk = 1.2f;       // a walk across covers at least this (m)
constexpr float kClearance = 0.7f;     // people keep this far apart, pelvis to pelvis on the floor (m)
constexpr int kTries = 24;             // candidate places per piece
constexpr int kWaits = 4;              // waits for the way to clear before a walk goes anyway
constexpr float kStep = 0.4f;          // an action may be performed up to this far aside (m)
// What people do.
constexpr double kEnterLate = 0.3;     // chance that another person than the first walks in later
constexpr double kLatestEntry = 0.4;   // ... within this share of the scene
constexpr double kLeaveEarly = 0.25;   // chance that another person walks out before the end
constexpr double kEarliestExit = 0.55, kLatestExit = 0.85;  // ... within this share of the scene
constexpr double kWalkAfter = 0.6;     // chance of a walk across after an action
constexpr double kLeadMin = 0.5, kLeadMax = 1.5;    // idle before the first action of one already there (s)
constexpr double kPauseMin = 0.4, kPauseMax = 2.0;  // idle between pieces (s)
constexpr double kBlendMin = 0.4, kBlendMax = 0.8;  // one transition (s)
constexpr int kActionList = 60;                     // actions drawn per person (cycled if used up)
constexpr int kHeadWindow = 3;                      // pixels around the head's image point
constexpr float kHeadTop = 0.071f;  // top of the head above the head joint per metre of height (the renderer: 0.125 m at 1.75 m)
constexpr double kTopRows = 2.0;   // the top of the head this many rows inside the image (the tracker's border rule)

Eigen::Vector2f pelvisOnFloor(const Skeleton& s)
{
  const Eigen::Vector3f p = 0.5f * (s[Joint::LeftHip] + s[Joint::RightHip]);
  return Eigen::Vector2f(p.x(), p.y());
}

Eigen::Isometry3f rootAt(const Eigen::Vector2f& place, float yaw)
{
  Eigen::Isometry3f root = Eigen::Isometry3f::Identity();
  root.linear() = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  root.translation() = Eigen::Vector3f(place.x(), place.y(), 0);
  return root;
}

/** Actions a person of a crowd performs in place: the person's stream actions (shuffle bags) without
 *  walks (the walks across are the crowd's own) and without sit_down / get_up (no chairs in a crowd). */
std::vector<std::string> placeActions(const std::string& actor, int scene, std::uint64_t seed)
{
  SampleSpec stream;
  stream.dataset = "stream";
  stream.person = actor;
  stream.action = "stream";
  stream.repetition = 1 + (scene - 1) % 99;
  stream.seed = seed;
  stream.stream_actions = kActionList;
  std::vector<std::string> out;
  for (const std::string& a : streamActions(stream))
    if (a != "walk" && a != "sit_down" && a != "get_up")
      out.push_back(a);
  return out;
}

/** A composed person: the motion from scene frame `first` on. */
struct Composed
{
  int first = 0;
  StreamMotion motion;
  bool present(int frame) const { return frame >= first && frame < first + int(motion.joints.size()); }
  Eigen::Vector2f floorAt(int frame) const { return pelvisOnFloor(motion.joints[size_t(frame - first)]); }
};

/** Builds one person's motion piece by piece, each piece placed where it keeps clear of `others`. */
class PersonComposer
{
public:
  PersonComposer(const Actor& actor, std::uint64_t seed, double fps, float view_slope, const std::vector<Composed>& others)
    : actor_(actor), seed_(seed), fps_(fps), slope_(view_slope), others_(others), r_(hash64(seed, 0xc70d))
  {
  }

  /** Starts at @p first: in view at a spot (idle), or walking in from outside the view. */
  void start(int first, bool walks_in)
  {
    out_.first = first;
    if (!walks_in)
    {
      place_ = spot();
      const float yaw = float(r_.uniform(0, 2 * kPi));
      const Performance idle = performIdle(actor_, nextSeed(), fps_, frames(kLeadMin, kLeadMax));
      placeBest([&](int) { return Candidate{ idle, rootAt(spot(), float(r_.uniform(0, 2 * kPi))) }; },
                Candidate{ idle, rootAt(place_, yaw) }, kTries);
      return;
    }
    // From outside the view on either side, to a spot in view.
    const std::uint64_t seed = nextSeed();
    walk([&](int) { return walkBetween(outside(r_.chance(0.5) ? 1.0f : -1.0f, float(r_.uniform(2.0, kFarthest - 0.5))),
                                       spot(), seed); });
  }

  /** Actions, pauses and walks across until the motion is @p length frames long. */
  void fill(int length, const std::vector<std::string>& actions)
  {
    for (size_t k = 0; int(out_.motion.joints.size()) < length; ++k)
    {
      act(actions[k % actions.size()]);
      pause();
      if (r_.chance(kWalkAfter))
        walkAcross();
    }
  }

  /** Walks out of the view: on the nearer side at about the same distance first, then anywhere. */
  void leave()
  {
    const Eigen::Vector2f from = place_;
    const std::uint64_t seed = nextSeed();
    walk([&](int t) {
      const float side = (t < 0 ? from.y() >= 0 : r_.chance(0.5)) ? 1.0f : -1.0f;
      const float depth = t < 0 ? from.x() : std::clamp(from.x() + float(r_.uniform(-1.5, 1.5)), 1.5f, float(kFarthest));
      return walkBetween(from, outside(side, depth), seed);
    });
  }

  Composed take() { return std::move(out_); }

private:
  struct Candidate
  {
    Performance perf;
    Eigen::Isometry3f root;
  };

  std::uint64_t nextSeed() { return hash64(seed_, ++pieces_, 0x9ece); }
  int frames(double lo, double hi) { return std::max(1, int(std::lround(r_.uniform(lo, hi) * fps_))); }

  /** The point @p depth away, kOutside beyond the edge of the view on the left (@p side 1) or right (-1). */
  Eigen::Vector2f outside(float side, float depth) const { return Eigen::Vector2f(depth, side * (depth * slope_ + kOutside)); }

  /** A place up to @p reach from @p p along each axis, kept kNearest..kFarthest from the camera and
   *  within the room's side walls (kOutside beyond the view's edge at kFarthest). */
  Eigen::Vector2f nearby(const Eigen::Vector2f& p, float reach)
  {
    const float side = float(kFarthest) * slope_ + kOutside;
    return Eigen::Vector2f(std::clamp(p.x() + float(r_.uniform(-reach, reach)), float(kNearest), float(kFarthest)),
                           std::clamp(p.y() + float(r_.uniform(-reach, reach)), -side, side));
  }

  /** A spot in view (at kNearest..kFarthest, kSideMargin inside the edge). */
  Eigen::Vector2f spot()
  {
    const float d = float(r_.uniform(kNearest, kFarthest));
    const float half = std::max(0.0f, d * slope_ - kSideMargin);
    return Eigen::Vector2f(d, float(r_.uniform(-half, half)));
  }

  /** The least distance to the others over the frames @p c would take after a transition of @p blend frames. */
  float clearance(const Candidate& c, int blend) const
  {
    float least = std::numeric_limits<float>::infinity();
    const int start = out_.first + int(out_.motion.joints.size());
    const auto check = [&](int frame, const Eigen::Vector2f& at) {
      for (const Composed& o : others_)
        if (o.present(frame))
          least = std::min(least, (o.floorAt(frame) - at).norm());
    };
    const auto placed = [&](size_t f) {
      const Eigen::Vector2f p = pelvisOnFloor(c.perf.joints[f]);
      return Eigen::Vector2f((c.root * Eigen::Vector3f(p.x(), p.y(), 0)).head<2>());
    };
    // The transition moves the pelvis from where the person stands to where the piece starts.
    for (int f = 0; f < blend; f += 2)
      check(start + f, place_ + (placed(0) - place_) * float(f + 1) / float(blend + 1));
    for (size_t f = 0; f < c.perf.joints.size(); f += 2)
      check(start + blend + int(f), placed(f));
    return least;
  }

  /** Where a piece went: the motion index of its frame 0, and its action's core there. */
  struct Placed
  {
    bool done = false;
    int start = 0, core_first = 0, core_last = 0;
  };

  /**
   * Appends, after a transition, @p first or else the first of @p tries candidates from @p draw that
   * keeps clear of the others (else the clearest; with @p must_clear, nothing).
   */
  template <typename Draw>
  Placed placeBest(Draw draw, Candidate first, int tries, bool must_clear = false)
  {
    const int blend = out_.motion.joints.empty() ? 0 : frames(kBlendMin, kBlendMax);
    Candidate best = std::move(first);
    float best_clear = clearance(best, blend);
    for (int t = 0; t < tries && best_clear < kClearance; ++t)
    {
      Candidate c = draw(t);
      const float clear = clearance(c, blend);
      if (clear > best_clear)
      {
        best_clear = clear;
        best = std::move(c);
      }
    }
    if (must_clear && best_clear < kClearance)
      return Placed{};
    if (blend > 0)
    {
      Skeleton to;
      for (int k = 0; k < kJointCount; ++k)
        to.joints[size_t(k)] = best.root * best.perf.joints.front().joints[size_t(k)];
      blendInto(out_.motion, to, best.root.linear() * best.perf.forward.front(), blend);
    }
    Placed placed;
    placed.done = true;
    placed.start = appendPlaced(out_.motion, best.perf.joints, best.perf.forward, best.root, 0,
                                int(best.perf.joints.size()));
    placed.core_first = placed.start + best.perf.core_first;
    placed.core_last = placed.start + best.perf.core_last;
    place_ = pelvisOnFloor(out_.motion.joints.back());
    return placed;
  }

  /**
   * Performs @p action where the person stands (or a step aside), facing any way; when that is
   * not clear of the others, walks across somewhere else first (@p may_move) and performs it there.
   */
  void act(const std::string& action, bool may_move = true)
  {
    const Performance perf = perform(actor_, action, nextSeed(), fps_);
    const Eigen::Vector2f here = place_;
    const auto aside = [&](int) { return Candidate{ perf, rootAt(nearby(here, kStep), float(r_.uniform(0, 2 * kPi))) }; };
    const Placed placed = placeBest(aside, Candidate{ perf, rootAt(here, float(r_.uniform(0, 2 * kPi))) }, kTries / 3,
                                    may_move);
    if (!placed.done)
    {
      walkAcross();
      act(action, false);
      return;
    }
    out_.motion.segments.push_back({ action, placed.core_first, placed.core_last });
  }

  /** Stands idle a moment, a step aside (up to @p reach) if someone comes close; with @p must_clear
   *  nothing when that is not clear. @return whether it was placed */
  bool idle(float reach, bool must_clear)
  {
    const Performance idle = performIdle(actor_, nextSeed(), fps_, frames(kPauseMin, kPauseMax));
    const float yaw = std::atan2(out_.motion.forward.back().y(), out_.motion.forward.back().x());
    const Eigen::Vector2f here = place_;
    const auto aside = [&](int) {
      return Candidate{ idle, rootAt(nearby(here, reach), yaw) };
    };
    return placeBest(aside, Candidate{ idle, rootAt(here, yaw) }, kTries, must_clear).done;
  }

  /** A pause between pieces; walks away when standing here is not clear. */
  void pause()
  {
    if (!idle(kStep, true))
      walkAcross();
  }

  /** Waits for the way to clear: the clearest of standing here and stepping up to a metre aside. */
  void waitAside() { idle(2.5f * kStep, false); }

  /** A walk from @p from to @p to (at least kMinWalk long), facing where it goes. */
  Candidate walkBetween(const Eigen::Vector2f& from, Eigen::Vector2f to, std::uint64_t seed) const
  {
    if ((to - from).norm() < kMinWalk)
      to = from + kMinWalk * ((to - from).norm() > 1e-3f ? Eigen::Vector2f((to - from).normalized())
                                                           : Eigen::Vector2f(0, from.y() > 0 ? -1.0f : 1.0f));
    const Eigen::Vector2f d = to - from;
    return Candidate{ performWalk(actor_, seed, fps_, d.norm()), rootAt(from, std::atan2(d.y(), d.x())) };
  }

  /**
   * The first walk from @p draw (called with -1, then 0, 1, ...) that keeps clear of the others; a
   * walk segment. When none does, the person waits a moment (walking in: enters later) and tries
   * again, up to kWaits times, then takes the clearest.
   */
  template <typename Draw>
  void walk(Draw draw)
  {
    Placed placed;
    for (int waited = 0; !placed.done; ++waited)
    {
      placed = placeBest(draw, draw(-1), kTries, waited < kWaits);
      if (placed.done)
        break;
      if (out_.motion.joints.empty())
        out_.first += frames(kPauseMin, kPauseMax);
      else
        waitAside();
    }
    out_.motion.segments.push_back({ "walk", placed.core_first, placed.core_last });
  }

  /** Walks across from where the person stands to a spot in view. */
  void walkAcross()
  {
    const Eigen::Vector2f from = place_;
    const std::uint64_t seed = nextSeed();
    walk([&](int) { return walkBetween(from, spot(), seed); });
  }

  const Actor& actor_;
  std::uint64_t seed_;
  double fps_;
  float slope_;
  const std::vector<Composed>& others_;
  Rng r_;
  Composed out_;
  Eigen::Vector2f place_ = Eigen::Vector2f(3, 0);
  std::uint64_t pieces_ = 0;
};

void validate(const SampleSpec& spec)
{
  if (spec.dataset != "crowd")
    throw std::invalid_argument("'" + spec.name() + "' is not a crowd scene (dataset '" + spec.dataset + "')");
  if (spec.crowd_people < 2 || spec.crowd_people > 5)
    throw std::invalid_argument("a crowd scene has 2..5 people, got " + std::to_string(spec.crowd_people));
  if (spec.repetition < 1 || spec.repetition > kMaxScene)
    throw std::invalid_argument("crowd scene number must be 1..999, got " + std::to_string(spec.repetition));
  if (!(spec.crowd_seconds >= 2.0 && spec.crowd_seconds <= 3600.0))
    throw std::invalid_argument("a crowd scene lasts 2..3600 s, got " + std::to_string(spec.crowd_seconds));
  if (spec.max_frames < 0)
    throw std::invalid_argument("max_frames must be >= 0");
}

/** The lab's materials in a room large enough for people at 5 m (its far walls beyond the depth range). */
Room crowdRoom(std::uint32_t seed)
{
  Room room = Room::lab(seed);
  room.boxes.clear();
  room.back_wall = 6.5f;
  room.left_wall = 4.2f;
  room.right_wall = -4.2f;
  room.ceiling = 3.0f;
  return room;
}
}  // namespace

std::vector<std::string> crowdActors(int people, int scene)
{
  std::vector<std::string> out;
  for (int k = 0; k < people; ++k)
  {
    char id[8];
    std::snprintf(id, sizeof id, "p%02d", 1 + ((scene - 1) * people + k) % 99);
    out.push_back(id);
  }
  return out;
}

std::vector<SampleSpec> crowdSamples(int people, int scenes, double seconds, std::uint64_t seed)
{
  if (scenes < 1 || scenes > kMaxScene)
    throw std::invalid_argument("crowdSamples: scenes must be 1..999, got " + std::to_string(scenes));
  std::vector<SampleSpec> out;
  for (int s = 1; s <= scenes; ++s)
  {
    SampleSpec c;
    c.dataset = "crowd";
    c.action = "crowd";
    c.repetition = s;
    c.seed = seed;
    c.crowd_people = people;
    c.crowd_seconds = seconds;
    for (const std::string& a : crowdActors(people, s))
      c.person += (c.person.empty() ? "" : "+") + a;
    validate(c);
    out.push_back(c);
  }
  return out;
}

CameraModel crowdCamera()
{
  CameraModel c;
  c.max_depth = 6.0;
  return c;
}

struct CrowdRenderer::Impl
{
  SampleSpec spec;
  CameraModel camera;
  std::vector<Actor> actors;
  std::vector<CrowdPerson> people;
  std::vector<Composed> motion;
  std::unique_ptr<SceneRenderer> scene;
  std::uint64_t noise_seed = 0;
  int frames = 0;
  float clearance = std::numeric_limits<float>::infinity();

  void compose();
  void measureClearance();
};

void CrowdRenderer::Impl::compose()
{
  const int total = int(std::lround(spec.crowd_seconds * camera.fps));
  const float slope = float(camera.cx / camera.fx);
  const std::uint64_t scene_seed = hash64(spec.seed, hashString(spec.name()), 0xc20d);
  Rng r(hash64(scene_seed, 0x5c3e));
  const std::vector<std::string> ids = crowdActors(spec.crowd_people, spec.repetition);
  for (size_t k = 0; k < ids.size(); ++k)
  {
    actors.push_back(makeActor(ids[k], spec.seed));
    CrowdPerson p;
    p.actor = ids[k];
    p.mask_id = std::uint8_t(k + 1);
    // Someone walks in later and someone walks out early in every scene; the others by chance.
    p.enters = k + 1 == ids.size() || (k > 0 && r.chance(kEnterLate));
    p.leaves = k == 0 || r.chance(kLeaveEarly);
    const int first = p.enters ? int(r.uniform(0, kLatestEntry) * total) : 0;
    const int exit = p.leaves ? int(r.uniform(kEarliestExit, kLatestExit) * total) : total;
    people.push_back(p);

    PersonComposer c(actors.back(), hash64(scene_seed, k, 0x9e7), camera.fps, slope, motion);
    c.start(first, p.enters);
    c.fill(exit - first, placeActions(ids[k], spec.repetition, spec.seed));
    if (p.leaves)
      c.leave();
    motion.push_back(c.take());
  }
  frames = spec.max_frames > 0 ? std::min(total, spec.max_frames) : total;
  for (size_t k = 0; k < people.size(); ++k)
  {
    // Nobody outlives the scene: cut at its end.
    Composed& m = motion[k];
    const int keep = std::clamp(frames - m.first, 0, int(m.motion.joints.size()));
    m.motion.joints.resize(size_t(keep));
    m.motion.forward.resize(size_t(keep));
    CrowdPerson& p = people[k];
    p.first_frame = m.first;
    p.last_frame = m.first + keep - 1;
    for (const StreamSegment& s : m.motion.segments)
      if (m.first + s.first <= p.last_frame)
        p.segments.push_back({ s.action, m.first + s.first, std::min(m.first + s.last, p.last_frame) });
  }
}

void CrowdRenderer::Impl::measureClearance()
{
  for (int f = 0; f < frames; ++f)
    for (size_t a = 0; a < motion.size(); ++a)
      for (size_t b = a + 1; b < motion.size(); ++b)
        if (motion[a].present(f) && motion[b].present(f))
          clearance = std::min(clearance, (motion[a].floorAt(f) - motion[b].floorAt(f)).norm());
}

CrowdRenderer::CrowdRenderer(const SampleSpec& spec, const CameraModel& camera) : impl_(new Impl)
{
  validate(spec);
  impl_->spec = spec;
  impl_->camera = camera;
  impl_->compose();
  impl_->measureClearance();
  impl_->scene.reset(new SceneRenderer(camera, crowdRoom(std::uint32_t(spec.seed))));
  impl_->noise_seed = hash64(spec.seed, hashString("crowd/" + spec.name()), 0x4015e);
}

CrowdRenderer::~CrowdRenderer() = default;

const SampleSpec& CrowdRenderer::spec() const { return impl_->spec; }
int CrowdRenderer::frames() const { return impl_->frames; }
double CrowdRenderer::stamp(int i) const { return kStampBase + i / impl_->camera.fps; }
const std::vector<CrowdPerson>& CrowdRenderer::people() const { return impl_->people; }
const CameraModel& CrowdRenderer::camera() const { return impl_->camera; }
const SceneRenderer& CrowdRenderer::scene() const { return *impl_->scene; }
float CrowdRenderer::leastClearance() const { return impl_->clearance; }

bool CrowdRenderer::present(std::size_t k, int i) const
{
  return k < impl_->motion.size() && i < impl_->frames && impl_->motion[k].present(i);
}

const Skeleton& CrowdRenderer::worldSkeleton(std::size_t k, int i) const
{
  if (!present(k, i))
    throw std::out_of_range("person " + std::to_string(k) + " is not in the scene at frame " + std::to_string(i));
  const Composed& m = impl_->motion[k];
  return m.motion.joints[size_t(i - m.first)];
}

Skeleton CrowdRenderer::skeleton(std::size_t k, int i) const
{
  const Eigen::Isometry3f to_optical = impl_->camera.worldFromOptical().inverse();
  const Skeleton& w = worldSkeleton(k, i);
  Skeleton s;
  for (int j = 0; j < kJointCount; ++j)
    s.joints[size_t(j)] = to_optical * w.joints[size_t(j)];
  return s;
}

std::vector<PosedBody> CrowdRenderer::bodies(int i) const
{
  std::vector<PosedBody> out;
  for (size_t k = 0; k < impl_->motion.size(); ++k)
    if (present(k, i))
    {
      const Composed& m = impl_->motion[k];
      PosedBody b;
      b.shape = impl_->actors[k].shape;
      b.appearance = &impl_->actors[k].appearance;
      b.joints = m.motion.joints[size_t(i - m.first)];
      b.forward = m.motion.forward[size_t(i - m.first)];
      b.id = impl_->people[k].mask_id;
      out.push_back(b);
    }
  return out;
}

void CrowdRenderer::renderImages(int i, FrameImages& out, std::uint8_t only) const
{
  if (i < 0 || i >= impl_->frames)
    throw std::out_of_range("frame " + std::to_string(i) + " outside [0, " + std::to_string(impl_->frames) + ")");
  if (only > impl_->people.size())
    throw std::invalid_argument("CrowdRenderer::renderImages: no person has mask id " + std::to_string(only) +
                                " (the scene has " + std::to_string(impl_->people.size()) + ")");
  std::vector<PosedBody> posed = bodies(i);
  if (only != 0)
    posed.erase(std::remove_if(posed.begin(), posed.end(), [&](const PosedBody& b) { return b.id != only; }),
                posed.end());
  impl_->scene->render(posed, impl_->noise_seed, i, out);
}

void CrowdRenderer::render(int i, Cloud& out, std::vector<std::uint8_t>* mask) const
{
  thread_local FrameImages im;  // reused: see SceneRenderer::render
  renderImages(i, im);
  impl_->scene->toFrameCloud(im, stamp(i), i, out, mask);
}

std::vector<CrowdTruth> CrowdRenderer::truth(int i, const FrameImages& images) const
{
  const CameraModel& cam = impl_->camera;
  if (images.width != cam.width || images.height != cam.height ||
      images.mask.size() != size_t(cam.width) * size_t(cam.height) || images.depth.size() != images.mask.size())
    throw std::invalid_argument("CrowdRenderer::truth: the images are not this camera's");
  std::array<int, 256> pixels{};
  for (size_t p = 0; p < images.mask.size(); ++p)
    if (images.mask[p] && std::isfinite(images.depth[p]))
      ++pixels[images.mask[p]];
  const Eigen::Isometry3f to_optical = cam.worldFromOptical().inverse();
  std::vector<CrowdTruth> out;
  for (size_t k = 0; k < impl_->motion.size(); ++k)
  {
    if (!present(k, i))
      continue;
    const Skeleton& s = worldSkeleton(k, i);
    const Eigen::Vector3f fwd = impl_->motion[k].motion.forward[size_t(i - impl_->motion[k].first)];
    CrowdTruth t;
    t.mask_id = impl_->people[k].mask_id;
    for (const Eigen::Vector3f& j : s.joints)
      t.position += j / float(kJointCount);
    t.yaw = std::atan2(fwd.y(), fwd.x());
    t.visible_pixels = pixels[t.mask_id];
    const float z = (to_optical * t.position).z();
    t.visible_area = z > 0 ? float(t.visible_pixels) * z * z / float(cam.fx * cam.fy) : 0.0f;
    const Eigen::Vector3f head = to_optical * s[Joint::Head];
    const Eigen::Vector3f top = to_optical * (s[Joint::Head] + Eigen::Vector3f(0, 0, kHeadTop * impl_->actors[k].shape.height));
    const bool top_in_view = top.z() > 0 && cam.fy * top.y() / top.z() + cam.cy >= kTopRows;
    if (top_in_view && head.z() >= cam.min_depth && head.z() <= cam.max_depth)
    {
      const int u = int(std::lround(cam.fx * head.x() / head.z() + cam.cx));
      const int v = int(std::lround(cam.fy * head.y() / head.z() + cam.cy));
      if (u >= 0 && u < cam.width && v >= 0 && v < cam.height)
        for (int dv = -kHeadWindow; dv <= kHeadWindow && !t.head_visible; ++dv)
          for (int du = -kHeadWindow; du <= kHeadWindow && !t.head_visible; ++du)
          {
            const int uu = u + du, vv = v + dv;
            t.head_visible = uu >= 0 && uu < cam.width && vv >= 0 && vv < cam.height &&
                             images.mask[size_t(vv) * size_t(cam.width) + size_t(uu)] == t.mask_id;
          }
    }
    t.counted = t.head_visible && t.visible_area >= kCrowdMinVisibleArea;
    out.push_back(t);
  }
  return out;
}

}  // namespace synth
}  // namespace action_flow
