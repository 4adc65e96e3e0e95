// Continuous streams of actions (dataset "stream"): which actions a stream performs (shuffle bags
// per person) and how their performances are joined into one motion: placement and heading in the
// room, transitions, idle periods, the seated pause between sit_down and get_up, the chairs. And
// streams of real motion (dataset "msr_stream"): which MSR Action3D sequences of a subject a stream
// performs, and how they are joined with the same transitions.
#include "motion.h"
#include "random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <map>
#include <regex>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr float kPi = 3.14159265358979f;
constexpr int kMaxCount = 99;  // person numbers, streams and actions per stream

// Where the actor is (world frame: floor below the camera, x away from it, y to its left).
constexpr double kNearest = 3.0, kFarthest = 3.6;  // distance from the camera (m)
constexpr double kStartSide = 1.0;                 // lateral offset of the start, either side (m)
constexpr double kStartJitter = 0.1;               // ... +- this (m)
constexpr float kMaxSide = 1.2f;                   // lateral limit of where a walk may end (m)
constexpr float kSideTolerance = 0.2f;             // a walk ending this close to kStartSide is taken at once
constexpr int kWalkTries = 8;                      // walk repetitions tried for one that fits
constexpr double kWalkSlant = 0.1;                 // walks turn toward the camera by up to this (rad)
constexpr double kMaxFacing = 0.52;                // facing off the camera (rad, 30 degrees)
constexpr double kRefacing = 0.3;                  // chance of a new facing in an idle period
// Durations (s).
constexpr double kLeadMin = 1.0, kLeadMax = 2.0;    // idle at the start and at the end
constexpr double kIdleMin = 0.5, kIdleMax = 3.0;    // idle between two actions
constexpr double kBlendMin = 0.4, kBlendMax = 0.8;  // one transition
constexpr double kStandingIdle = 0.6;               // chance that an idle period is a piece of "standing"
// Breathing while seated between sit_down and get_up.
constexpr float kBreathLift = 0.004f;                      // m
constexpr double kBreathMin = 3.0, kBreathMax = 4.5;       // period (s)

const std::string kPair = "sit_down";  // the bag item standing for sit_down followed by get_up

// One shuffle bag: every IAS-Lab action once, but standing (the idle periods) and get_up (in the pair).
std::vector<std::string> bagItems()
{
  std::vector<std::string> items;
  for (const std::string& a : iasLabActions())
    if (a != "standing" && a != "get_up")
      items.push_back(a);
  return items;
}

float ease(float x)
{
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}

Eigen::Matrix3f rotZ(float a) { return Eigen::AngleAxisf(a, Eigen::Vector3f::UnitZ()).toRotationMatrix(); }

Eigen::Vector3f pelvisOf(const Skeleton& s) { return 0.5f * (s[Joint::LeftHip] + s[Joint::RightHip]); }
Eigen::Vector3f flat(const Eigen::Vector3f& v) { return Eigen::Vector3f(v.x(), v.y(), 0); }
float headingOf(const Eigen::Vector3f& forward) { return std::atan2(forward.y(), forward.x()); }

Eigen::Isometry3f rootAt(const Eigen::Vector2f& place, float yaw)
{
  Eigen::Isometry3f root = Eigen::Isometry3f::Identity();
  root.linear() = rotZ(yaw);
  root.translation() = Eigen::Vector3f(place.x(), place.y(), 0);
  return root;
}

/** Shuffles @p v in place (Fisher-Yates). */
template <typename T>
void shuffle(std::vector<T>& v, Rng& rng)
{
  for (size_t i = v.size(); i > 1; --i)
    std::swap(v[i - 1], v[size_t(rng.integer(0, int(i - 1)))]);
}

Skeleton transformed(const Skeleton& s, const Eigen::Isometry3f& t)
{
  Skeleton o;
  for (int k = 0; k < kJointCount; ++k)
    o.joints[k] = t * s.joints[k];
  return o;
}

}  // namespace

