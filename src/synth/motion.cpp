// Procedural motion of the 15 IAS-Lab actions: an idle body (breathing, sway, weight shifts) plus
// each action's movements of trunk, arms and legs, posed by two-bone inverse kinematics. Person
// traits (pace, amplitude, handedness, and a per-person shape of each gesture) are drawn from the
// actor; each repetition jitters them a little and redraws timings and phases.
#include "motion.h"

#include "random.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
constexpr float kPi = 3.14159265358979f;

float clamp01(float x) { return std::clamp(x, 0.0f, 1.0f); }
float ease(float x)
{
  x = clamp01(x);
  return x * x * (3 - 2 * x);
}
// Rises over [a,b], holds, falls over [c,d].
float envelope(float u, float a, float b, float c, float d) { return ease((u - a) / (b - a)) * (1 - ease((u - c) / (d - c))); }
Eigen::Vector3f mix(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float t) { return a + (b - a) * t; }

Eigen::Matrix3f rotZ(float a) { return Eigen::AngleAxisf(a, Eigen::Vector3f::UnitZ()).toRotationMatrix(); }
Eigen::Matrix3f rotY(float a) { return Eigen::AngleAxisf(a, Eigen::Vector3f::UnitY()).toRotationMatrix(); }
Eigen::Matrix3f rotX(float a) { return Eigen::AngleAxisf(a, Eigen::Vector3f::UnitX()).toRotationMatrix(); }

/** Segment lengths from the body height (after anthropometric tables, e.g. Winter's). */
struct Dims
{
  explicit Dims(float h)
      : height(h), thigh(0.245f * h), shin(0.246f * h), ankle(0.039f * h), upper_arm(0.186f * h),
        forearm(0.19f * h), shoulder_half(0.118f * h), hip_half(0.052f * h), spine(0.285f * h), head(0.11f * h),
        pelvis_height(0.522f * h)
  {
  }
  float height, thigh, shin, ankle, upper_arm, forearm, shoulder_half, hip_half, spine, head, pelvis_height;
  float arm() const { return upper_arm + forearm; }
};

/** A pose in the actor's root frame. Side index 0 = left, 1 = right. */
struct Pose
{
  Eigen::Vector3f pelvis = Eigen::Vector3f::Zero();
  float yaw = 0, pitch = 0, roll = 0, twist = 0, head_pitch = 0, head_yaw = 0;
  Eigen::Vector3f hand[2];            // relative to the shoulder, trunk frame
  Eigen::Vector3f hand_world[2];      // root frame, used with weight hand_world_w
  float hand_world_w[2] = { 0, 0 };
  Eigen::Vector3f elbow_pole[2];      // trunk frame
  Eigen::Vector3f foot[2];            // ankle, root frame, before yaw of the body
  bool feet_in_body_frame = true;     // true: foot[] rotates with yaw about the pelvis
};

// Two-bone IK: elbow (knee) position for a chain from root to target with lengths a, b, bent toward pole.
Eigen::Vector3f solveIk(const Eigen::Vector3f& root, Eigen::Vector3f& target, float a, float b, const Eigen::Vector3f& pole)
{
  Eigen::Vector3f dv = target - root;
  float d = dv.norm();
  const float dmax = (a + b) * 0.999f, dmin = std::abs(a - b) + 1e-3f;
  Eigen::Vector3f n = d > 1e-6f ? Eigen::Vector3f(dv / d) : Eigen::Vector3f(0, 0, -1);
  d = std::clamp(d, dmin, dmax);
  target = root + n * d;
  const float cos_a = std::clamp((a * a + d * d - b * b) / (2 * a * d), -1.0f, 1.0f);
  Eigen::Vector3f m = pole - pole.dot(n) * n;
  if (m.squaredNorm() < 1e-8f)
    m = n.unitOrthogonal();
  m.normalize();
  return root + a * (cos_a * n + std::sqrt(1 - cos_a * cos_a) * m);
}

struct Posed
{
  Skeleton joints;
  Eigen::Vector3f forward;
};