int appendPlaced(StreamMotion& out, const std::vector<Skeleton>& joints, const std::vector<Eigen::Vector3f>& forward,
                 const Eigen::Isometry3f& root, int first, int count)
{
  const int start = int(out.joints.size()) - first;
  for (int i = first; i < first + count; ++i)
  {
    out.joints.push_back(transformed(joints[size_t(i)], root));
    out.forward.push_back(root.linear() * forward[size_t(i)]);
  }
  return start;
}

void blendInto(StreamMotion& out, const Skeleton& to, const Eigen::Vector3f& to_forward, int n)
{
  const Skeleton from = out.joints.back();
  const float heading = headingOf(out.forward.back());
  const float turn = std::remainder(headingOf(to_forward) - heading, 2 * kPi);
  const Eigen::Vector3f pa = flat(pelvisOf(from)), pb = flat(pelvisOf(to));
  const Eigen::Matrix3f ra = rotZ(-heading), rb = rotZ(-(heading + turn));
  Skeleton la, lb;
  for (int k = 0; k < kJointCount; ++k)
  {
    la.joints[k] = ra * (from.joints[k] - pa);
    lb.joints[k] = rb * (to.joints[k] - pb);
  }
  for (int i = 1; i <= n; ++i)
  {
    const float t = ease(float(i) / float(n + 1));
    const float h = heading + t * turn;
    const Eigen::Matrix3f rot = rotZ(h);
    const Eigen::Vector3f pelvis = pa + t * (pb - pa);
    Skeleton s;
    for (int k = 0; k < kJointCount; ++k)
      s.joints[k] = pelvis + rot * (la.joints[k] + t * (lb.joints[k] - la.joints[k]));
    out.joints.push_back(s);
    out.forward.push_back(Eigen::Vector3f(std::cos(h), std::sin(h), 0));
  }
}

namespace
{
/** Appends n frames of the last pose so far, breathing (the upper body lifts, @p period seconds). */
void holdBreathing(StreamMotion& out, int n, double period, double fps)
{
  const Skeleton base = out.joints.back();
  const Eigen::Vector3f forward = out.forward.back();
  for (int i = 1; i <= n; ++i)
  {
    const float lift = kBreathLift * 0.5f * float(1 - std::cos(2 * kPi * i / (fps * period)));
    Skeleton s = base;
    for (Joint j : { Joint::Head, Joint::Neck, Joint::LeftShoulder, Joint::RightShoulder })
      s[j].z() += lift;
    for (Joint j : { Joint::Torso, Joint::LeftElbow, Joint::RightElbow })
      s[j].z() += 0.5f * lift;
    out.joints.push_back(s);
    out.forward.push_back(forward);
  }
}

// Streams 1..@p streams of each of @p persons, of @p actions actions each, in @p dataset; @p caller
// names the function in the message when a count is out of range.
std::vector<SampleSpec> streamSpecs(const char* caller, const std::string& dataset,
                                    const std::vector<std::string>& persons, int streams, int actions,
                                    std::uint64_t seed)
{
  if (streams < 1 || streams > kMaxCount)
    throw std::invalid_argument(std::string(caller) + ": streams must be 1..99, got " + std::to_string(streams));
  if (actions < 1 || actions > kMaxCount)
    throw std::invalid_argument(std::string(caller) + ": actions must be 1..99, got " + std::to_string(actions));
  std::vector<SampleSpec> out;
  for (const std::string& person : persons)
    for (int k = 1; k <= streams; ++k)
    {
      SampleSpec s;
      s.dataset = dataset;
      s.person = person;
      s.action = "stream";
      s.repetition = k;
      s.seed = seed;
      s.stream_actions = actions;
      out.push_back(s);
    }
  return out;
}

// The stream number, its action count and its (empty or 'stream') action, as a stream's name gives
// them; @throws std::invalid_argument naming the one out of range.
void checkStreamNumbers(const SampleSpec& spec)
{
  if (spec.repetition < 1 || spec.repetition > kMaxCount)
    throw std::invalid_argument("stream number must be 1..99, got " + std::to_string(spec.repetition));
  if (spec.stream_actions < 1 || spec.stream_actions > kMaxCount)
    throw std::invalid_argument("stream_actions must be 1..99, got " + std::to_string(spec.stream_actions));
  if (!spec.action.empty() && spec.action != "stream")
    throw std::invalid_argument("a stream's action must be 'stream', got '" + spec.action + "'");
}

void validateStream(const SampleSpec& spec)
{
  if (spec.dataset != "stream")
    throw std::invalid_argument("'" + spec.name() + "' is not a stream (dataset '" + spec.dataset + "')");
  static const std::regex re(R"(p(\d{1,2}))");
  std::smatch m;
  if (!std::regex_match(spec.person, m, re) || std::stoi(m[1]) < 1)
    throw std::invalid_argument("invalid person id '" + spec.person + "' for a stream (expected p01..p99)");
  checkStreamNumbers(spec);
}

/** Builds the stream piece by piece: each piece is placed in the world and joined to the frames so far. */
class Composer
{
public:
  Composer(const Actor& actor, std::uint64_t seed, double fps)
    : actor_(actor), seed_(seed), fps_(fps), r_(hash64(seed, 0x57ea))
  {
    const double side = r_.chance(0.5) ? 1.0 : -1.0;
    place_ = Eigen::Vector2f(float(r_.uniform(kNearest, kFarthest)),
                             float(side * (kStartSide + r_.uniform(-kStartJitter, kStartJitter))));
    facing_ = float(r_.uniform(-kMaxFacing, kMaxFacing));
  }

  /** Standing idle for lo..hi seconds where the actor is, facing the camera (turning to it first). */
  void idle(double lo, double hi)
  {
    const int n = frames(lo, hi);
    const std::uint64_t seed = nextSeed();
    Rng choice(hash64(seed, 0x1d1e));
    if (choice.chance(kStandingIdle))
    {
      // A stretch of doing nothing in particular: weight shifts, looking around.
      const Performance standing = perform(actor_, "standing", seed, fps_);
      const int size = int(standing.joints.size());
      if (size >= n)
      {
        add(standing, rootAt(place_, towardCamera()), choice.integer(0, size - n), n);
        return;
      }
    }
    add(performIdle(actor_, seed, fps_, n), rootAt(place_, towardCamera()), 0, n);
  }

  /** Idle between two actions; sometimes the actor turns to another facing. */
  void pause()
  {
    if (r_.chance(kRefacing))
      facing_ = float(r_.uniform(-kMaxFacing, kMaxFacing));
    idle(kIdleMin, kIdleMax);
  }

  /** Stays seated (the last pose, breathing) for an idle period's time. */
  void seated()
  {
    const int n = frames(kIdleMin, kIdleMax);
    holdBreathing(out_, n, r_.uniform(kBreathMin, kBreathMax), fps_);
  }

  /** Performs @p action (repetition seed @p rep_seed) where the actor is; a segment of ground truth. */
  void act(const std::string& action, std::uint64_t rep_seed)
  {
    const bool rises = action == "get_up" && last_action_ == "sit_down";
    Performance perf;
    Eigen::Isometry3f root;
    Eigen::Vector2f end = place_;
    if (action == "walk")
      perf = walk(rep_seed, root, end);
    else
    {
      perf = perform(actor_, action, rep_seed, fps_);
      // Getting up from the chair sat down on, facing as when sitting down.
      root = rises ? sit_root_ : rootAt(place_, towardCamera());
    }
    const int start = add(perf, root, 0, int(perf.joints.size()));
    out_.segments.push_back({ action, start + perf.core_first, start + perf.core_last });
    if (perf.uses_chair && !rises)
    {
      // The chair stands where the performance expects it (behind the actor), from the start on.
      const Eigen::Vector3f seat = root * Eigen::Vector3f(perf.chair.x(), perf.chair.y(), 0);
      out_.chairs.emplace_back(seat.x(), seat.y(), perf.chair.z(), headingOf(root.linear().col(0)));
      sit_root_ = root;
    }
    if (action == "walk")
    {
      place_ = end;
      facing_ = float(r_.uniform(-kMaxFacing, kMaxFacing));
    }
    last_action_ = action;
  }