Posed solvePose(const Dims& dm, const Pose& p)
{
  Posed out;
  Skeleton& s = out.joints;
  const Eigen::Matrix3f body = rotZ(p.yaw);
  const Eigen::Matrix3f trunk = body * rotZ(p.twist) * rotX(p.roll) * rotY(p.pitch);
  const Eigen::Matrix3f mid = body * rotZ(0.5f * p.twist) * rotX(0.5f * p.roll) * rotY(0.5f * p.pitch);
  const Eigen::Matrix3f head = trunk * rotZ(p.head_yaw) * rotY(p.head_pitch);
  s[Joint::Neck] = p.pelvis + mid * Eigen::Vector3f(0, 0, 0.5f * dm.spine) + trunk * Eigen::Vector3f(0, 0, 0.5f * dm.spine);
  s[Joint::Torso] = p.pelvis + mid * Eigen::Vector3f(0, 0, 0.45f * dm.spine);
  s[Joint::Head] = s[Joint::Neck] + head * Eigen::Vector3f(0.01f * dm.height, 0, dm.head);
  out.forward = body * Eigen::Vector3f::UnitX();
  for (int side = 0; side < 2; ++side)
  {
    const float out_sign = side == 0 ? 1.0f : -1.0f;  // +y is the person's left
    const LimbJoints limb = limbJoints(side);
    const Joint sh = limb.shoulder, el = limb.elbow, ha = limb.hand, hp = limb.hip, kn = limb.knee, ft = limb.foot;
    s[sh] = s[Joint::Neck] + trunk * Eigen::Vector3f(-0.01f * dm.height, out_sign * dm.shoulder_half, -0.015f * dm.height);
    Eigen::Vector3f hand = s[sh] + trunk * p.hand[side];
    hand = mix(hand, p.hand_world[side], p.hand_world_w[side]);
    s[el] = solveIk(s[sh], hand, dm.upper_arm, dm.forearm, trunk * p.elbow_pole[side]);
    s[ha] = hand;
    s[hp] = p.pelvis + body * Eigen::Vector3f(0, out_sign * dm.hip_half, 0);
    Eigen::Vector3f foot = p.feet_in_body_frame
                               ? Eigen::Vector3f(body * (p.foot[side] - Eigen::Vector3f(p.pelvis.x(), p.pelvis.y(), 0)) +
                                                 Eigen::Vector3f(p.pelvis.x(), p.pelvis.y(), 0))
                               : p.foot[side];
    const Eigen::Vector3f knee_pole = body * Eigen::Vector3f(1.0f, out_sign * 0.15f, 0.0f);
    s[kn] = solveIk(s[hp], foot, dm.thigh, dm.shin, knee_pole);
    s[ft] = foot;
  }
  return out;
}

/** Everything an action generator needs: the actor, the jittered traits of this repetition, timings. */
struct Context
{
  const Actor* actor = nullptr;
  Dims dm{ 1.75f };
  float sc = 1.0f;       // height / 1.75
  float pace = 1.0f, amp = 1.0f;
  int dom = 1;           // dominant side (1 = right)
  Rng* style = nullptr;  // per person and action: the same for every repetition
  Rng* rep = nullptr;    // per repetition
  float sway_phase[4] = { 0, 0, 0, 0 };
  float stance = 0.0f;   // extra half-width of the stance
  // A per-person value in [lo,hi], jittered by +-jitter of its range per repetition.
  float trait(float lo, float hi, float jitter = 0.1f)
  {
    const float v = float(style->uniform(lo, hi));
    return std::clamp(v + float(rep->uniform(-jitter, jitter)) * (hi - lo), lo - 0.1f * (hi - lo), hi + 0.1f * (hi - lo));
  }
  float sideSign(int side) const { return side == 0 ? 1.0f : -1.0f; }
};

Eigen::Vector3f neutralHand(const Context& c, int side)
{
  return Eigen::Vector3f(0.03f * c.sc, c.sideSign(side) * 0.05f * c.sc, -0.95f * c.dm.arm());
}
Eigen::Vector3f neutralPole(const Context& c, int side) { return Eigen::Vector3f(-1.0f, c.sideSign(side) * 0.4f, 0.0f); }

// The idle body at time t (s): standing, breathing, swaying a little.
Pose idlePose(const Context& c, double t)
{
  Pose p;
  const float sway = c.actor->sway;
  const float tt = float(t);
  p.pelvis = Eigen::Vector3f(0.008f * sway * std::sin(0.7f * tt + c.sway_phase[0]),
                             0.012f * sway * std::sin(0.45f * tt + c.sway_phase[1]),
                             c.dm.pelvis_height + 0.003f * std::sin(1.6f * tt + c.sway_phase[2]));
  p.pitch = 0.02f + 0.01f * sway * std::sin(0.5f * tt + c.sway_phase[3]);
  p.roll = 0.01f * sway * std::sin(0.45f * tt + c.sway_phase[1] + 1.0f);
  p.head_yaw = 0.05f * sway * std::sin(0.3f * tt + c.sway_phase[2]);
  p.head_pitch = 0.05f;
  for (int s = 0; s < 2; ++s)
  {
    p.hand[s] = neutralHand(c, s) + Eigen::Vector3f(0.01f * std::sin(1.6f * tt + s), 0, 0);
    p.elbow_pole[s] = neutralPole(c, s);
    p.hand_world[s] = Eigen::Vector3f::Zero();
    p.foot[s] = Eigen::Vector3f(0.0f, c.sideSign(s) * (c.dm.hip_half + c.stance), c.dm.ankle);
  }
  return p;
}