  StreamMotion take() { return std::move(out_); }

private:
  std::uint64_t nextSeed() { return hash64(seed_, ++pieces_, 0x9ece); }
  int frames(double lo, double hi) { return std::max(1, int(std::lround(r_.uniform(lo, hi) * fps_))); }
  float towardCamera() const { return std::atan2(-place_.y(), -place_.x()) + facing_; }

  /**
   * A walk across the view toward the side with more room, of the tried repetitions the first to
   * end near kStartSide off the centre (else the one ending nearest to it within kMaxSide). It may
   * slant toward the camera, never away, so that the chairs sat on stay behind the actor.
   */
  Performance walk(std::uint64_t rep_seed, Eigen::Isometry3f& root, Eigen::Vector2f& end)
  {
    const float dir = place_.y() > 0 ? -1.0f : 1.0f;
    const float slant = dir * float(r_.uniform(0.0, kWalkSlant));
    Performance best;
    float best_score = std::numeric_limits<float>::infinity();
    for (int k = 0; k < kWalkTries; ++k)
    {
      Performance perf = perform(actor_, "walk", hash64(rep_seed, std::uint64_t(k)), fps_);
      const float len = pelvisOf(perf.joints.back()).x() - pelvisOf(perf.joints.front()).x();
      float yaw = dir * kPi / 2 + slant;
      Eigen::Vector2f stop = place_ + len * Eigen::Vector2f(std::cos(yaw), std::sin(yaw));
      if (stop.x() < kNearest)
      {
        yaw = dir * kPi / 2;  // straight across, not nearer than kNearest
        stop = place_ + len * Eigen::Vector2f(std::cos(yaw), std::sin(yaw));
      }
      const float side = std::abs(stop.y());
      const float score = side > kMaxSide ? 10 + side : std::abs(side - float(kStartSide));
      if (score < best_score)
      {
        best_score = score;
        best = std::move(perf);
        root = rootAt(place_, yaw);
        end = stop;
      }
      if (score <= kSideTolerance)
        break;
    }
    return best;
  }

  /**
   * Appends frames [first, first + count) of @p perf placed by @p root, after a transition from the
   * last frame so far into the first of them; returns the stream index of frame 0 of @p perf.
   */
  int add(const Performance& perf, const Eigen::Isometry3f& root, int first, int count)
  {
    if (!out_.joints.empty())
      blendInto(out_, transformed(perf.joints[size_t(first)], root), root.linear() * perf.forward[size_t(first)],
                frames(kBlendMin, kBlendMax));
    return appendPlaced(out_, perf.joints, perf.forward, root, first, count);
  }

  const Actor& actor_;
  std::uint64_t seed_;
  double fps_;
  Rng r_;
  StreamMotion out_;
  Eigen::Vector2f place_;  // where the actor stands (floor)
  float facing_ = 0;       // heading off the direction to the camera (rad)
  std::uint64_t pieces_ = 0;
  std::string last_action_;
  Eigen::Isometry3f sit_root_ = Eigen::Isometry3f::Identity();
};

}  // namespace