// Hand position on a sphere around the shoulder: elevation alpha from hanging (0) through forward
// (pi/2) to overhead (pi), azimuth beta outward, reach as a fraction of the arm.
Eigen::Vector3f armArc(const Context& c, int side, float alpha, float beta, float reach)
{
  const float r = reach * c.dm.arm();
  return Eigen::Vector3f(r * std::sin(alpha) * std::cos(beta), c.sideSign(side) * r * std::sin(alpha) * std::sin(beta) +
                                                                   c.sideSign(side) * 0.03f * c.sc,
                         -r * std::cos(alpha));
}

using Generator = std::function<void(Context&, Pose&, float u, float t_core)>;

struct ActionDef
{
  float duration;  // seconds of the action itself at pace 1
  Generator apply;
};

void seatedPose(const Context& c, Pose& p, float w, Eigen::Vector3f chair)
{
  // w = 0 standing, 1 seated on the chair whose seat centre (x,y) and height z are given.
  const Eigen::Vector3f seated(chair.x() + 0.04f * c.sc, chair.y(), chair.z() + 0.095f * c.sc);
  p.pelvis = mix(p.pelvis, seated, w);
  for (int s = 0; s < 2; ++s)
  {
    p.foot[s].x() += 0.06f * c.sc * w;
    p.hand[s] = mix(p.hand[s], Eigen::Vector3f(0.3f * c.sc, c.sideSign(s) * 0.02f * c.sc, -0.42f * c.sc), w);
  }
  p.pitch += 0.08f * w;
}

const std::map<std::string, ActionDef>& actionTable();

}  // namespace

namespace
{
const std::map<std::string, ActionDef>& actionTable()
{
  static const std::map<std::string, ActionDef> table = {
    { "check_watch",
      { 3.0f,
        [](Context& c, Pose& p, float u, float) {
          const int nd = 1 - c.dom;
          const float e = envelope(u, c.trait(0.05f, 0.15f), c.trait(0.25f, 0.38f), c.trait(0.65f, 0.78f), 0.95f);
          const Eigen::Vector3f watch(c.trait(0.22f, 0.32f) * c.sc, -c.sideSign(nd) * c.trait(0.08f, 0.16f) * c.sc,
                                      -c.trait(0.12f, 0.26f) * c.sc);
          p.hand[nd] = mix(p.hand[nd], watch, e);
          p.elbow_pole[nd] = mix(p.elbow_pole[nd], Eigen::Vector3f(-0.2f, c.sideSign(nd) * 1.0f, -0.6f), e);
          // Some people pull the sleeve back with the other hand first.
          const float pull = c.trait(0.0f, 1.0f) > 0.5f ? envelope(u, 0.15f, 0.3f, 0.4f, 0.55f) : 0.0f;
          p.hand[c.dom] = mix(p.hand[c.dom], Eigen::Vector3f(0.25f * c.sc, -c.sideSign(c.dom) * 0.16f * c.sc, -0.28f * c.sc), pull);
          p.head_pitch += e * c.amp * c.trait(0.3f, 0.5f);
          p.head_yaw += e * c.sideSign(nd) * 0.2f;
          p.pitch += 0.05f * e;
        } } },
    { "cross_arms",
      { 3.5f,
        [](Context& c, Pose& p, float u, float t) {
          const float e = envelope(u, c.trait(0.05f, 0.12f), c.trait(0.22f, 0.32f), c.trait(0.72f, 0.82f), 0.96f);
          const int top = c.dom;  // the dominant forearm lies on top
          for (int s = 0; s < 2; ++s)
          {
            const float up = s == top ? 0.05f : 0.0f;
            const Eigen::Vector3f across(c.trait(0.17f, 0.23f) * c.sc, -c.sideSign(s) * c.trait(0.22f, 0.28f) * c.sc,
                                         (-0.22f + up) * c.sc);
            p.hand[s] = mix(p.hand[s], across, e);
            p.elbow_pole[s] = mix(p.elbow_pole[s], Eigen::Vector3f(0.0f, c.sideSign(s) * 1.0f, -1.0f), e);
          }
          p.pitch -= 0.06f * e * c.amp;
          p.pelvis.z() += 0.004f * e * std::sin(2.0f * t);
        } } },
    { "get_up",
      { 2.6f,
        [](Context& c, Pose& p, float u, float) {
          const float lean = c.trait(0.45f, 0.7f) * c.amp;
          const float w = 1 - ease((u - 0.25f) / 0.5f);
          p.pitch += lean * envelope(u, 0.0f, 0.3f, 0.55f, 0.9f);
          seatedPose(c, p, w, Eigen::Vector3f(-0.3f * c.sc, 0, 0.46f));
          // Hands push on the thighs while rising.
          for (int s = 0; s < 2; ++s)
            p.hand[s] = mix(p.hand[s], Eigen::Vector3f(0.32f * c.sc, c.sideSign(s) * 0.0f, -0.4f * c.sc),
                            envelope(u, 0.0f, 0.2f, 0.5f, 0.7f));
        } } },
    { "kick",
      { 2.0f,
        [](Context& c, Pose& p, float u, float) {
          const int k = c.dom, st = 1 - c.dom;
          const float height = c.trait(0.3f, 0.55f) * c.amp * c.sc, reach = c.trait(0.45f, 0.6f) * c.sc;
          const float back = envelope(u, 0.1f, 0.32f, 0.32f, 0.45f), kick = envelope(u, 0.32f, 0.45f, 0.5f, 0.75f);
          p.foot[k] += Eigen::Vector3f(-0.25f * c.sc * back + reach * kick, 0, 0.12f * c.sc * back + height * kick);
          const float shift = envelope(u, 0.05f, 0.25f, 0.75f, 0.9f);
          p.pelvis.y() += c.sideSign(st) * 0.06f * c.sc * shift;
          p.pelvis.z() -= 0.03f * shift;
          p.pitch -= 0.2f * kick * c.amp;
          for (int s = 0; s < 2; ++s)
            p.hand[s] = mix(p.hand[s], armArc(c, s, 0.7f, 1.2f, 0.95f), shift * c.trait(0.5f, 1.0f));
        } } },
    { "pick_up",
      { 3.0f,
        [](Context& c, Pose& p, float u, float) {
          const float bend = envelope(u, 0.08f, 0.42f, 0.55f, 0.88f);
          const float squat = c.trait(0.0f, 1.0f);  // some bend the back, some the knees
          p.pitch += bend * (1.9f - 0.7f * squat);  // the lower spine bends half as much (solvePose)
          p.pelvis.z() -= bend * (0.25f + 0.2f * squat) * c.sc;
          p.pelvis.x() -= bend * (0.15f - 0.08f * squat) * c.sc;
          const Eigen::Vector3f object(c.trait(0.3f, 0.4f) * c.sc, -c.sideSign(c.dom) * 0.1f * c.sc, 0.09f);
          p.hand_world[c.dom] = object;
          p.hand_world_w[c.dom] = envelope(u, 0.15f, 0.45f, 0.55f, 0.8f);
          p.elbow_pole[c.dom] = Eigen::Vector3f(-0.5f, c.sideSign(c.dom), 0);
          const int nd = 1 - c.dom;
          p.hand[nd] = mix(p.hand[nd], Eigen::Vector3f(0.3f * c.sc, 0.0f, -0.45f * c.sc), bend);
          // Holding the object in front at the end.
          const float hold = envelope(u, 0.6f, 0.8f, 0.88f, 1.0f);
          p.hand[c.dom] = mix(p.hand[c.dom], Eigen::Vector3f(0.3f * c.sc, -c.sideSign(c.dom) * 0.1f * c.sc, -0.3f * c.sc), hold);
          p.head_pitch += 0.3f * bend;
        } } },
    { "point",
      { 3.0f,
        [](Context& c, Pose& p, float u, float) {
          const float e = envelope(u, c.trait(0.05f, 0.15f), c.trait(0.25f, 0.35f), c.trait(0.65f, 0.75f), 0.92f);
          const float beta = c.trait(-0.3f, 0.7f), elev = kPi / 2 + c.trait(-0.15f, 0.35f) * c.amp;
          p.hand[c.dom] = mix(p.hand[c.dom], armArc(c, c.dom, elev, beta, 0.98f), e);
          p.elbow_pole[c.dom] = mix(p.elbow_pole[c.dom], Eigen::Vector3f(0, c.sideSign(c.dom), -1), e);
          p.head_yaw += e * c.sideSign(c.dom) * 0.6f * beta;
          p.twist += e * c.sideSign(c.dom) * 0.1f;
        } } },
    { "punch",
      { 2.6f,
        [](Context& c, Pose& p, float u, float) {
          const float guard = envelope(u, 0.03f, 0.15f, 0.85f, 0.97f);
          const int punches = c.style->uniform(0, 1) < 0.5 ? 2 : 3;
          const bool alternate = c.trait(0.0f, 1.0f) > 0.4f;
          for (int s = 0; s < 2; ++s)
          {
            p.hand[s] = mix(p.hand[s], Eigen::Vector3f(0.2f * c.sc, -c.sideSign(s) * 0.1f * c.sc, -0.1f * c.sc), guard);
            p.elbow_pole[s] = mix(p.elbow_pole[s], Eigen::Vector3f(0, c.sideSign(s) * 0.5f, -1), guard);
          }
          for (int j = 0; j < punches; ++j)
          {
            const float start = 0.18f + 0.62f * j / punches;
            const float len = 0.62f / punches;
            const float ext = envelope(u, start, start + 0.25f * len, start + 0.4f * len, start + 0.85f * len);
            const int s = alternate && (j & 1) ? 1 - c.dom : c.dom;
            const Eigen::Vector3f target(0.97f * c.dm.arm(), -c.sideSign(s) * 0.12f * c.sc, c.trait(-0.12f, 0.02f) * c.sc);
            p.hand[s] = mix(p.hand[s], target, ext * c.amp > 1 ? 1.0f : ext);
            p.twist -= c.sideSign(s) * 0.25f * ext * c.amp;
          }
          p.pitch += 0.08f * guard;
        } } },
    { "scratch_head",
      { 3.2f,
        [](Context& c, Pose& p, float u, float t) {
          const float e = envelope(u, c.trait(0.05f, 0.15f), c.trait(0.28f, 0.38f), c.trait(0.7f, 0.8f), 0.95f);
          const float f = c.trait(2.5f, 4.5f), a = 0.018f * c.amp;
          const Eigen::Vector3f head(c.trait(-0.04f, 0.04f) * c.sc, -c.sideSign(c.dom) * c.trait(0.1f, 0.17f) * c.sc,
                                     c.trait(0.28f, 0.34f) * c.sc);
          const Eigen::Vector3f scratch(a * std::sin(2 * kPi * f * t), a * std::sin(2 * kPi * f * t + 1.3f), 0);
          p.hand[c.dom] = mix(p.hand[c.dom], head + scratch * envelope(u, 0.3f, 0.38f, 0.7f, 0.78f), e);
          p.elbow_pole[c.dom] = mix(p.elbow_pole[c.dom], Eigen::Vector3f(0.3f, c.sideSign(c.dom), 0.5f), e);
          p.head_pitch += 0.15f * e;
          p.roll += c.sideSign(c.dom) * 0.05f * e;
        } } },
    { "sit_down",
      { 2.6f,
        [](Context& c, Pose& p, float u, float) {
          const float lean = c.trait(0.35f, 0.6f) * c.amp;
          const float w = ease((u - 0.2f) / 0.55f);
          p.pitch += lean * envelope(u, 0.05f, 0.35f, 0.6f, 0.95f);
          seatedPose(c, p, w, Eigen::Vector3f(-0.3f * c.sc, 0, 0.46f));
          for (int s = 0; s < 2; ++s)
            p.hand[s] = mix(p.hand[s], armArc(c, s, 0.6f, 0.2f, 0.9f), envelope(u, 0.15f, 0.4f, 0.55f, 0.85f));
        } } },
    { "standing",
      { 3.0f,
        [](Context& c, Pose& p, float u, float t) {
          // Doing nothing in particular: a weight shift, a look around, hands brought together once.
          const float shift = envelope(u, c.trait(0.1f, 0.3f), c.trait(0.35f, 0.5f), 0.6f, 0.9f);
          p.pelvis.y() += c.sideSign(c.dom) * 0.03f * c.sc * shift;
          p.roll -= c.sideSign(c.dom) * 0.02f * shift;
          p.head_yaw += 0.25f * std::sin(0.8f * t + c.trait(0.0f, 3.0f)) * c.trait(0.3f, 1.0f);
          const float hands = c.trait(0.0f, 1.0f) > 0.5f ? envelope(u, 0.2f, 0.35f, 0.7f, 0.85f) : 0.0f;
          for (int s = 0; s < 2; ++s)
            p.hand[s] = mix(p.hand[s], Eigen::Vector3f(0.12f * c.sc, -c.sideSign(s) * 0.17f * c.sc, -0.5f * c.sc), hands);
        } } },
    { "throw_bottom_up",
      { 2.4f,
        [](Context& c, Pose& p, float u, float) {
          const float wind = envelope(u, 0.1f, 0.38f, 0.38f, 0.52f);
          const float release = envelope(u, 0.38f, 0.52f, 0.58f, 0.88f);
          const float top = kPi / 2 + c.trait(-0.2f, 0.5f) * c.amp;
          const float alpha = -0.7f * c.amp * wind + top * release;
          const float act = envelope(u, 0.08f, 0.2f, 0.75f, 0.9f);
          p.hand[c.dom] = mix(p.hand[c.dom], armArc(c, c.dom, alpha, 0.1f, 0.95f), act);
          p.pitch += 0.18f * wind - 0.06f * release;
          p.pelvis.z() -= 0.05f * c.sc * wind;
          const int nd = 1 - c.dom;
          p.foot[nd].x() += 0.18f * c.sc * envelope(u, 0.1f, 0.3f, 0.75f, 0.95f);
          p.twist += c.sideSign(c.dom) * 0.2f * (wind - release);
        } } },
    { "throw_over_head",
      { 2.6f,
        [](Context& c, Pose& p, float u, float) {
          const float raise = envelope(u, 0.08f, 0.4f, 0.45f, 0.58f);
          const float thrust = envelope(u, 0.45f, 0.58f, 0.62f, 0.9f);
          const float act = envelope(u, 0.05f, 0.2f, 0.8f, 0.95f);
          const float back = kPi + c.trait(0.15f, 0.45f) * c.amp;
          const float alpha = back * raise + c.trait(1.7f, 2.2f) * thrust;
          const float reach = 0.7f + 0.27f * thrust;
          for (int s = 0; s < 2; ++s)
          {
            p.hand[s] = mix(p.hand[s], armArc(c, s, alpha, 0.15f, reach), act);
            p.elbow_pole[s] = mix(p.elbow_pole[s], Eigen::Vector3f(0, c.sideSign(s), 0.3f), act);
          }
          p.pitch += -0.18f * raise * c.amp + 0.3f * thrust * c.amp;
          p.foot[c.dom].x() -= 0.2f * c.sc * envelope(u, 0.1f, 0.3f, 0.75f, 0.95f);
          p.head_pitch -= 0.2f * raise;
        } } },
    { "turn_around",
      { 3.2f,
        [](Context& c, Pose& p, float u, float) {
          const float dir = c.style->uniform(0, 1) < 0.5 ? 1.0f : -1.0f;
          const auto yaw_at = [&](float x) { return dir * 2 * kPi * ease(x); };
          p.yaw = yaw_at(u);
          // Small steps: each foot in turn lifts and turns to where the body will face next.
          const int steps = 8;
          for (int s = 0; s < 2; ++s)
          {
            float foot_yaw = 0, lift = 0;
            for (int j = s; j < steps; j += 2)
            {
              const float a = float(j) / steps, b = float(j + 1) / steps;
              if (u >= b)
                foot_yaw = yaw_at(std::min(1.0f, b + 0.5f / steps));
              else if (u > a)
              {
                const float tau = (u - a) / (b - a);
                foot_yaw = foot_yaw + (yaw_at(std::min(1.0f, b + 0.5f / steps)) - foot_yaw) * ease(tau);
                lift = 0.07f * c.sc * std::sin(kPi * tau);
              }
            }
            const Eigen::Vector3f rest(0.0f, c.sideSign(s) * (c.dm.hip_half + c.stance), c.dm.ankle);
            p.foot[s] = rotZ(foot_yaw) * rest + Eigen::Vector3f(0, 0, lift);
          }
          p.feet_in_body_frame = false;
          const float swing = envelope(u, 0.05f, 0.15f, 0.85f, 0.95f);
          for (int s = 0; s < 2; ++s)
            p.hand[s] = mix(p.hand[s], armArc(c, s, 0.25f, 0.3f, 0.95f), swing);
          p.head_yaw += dir * 0.3f * swing;
        } } },
    { "walk",
      { 0.0f,  // set by the path length and speed
        nullptr } },
    { "wave",
      { 3.0f,
        [](Context& c, Pose& p, float u, float t) {
          const float e = envelope(u, c.trait(0.05f, 0.12f), c.trait(0.2f, 0.3f), c.trait(0.75f, 0.85f), 0.96f);
          const float f = c.trait(1.6f, 2.6f), a = c.trait(0.08f, 0.16f) * c.amp * c.sc;
          const Eigen::Vector3f up(c.trait(0.05f, 0.2f) * c.sc, c.sideSign(c.dom) * c.trait(0.15f, 0.28f) * c.sc,
                                   c.trait(0.3f, 0.42f) * c.sc * c.amp);
          const float osc = envelope(u, 0.22f, 0.3f, 0.72f, 0.8f);
          const Eigen::Vector3f wave(0, c.sideSign(c.dom) * a * std::sin(2 * kPi * f * t), 0);
          p.hand[c.dom] = mix(p.hand[c.dom], up + wave * osc, e);
          p.elbow_pole[c.dom] = mix(p.elbow_pole[c.dom], Eigen::Vector3f(0, c.sideSign(c.dom), -0.7f), e);
          p.roll -= c.sideSign(c.dom) * 0.03f * e;
        } } },
  };
  return table;
}

// Walking: a path of length len along +x with acceleration and deceleration, gait from the distance.
void walkPose(Context& c, Pose& p, double t, double t0, double t1, float len, float speed)
{
  const double ramp = std::min(0.6, 0.25 * (t1 - t0));
  const double cruise = (t1 - t0) - ramp;  // integral of the speed profile = speed * cruise = len
  double s = 0, v = 0;
  const double tc = std::clamp(t - t0, 0.0, t1 - t0);
  if (tc < ramp)
  {
    v = speed * tc / ramp;
    s = 0.5 * speed * tc * tc / ramp;
  }
  else if (tc < t1 - t0 - ramp)
  {
    v = speed;
    s = 0.5 * speed * ramp + speed * (tc - ramp);
  }
  else
  {
    const double td = (t1 - t0) - tc;
    v = speed * td / ramp;
    s = speed * cruise - 0.5 * speed * td * td / ramp;
  }
  (void)len;
  const float w = float(v / speed);
  const float step = c.trait(0.36f, 0.44f) * c.dm.height * std::sqrt(c.pace);
  const float stride = 2 * step;
  const float phi = float(s) / stride;
  p.pelvis.x() += float(s);
  p.pelvis.z() += (-0.012f + 0.015f * std::cos(4 * kPi * phi)) * w * c.sc;
  p.pelvis.y() += 0.02f * std::sin(2 * kPi * phi) * w * c.sc;
  p.pitch += 0.06f * w;
  p.twist += 0.1f * std::sin(2 * kPi * phi) * w;
  const float lift_h = c.trait(0.08f, 0.13f) * c.sc;
  for (int sd = 0; sd < 2; ++sd)
  {
    const float off = sd == 0 ? 0.0f : 0.5f;
    const float psi = phi + off;
    const float n = std::floor(psi), f = psi - n;
    float x = stride * n + stride * (0.3f - off);
    float z = c.dm.ankle;
    if (f >= 0.6f)
    {
      const float tau = (f - 0.6f) / 0.4f;
      x += stride * ease(tau);
      z += lift_h * std::sin(kPi * tau);
    }
    // Feet together when standing, gait when moving.
    const Eigen::Vector3f gait(x, c.sideSign(sd) * (c.dm.hip_half + c.stance), z);
    const Eigen::Vector3f still(float(s), c.sideSign(sd) * (c.dm.hip_half + c.stance), c.dm.ankle);
    p.foot[sd] = mix(still, gait, std::min(1.0f, 2.0f * w));
    // Arms swing against the legs.
    const float swing = 0.35f * c.amp * w * std::sin(2 * kPi * (psi + 0.25f));
    p.hand[sd] = armArc(c, sd, -swing, 0.08f, 0.95f);
  }
  p.feet_in_body_frame = false;
}

// The actor's traits jittered for one repetition, drawn from style and rep in a fixed order.
Context makeContext(const Actor& actor, Rng& style, Rng& rep)
{
  Context c;
  c.actor = &actor;
  c.dm = Dims(actor.shape.height);
  c.sc = actor.shape.height / 1.75f;
  c.pace = actor.pace * float(1.0 + 0.06 * std::clamp(rep.normal(), -2.0, 2.0));
  c.amp = actor.amplitude * float(1.0 + 0.06 * std::clamp(rep.normal(), -2.0, 2.0));
  c.dom = actor.left_handed ? 0 : 1;
  c.style = &style;
  c.rep = &rep;
  for (float& ph : c.sway_phase)
    ph = float(rep.uniform(0, 2 * kPi));
  c.stance = float(style.uniform(0.0, 0.06)) * c.sc;
  return c;
}

}  // namespace