std::vector<SampleSpec> streamSamples(int first_person, int people, int streams, int actions, std::uint64_t seed)
{
  if (people < 1 || people > kMaxCount)
    throw std::invalid_argument("streamSamples: people must be 1..99, got " + std::to_string(people));
  if (first_person < 1 || first_person + people - 1 > kMaxCount)
    throw std::invalid_argument("streamSamples: persons p" + std::to_string(first_person) + "..p" +
                                std::to_string(first_person + people - 1) + " outside p01..p99");
  std::vector<std::string> persons;
  for (int p = first_person; p < first_person + people; ++p)
  {
    char id[8];
    std::snprintf(id, sizeof id, "p%02d", p);
    persons.push_back(id);
  }
  return streamSpecs("streamSamples", "stream", persons, streams, actions, seed);
}

std::vector<std::string> streamActions(const SampleSpec& spec)
{
  validateStream(spec);
  // The person's streams take the items of one endless sequence of shuffle bags in turn. An item
  // is skipped (and stays first in line) where it would follow itself, or where the pair would
  // not fit into the stream.
  Rng rng(hash64(spec.seed, hashString(spec.person), 0x5b46));
  const std::vector<std::string> items = bagItems();
  std::deque<std::string> pending;
  std::string last;
  std::vector<std::string> out;
  for (int stream = 1; stream <= spec.repetition; ++stream)
  {
    out.clear();
    while (int(out.size()) < spec.stream_actions)
    {
      const bool pair_fits = spec.stream_actions - int(out.size()) >= 2;
      const auto allowed = [&](const std::string& a) { return a != last && (pair_fits || a != kPair); };
      auto it = std::find_if(pending.begin(), pending.end(), allowed);
      while (it == pending.end())
      {
        std::vector<std::string> bag = items;
        shuffle(bag, rng);
        pending.insert(pending.end(), bag.begin(), bag.end());
        it = std::find_if(pending.begin(), pending.end(), allowed);
      }
      last = *it;
      pending.erase(it);
      out.push_back(last);
      if (last == kPair)
        out.push_back("get_up");
    }
  }
  return out;
}

StreamMotion composeStream(const Actor& actor, const std::vector<std::string>& actions, std::uint64_t stream_seed,
                           double fps)
{
  Composer c(actor, stream_seed, fps);
  c.idle(kLeadMin, kLeadMax);
  for (size_t k = 0; k < actions.size(); ++k)
  {
    if (k > 0)
    {
      if (actions[k] == "get_up" && actions[k - 1] == "sit_down")
        c.seated();
      else
        c.pause();
    }
    c.act(actions[k], hash64(stream_seed, k, 0xac7));
  }
  c.idle(kLeadMin, kLeadMax);
  return c.take();
}

std::vector<SampleSpec> msrStreamSequences(const SampleSpec& spec)
{
  if (spec.dataset != "msr_stream" || !spec.segments_file.empty())
    throw std::invalid_argument("'" + spec.name() + "' is not an MSR stream dealt from a folder");
  static const std::regex re(R"(s\d\d)");
  if (!std::regex_match(spec.person, re))
    throw std::invalid_argument("invalid subject id '" + spec.person + "' for an MSR stream (expected s01..s99)");
  checkStreamNumbers(spec);
  const auto& names = msrActions();
  for (const std::string& a : spec.stream_pool)
    if (std::find(names.begin(), names.end(), a) == names.end())
      throw std::invalid_argument("unknown MSR action '" + a + "' in the stream's pool");

  // The subject's takes of each action (msrActions() order), then rounds of one take of every
  // action: takes and rounds shuffled, a round's first action swapped away from the last one's.
  std::map<int, std::vector<SampleSpec>> takes;
  for (const SampleSpec& s : msrSamples(spec.skeleton_file, spec.seed))
    if (s.person == spec.person &&
        (spec.stream_pool.empty() ||
         std::find(spec.stream_pool.begin(), spec.stream_pool.end(), s.action) != spec.stream_pool.end()))
      takes[int(std::find(names.begin(), names.end(), s.action) - names.begin())].push_back(s);
  Rng rng(hash64(spec.seed, hashString(spec.person), 0x35d1));
  size_t rounds = 0;
  for (auto& [action, list] : takes)
  {
    shuffle(list, rng);
    rounds = std::max(rounds, list.size());
  }
  std::vector<SampleSpec> order;
  for (size_t round = 0; round < rounds; ++round)
  {
    std::vector<const SampleSpec*> bag;
    for (const auto& [action, list] : takes)
      if (round < list.size())
        bag.push_back(&list[round]);
    shuffle(bag, rng);
    if (!order.empty() && bag.size() > 1 && bag.front()->action == order.back().action)
      std::swap(bag.front(), bag[size_t(rng.integer(1, int(bag.size()) - 1))]);
    for (const SampleSpec* s : bag)
      order.push_back(*s);
  }
  const size_t first = size_t(spec.repetition - 1) * size_t(spec.stream_actions);
  const size_t end = first + size_t(spec.stream_actions);
  if (end > order.size())
    throw std::invalid_argument("subject " + spec.person + " has " + std::to_string(order.size()) +
                                " sequences to deal; stream " + std::to_string(spec.repetition) + " of " +
                                std::to_string(spec.stream_actions) + " would need " + std::to_string(end));
  return std::vector<SampleSpec>(order.begin() + long(first), order.begin() + long(end));
}

std::vector<SampleSpec> msrStreamSamples(const std::string& folder, const std::vector<std::string>& subjects,
                                         int streams, int actions, std::uint64_t seed,
                                         const std::vector<std::string>& pool)
{
  std::vector<SampleSpec> out = streamSpecs("msrStreamSamples", "msr_stream", subjects, streams, actions, seed);
  for (SampleSpec& s : out)
  {
    s.skeleton_file = folder;
    s.stream_pool = pool;
  }
  // The last stream of each subject checks the spec and that there are sequences enough.
  for (size_t i = size_t(streams) - 1; i < out.size(); i += size_t(streams))
    msrStreamSequences(out[i]);
  return out;
}

StreamMotion composeMsrStream(const std::vector<MsrMotion>& sequences, const std::vector<std::string>& actions,
                              std::uint64_t stream_seed, double fps)
{
  if (sequences.empty() || sequences.size() != actions.size())
    throw std::invalid_argument("composeMsrStream: one action per sequence, at least one sequence");
  Rng r(hash64(stream_seed, 0x35ee));
  StreamMotion out;
  const auto frames = [&](double lo, double hi) { return std::max(1, int(std::lround(r.uniform(lo, hi) * fps))); };
  const auto hold = [&](int n) { holdBreathing(out, n, r.uniform(kBreathMin, kBreathMax), fps); };
  // The subject stays where the first sequence starts.
  const Eigen::Vector3f spot = flat(pelvisOf(sequences.front().joints.front()));
  for (size_t k = 0; k < sequences.size(); ++k)
  {
    const MsrMotion& m = sequences[k];
    Eigen::Isometry3f shift = Eigen::Isometry3f::Identity();
    shift.translation() = spot - flat(pelvisOf(m.joints.front()));
    if (k == 0)
    {
      appendPlaced(out, m.joints, m.forward, shift, 0, 1);
      hold(frames(kLeadMin, kLeadMax) - 1);
    }
    else
    {
      // An idle period: the end pose held, then a transition into the next first pose.
      const int gap = frames(kIdleMin, kIdleMax);
      const int blend = std::min(gap, frames(kBlendMin, kBlendMax));
      hold(gap - blend);
      blendInto(out, transformed(m.joints.front(), shift), m.forward.front(), blend);
    }
    const int n = int(m.joints.size());
    const int start = appendPlaced(out, m.joints, m.forward, shift, 0, n);
    out.segments.push_back({ actions[k], start, start + n - 1 });
  }
  hold(frames(kLeadMin, kLeadMax));
  return out;
}

}  // namespace synth
}  // namespace action_flow