namespace
{
// perform(), with the walk's length given (m; 0 = drawn as for the IAS-Lab walk, 1.6-2.2 m).
Performance performAction(const Actor& actor, const std::string& action, std::uint64_t rep_seed, double fps,
                          float walk_length)
{
  const auto& table = actionTable();
  const auto it = table.find(action);
  if (it == table.end())
    throw std::invalid_argument("unknown action '" + action + "'");
  Rng style(hash64(actor.style_seed, hashString(action), 0x5717e));
  Rng rep(hash64(rep_seed, 0x7e9));
  Context c = makeContext(actor, style, rep);

  const double idle_before = rep.uniform(0.3, 0.8), idle_after = rep.uniform(0.3, 0.8);
  Performance perf;
  double core = it->second.duration / c.pace;
  float walk_len = 0, walk_speed = 0;
  if (action == "walk")
  {
    walk_speed = float(style.uniform(1.0, 1.35) * c.pace * (1.0 + rep.uniform(-0.05, 0.05)));
    walk_len = float(rep.uniform(1.6, 2.2));  // drawn even when given: the draws that follow stay the same
    if (walk_length > 0)
      walk_len = walk_length;
    const double ramp = 0.6;
    core = walk_len / walk_speed + ramp;
    perf.walks = true;
  }
  core *= rep.uniform(0.95, 1.05);
  const double total = idle_before + core + idle_after;
  const int frames = std::max(2, int(std::round(total * fps)));
  const Eigen::Vector3f chair(-0.3f * c.sc, 0, 0.46f);
  perf.uses_chair = action == "get_up" || action == "sit_down";
  perf.chair = chair;
  perf.core_first = std::min(frames - 1, int(std::ceil(idle_before * fps - 1e-6)));
  perf.core_last = std::clamp(int(std::floor((idle_before + core) * fps + 1e-6)), perf.core_first, frames - 1);
  perf.joints.reserve(frames);
  perf.forward.reserve(frames);
  // The random draws of the generators must not depend on the frame: fix their sequence by
  // re-seeding the repetition generator identically for every frame.
  const std::uint64_t rep_state = rep.next();
  for (int i = 0; i < frames; ++i)
  {
    const double t = i / fps;
    Rng frame_rep(rep_state);
    Rng frame_style(hash64(actor.style_seed, hashString(action), 0x5717e));
    c.rep = &frame_rep;
    c.style = &frame_style;
    Pose p = idlePose(c, t);
    const float u = float(std::clamp((t - idle_before) / core, 0.0, 1.0));
    if (action == "walk")
      walkPose(c, p, t, idle_before, idle_before + core, walk_len, walk_speed);
    else
    {
      it->second.apply(c, p, u, float(t - idle_before));
    }
    const Posed posed = solvePose(c.dm, p);
    perf.joints.push_back(posed.joints);
    perf.forward.push_back(posed.forward);
  }
  return perf;
}

}  // namespace

Performance perform(const Actor& actor, const std::string& action, std::uint64_t rep_seed, double fps)
{
  return performAction(actor, action, rep_seed, fps, 0.0f);
}

Performance performWalk(const Actor& actor, std::uint64_t rep_seed, double fps, float length)
{
  if (!(length > 0.0f) || !std::isfinite(length))
    throw std::invalid_argument("performWalk: the length must be positive, got " + std::to_string(length));
  return performAction(actor, "walk", rep_seed, fps, length);
}

Performance performIdle(const Actor& actor, std::uint64_t rep_seed, double fps, int frames)
{
  Rng style(hash64(actor.style_seed, hashString("idle"), 0x5717e));
  Rng rep(hash64(rep_seed, 0x1d1e));
  const Context c = makeContext(actor, style, rep);
  Performance perf;
  frames = std::max(1, frames);
  perf.core_last = frames - 1;
  for (int i = 0; i < frames; ++i)
  {
    const Posed posed = solvePose(c.dm, idlePose(c, i / fps));
    perf.joints.push_back(posed.joints);
    perf.forward.push_back(posed.forward);
  }
  return perf;
}

}  // namespace synth
}  // namespace action_flow
