// Tests of the synthetic actors and the per-sample renderer: the sets, the rendered frames and
// masks, determinism, and that the actions move what they should.
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

using namespace action_flow::synth;

namespace
{
SampleSpec ias(const std::string& person, const std::string& action, int rep, int max_frames = 0, std::uint64_t seed = 1)
{
  SampleSpec s;
  s.dataset = "ias";
  s.person = person;
  s.action = action;
  s.repetition = rep;
  s.seed = seed;
  s.max_frames = max_frames;
  return s;
}

// Path length of a joint over the whole sample (m).
float travel(const SampleRenderer& r, Joint j)
{
  float len = 0;
  for (int i = 1; i < r.frames(); ++i)
    len += (r.worldSkeleton(i)[j] - r.worldSkeleton(i - 1)[j]).norm();
  return len;
}

float maxHandTravel(const SampleRenderer& r) { return std::max(travel(r, Joint::LeftHand), travel(r, Joint::RightHand)); }
float maxFootTravel(const SampleRenderer& r) { return std::max(travel(r, Joint::LeftFoot), travel(r, Joint::RightFoot)); }

Eigen::Vector3f pelvis(const Skeleton& s) { return 0.5f * (s[Joint::LeftHip] + s[Joint::RightHip]); }

// Hands and feet relative to the pelvis, at 20 evenly spaced moments: a crude motion signature.
Eigen::VectorXf signature(const SampleRenderer& r)
{
  const Joint parts[] = { Joint::LeftHand, Joint::RightHand, Joint::LeftFoot, Joint::RightFoot, Joint::Head };
  Eigen::VectorXf v(20 * 5 * 3);
  int k = 0;
  for (int t = 0; t < 20; ++t)
  {
    const Skeleton& s = r.worldSkeleton(int(std::lround(t * (r.frames() - 1) / 19.0)));
    for (Joint j : parts)
    {
      v.segment<3>(k) = s[j] - pelvis(s);
      k += 3;
    }
  }
  return v;
}
}  // namespace

TEST(Sets, IasLabHas540UniqueSamplesOf15Actions)
{
  ASSERT_EQ(iasLabActions().size(), 15u);
  EXPECT_EQ(iasLabActions().front(), "check_watch");
  EXPECT_EQ(iasLabActions().back(), "wave");
  const auto specs = iasLabSamples();
  ASSERT_EQ(specs.size(), 540u);
  std::set<std::string> names;
  for (const auto& s : specs)
    names.insert(s.name());
  EXPECT_EQ(names.size(), 540u);
  EXPECT_EQ(specs.front().name(), "p01_check_watch_1");
  EXPECT_EQ(iasLabSamples(2, 1).size(), 30u);
  EXPECT_THROW(iasLabSamples(0, 3), std::invalid_argument);
  EXPECT_THROW(iasLabSamples(12, 0), std::invalid_argument);
}

TEST(Actors, TwelveDistinctPeopleCoverTheHeightRange)
{
  float lo = 10, hi = 0;
  int left = 0;
  std::set<std::tuple<float, float, float>> shirts;
  for (const auto& s : iasLabSamples(12, 1))
  {
    if (s.action != "wave")
      continue;
    const Actor a = makeActor(s.person, 1);
    lo = std::min(lo, a.shape.height);
    hi = std::max(hi, a.shape.height);
    left += a.left_handed ? 1 : 0;
    EXPECT_GE(a.pace, 0.75f);
    EXPECT_LE(a.pace, 1.25f);
    shirts.insert({ a.appearance.shirt.base.x(), a.appearance.shirt.base.y(), a.appearance.shirt.base.z() });
  }
  EXPECT_GE(lo, 1.55f);
  EXPECT_LE(hi, 1.95f);
  EXPECT_LT(lo, 1.62f);
  EXPECT_GT(hi, 1.88f);
  EXPECT_GE(left, 1);
  EXPECT_EQ(shirts.size(), 12u);
  EXPECT_THROW(makeActor("x7"), std::invalid_argument);
}

TEST(SampleRenderer, RendersAnOrganizedCloudWithThePersonMasked)
{
  const SampleRenderer r(ias("p01", "wave", 1, 3));
  ASSERT_EQ(r.frames(), 3);
  EXPECT_EQ(r.label(), "wave");
  EXPECT_NEAR(r.stamp(1) - r.stamp(0), 1.0 / 30, 1e-6);
  action_flow::Cloud cloud;
  std::vector<std::uint8_t> mask;
  r.render(2, cloud, &mask);
  ASSERT_EQ(cloud.width, 640u);
  ASSERT_EQ(cloud.height, 480u);
  EXPECT_FALSE(cloud.is_dense);
  EXPECT_EQ(cloud.header.frame_id, "camera_rgb_optical_frame");
  EXPECT_EQ(cloud.header.stamp, std::uint64_t(std::llround(r.stamp(2) * 1e6)));
  ASSERT_EQ(mask.size(), cloud.size());
  // The person: thousands of pixels, all near the skeleton, 2.3-3.8 m away.
  const Skeleton sk = r.skeleton(2);
  Eigen::Vector3f lo = sk.joints[0], hi = sk.joints[0];
  for (const auto& j : sk.joints)
  {
    lo = lo.cwiseMin(j);
    hi = hi.cwiseMax(j);
  }
  lo.array() -= 0.3f;
  hi.array() += 0.3f;
  int person = 0, with_depth = 0, nan_elsewhere = 0;
  for (size_t i = 0; i < cloud.size(); ++i)
  {
    const auto& p = cloud.points[i];
    if (!mask[i])
    {
      nan_elsewhere += std::isnan(p.z) ? 1 : 0;
      continue;
    }
    EXPECT_EQ(mask[i], 1);
    ++person;
    if (!std::isfinite(p.z))
      continue;
    ++with_depth;
    const Eigen::Vector3f q(p.x, p.y, p.z);
    ASSERT_TRUE((q.array() >= lo.array()).all() && (q.array() <= hi.array()).all()) << q.transpose();
  }
  EXPECT_GT(person, 4000);
  EXPECT_GT(with_depth, 0.8 * person);
  EXPECT_GT(nan_elsewhere, 0);  // the range limit and edges leave holes
  // Head above feet in the image (y down) and the camera about 1.1 m above the floor.
  EXPECT_LT(sk[Joint::Head].y(), sk[Joint::LeftFoot].y() - 1.2f);
  EXPECT_NEAR(r.camera().height_above_floor, 1.1, 0.05);
  EXPECT_THROW(r.render(3, cloud), std::out_of_range);
}

TEST(SampleRenderer, SameSpecSameBytesAndRepetitionsDiffer)
{
  const SampleRenderer a(ias("p03", "punch", 2, 40)), b(ias("p03", "punch", 2, 40));
  action_flow::Cloud ca, cb;
  std::vector<std::uint8_t> ma, mb;
  a.render(30, ca, &ma);
  b.render(30, cb, &mb);
  ASSERT_EQ(ca.size(), cb.size());
  EXPECT_EQ(std::memcmp(ca.points.data(), cb.points.data(), ca.size() * sizeof(action_flow::PointT)), 0);
  EXPECT_EQ(ma, mb);
  // Another repetition or another seed: different motion and noise.
  const SampleRenderer c(ias("p03", "punch", 3, 40)), d(ias("p03", "punch", 2, 40, 2));
  float diff_rep = 0, diff_seed = 0;
  for (int i = 0; i < 40; ++i)
    for (int k = 0; k < kJointCount; ++k)
    {
      diff_rep = std::max(diff_rep, (a.worldSkeleton(i).joints[k] - c.worldSkeleton(i).joints[k]).norm());
      diff_seed = std::max(diff_seed, (a.worldSkeleton(i).joints[k] - d.worldSkeleton(i).joints[k]).norm());
    }
  EXPECT_GT(diff_rep, 0.02f);
  EXPECT_GT(diff_seed, 0.02f);
}

TEST(Motion, ActionsMoveTheLimbsTheyShould)
{
  const auto make = [](const std::string& action) { return SampleRenderer(ias("p02", action, 1)); };
  const SampleRenderer standing = make("standing"), wave = make("wave"), kick = make("kick"), walk = make("walk");
  const SampleRenderer sit = make("sit_down"), get_up = make("get_up"), pick = make("pick_up");
  // Wave: the hand travels metres, the feet stay.
  EXPECT_GT(maxHandTravel(wave), 4 * maxHandTravel(standing));
  EXPECT_LT(maxFootTravel(wave), 0.1f);
  // Kick: a foot travels far more than when standing.
  EXPECT_GT(maxFootTravel(kick), 0.8f);
  EXPECT_LT(maxFootTravel(standing), 0.1f);
  // Walk: the body crosses more than a metre.
  EXPECT_GT((pelvis(walk.worldSkeleton(walk.frames() - 1)) - pelvis(walk.worldSkeleton(0))).norm(), 1.2f);
  // Sit down ends lower than it starts, get up the reverse; pick up brings a hand near the floor.
  EXPECT_LT(pelvis(sit.worldSkeleton(sit.frames() - 1)).z(), pelvis(sit.worldSkeleton(0)).z() - 0.2f);
  EXPECT_GT(pelvis(get_up.worldSkeleton(get_up.frames() - 1)).z(), pelvis(get_up.worldSkeleton(0)).z() + 0.2f);
  float lowest = 10;
  for (int i = 0; i < pick.frames(); ++i)
    lowest = std::min({ lowest, pick.worldSkeleton(i)[Joint::LeftHand].z(), pick.worldSkeleton(i)[Joint::RightHand].z() });
  EXPECT_LT(lowest, 0.25f);
}

TEST(Motion, DominantHandDoesTheGesture)
{
  // p03 is left-handed, p01 right-handed.
  ASSERT_TRUE(makeActor("p03").left_handed);
  ASSERT_FALSE(makeActor("p01").left_handed);
  const SampleRenderer left(ias("p03", "wave", 1)), right(ias("p01", "wave", 1));
  EXPECT_GT(travel(left, Joint::LeftHand), 3 * travel(left, Joint::RightHand));
  EXPECT_GT(travel(right, Joint::RightHand), 3 * travel(right, Joint::LeftHand));
}

TEST(Motion, PeopleDifferMoreThanRepetitions)
{
  double within = 0, between = 0;
  int n = 0;
  for (const std::string action : { "wave", "point", "kick", "check_watch", "throw_over_head" })
    for (const std::string person : { "p01", "p04", "p06" })
    {
      const Eigen::VectorXf r1 = signature(SampleRenderer(ias(person, action, 1)));
      const Eigen::VectorXf r2 = signature(SampleRenderer(ias(person, action, 2)));
      const Eigen::VectorXf other = signature(SampleRenderer(ias(person == "p01" ? "p05" : "p01", action, 1)));
      within += (r1 - r2).norm();
      between += (r1 - other).norm();
      EXPECT_GT((r1 - r2).norm(), 0.01f) << person << " " << action << ": repetitions identical";
      ++n;
    }
  EXPECT_LT(within / n, between / n);
}

TEST(Placement, WholeBodyInViewAndFacingTheCamera)
{
  for (const std::string person : { "p01", "p05", "p09" })
    for (const auto& action : iasLabActions())
    {
      const SampleRenderer r(ias(person, action, 2));
      const auto& cam = r.camera();
      for (int i = 0; i < r.frames(); i += 5)
      {
        const Skeleton s = r.skeleton(i);
        for (const auto& p : s.joints)
        {
          const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
          ASSERT_TRUE(u > 0 && u < 639 && v > 0 && v < 479) << r.spec().name() << " frame " << i;
        }
      }
      // Distance of the standing start from the camera (horizontal), 2.5-3.5 m (walkers may be off).
      const Skeleton& w0 = r.worldSkeleton(0);
      const float d = pelvis(w0).head<2>().norm();
      if (action != "walk")
      {
        EXPECT_GE(d, 2.45f) << r.spec().name();
        EXPECT_LE(d, 4.25f) << r.spec().name();
      }
    }
}

// The cross-view evaluation's placement: the same performance, turned to face the camera at an angle.
TEST(Placement, FacingTurnsTheActorAndKeepsThePerformance)
{
  for (const std::string action : { "wave", "kick", "sit_down" })
  {
    SampleSpec front = ias("p02", action, 1);
    EXPECT_EQ(front.name(), "p02_" + action + "_1");
    const SampleRenderer r0(front);
    for (double facing : { 45.0, 90.0, 180.0 })
    {
      SampleSpec turned = front;
      turned.facing = facing;
      turned.facing_spread = 0.0;
      const SampleRenderer r(turned);
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, "_f%gs0", facing);
      EXPECT_EQ(r.spec().name(), front.name() + suffix);
      ASSERT_EQ(r.frames(), r0.frames()) << turned.name();
      // The angle between where the body faces and the way to the camera, on the ground.
      const Eigen::Vector3f cam = r.camera().worldFromOptical().translation();
      const Eigen::Vector3f at = pelvis(r.worldSkeleton(0));
      const Eigen::Vector2f to_cam = (cam - at).head<2>().normalized();
      const Eigen::Vector2f fwd = r.posedBody(0).forward.head<2>().normalized();
      const double angle = std::acos(std::clamp(double(fwd.dot(to_cam)), -1.0, 1.0)) * 180.0 / M_PI;
      EXPECT_NEAR(angle, facing, 3.0) << turned.name();
      // The same motion: every joint's distance from the pelvis, frame by frame.
      for (int i = 0; i < r.frames(); i += 7)
        for (int k = 0; k < kJointCount; ++k)
          EXPECT_NEAR((r.worldSkeleton(i).joints[k] - pelvis(r.worldSkeleton(i))).norm(),
                      (r0.worldSkeleton(i).joints[k] - pelvis(r0.worldSkeleton(i))).norm(), 1e-4)
              << turned.name() << " frame " << i << " joint " << k;
    }
  }
  SampleSpec bad = ias("p02", "wave", 1);
  bad.facing = 200.0;
  EXPECT_THROW(SampleRenderer{ bad }, std::invalid_argument);
}

TEST(Msr, RendersRealSkeletonsWithTheRightArmWaving)
{
  const std::string folder = std::string(ACTION_FLOW_SHARED_DATA) + "/msr_action3d_skeletons";
  if (!std::filesystem::exists(folder))
    GTEST_SKIP() << "MSR skeletons not found at " << folder;
  const auto specs = msrSamples(folder);
  ASSERT_EQ(specs.size(), 557u);
  EXPECT_EQ(msrSamples(folder, 1, false).size(), 567u);
  const SampleSpec spec = specs.front();
  EXPECT_EQ(spec.name(), "a01_s01_e01");
  EXPECT_EQ(spec.action, "high_arm_wave");
  const MsrSkeletonFile file = parseMsrSkeletonFile(spec.skeleton_file);
  const SampleRenderer r(spec);
  EXPECT_EQ(r.frames(), 2 * int(file.frames.size()) - 1);  // 15 fps resampled to 30
  // High arm wave with the right arm: the right hand goes above the head, and, the person facing
  // the camera, appears on the image's left of the left hand.
  bool above = false;
  for (int i = 0; i < r.frames(); ++i)
  {
    const Skeleton& w = r.worldSkeleton(i);
    above = above || w[Joint::RightHand].z() > w[Joint::Head].z();
    EXPECT_LT(w[Joint::LeftHand].z(), w[Joint::Head].z());
  }
  EXPECT_TRUE(above);
  const Skeleton s = r.skeleton(0);
  EXPECT_LT(s[Joint::RightShoulder].x(), s[Joint::LeftShoulder].x());
  // Feet on the floor, whole person rendered.
  EXPECT_NEAR(std::min(r.worldSkeleton(0)[Joint::LeftFoot].z(), r.worldSkeleton(0)[Joint::RightFoot].z()), 0.07f, 0.08f);
  action_flow::Cloud cloud;
  std::vector<std::uint8_t> mask;
  r.render(r.frames() / 2, cloud, &mask);
  EXPECT_GT(std::count(mask.begin(), mask.end(), 1), 4000);
}

// A training copy is the same recorded motion with another body, pace, turn and distance: the
// joints keep their distances from the torso (turned and moved, not deformed), the frame count
// follows the pace, the whole body stays in view, and the recording itself is unchanged.
TEST(Msr, TrainingCopiesRenderTheSameMotionOtherwise)
{
  const std::string folder = std::string(ACTION_FLOW_SHARED_DATA) + "/msr_action3d_skeletons";
  if (!std::filesystem::exists(folder))
    GTEST_SKIP() << "MSR skeletons not found at " << folder;
  const SampleSpec original = msrSamples(folder).front();
  const SampleRenderer r0(original);
  const int n15 = int(parseMsrSkeletonFile(original.skeleton_file).frames.size());
  std::set<int> frame_counts;
  std::set<float> builds;
  for (int k = 1; k <= 4; ++k)
  {
    SampleSpec copy = original;
    copy.copy = k;
    EXPECT_EQ(copy.name(), "a01_s01_e01_c" + std::to_string(k));
    const SampleRenderer r(copy);
    EXPECT_EQ(r.label(), original.action);
    // Paced 0.8-1.2 times: 30 fps frames of (n15 - 1) / 15 s divided by the pace.
    EXPECT_GE(r.frames(), int(std::floor(2.0 * (n15 - 1) / 1.2)));
    EXPECT_LE(r.frames(), int(std::ceil(2.0 * (n15 - 1) / 0.8)) + 1);
    frame_counts.insert(r.frames());
    // The first frames are the same pose (both start at the recording's frame 0): each joint as far
    // from the torso, and the head as high above the floor.
    for (int j = 0; j < kJointCount; ++j)
      EXPECT_NEAR((r.worldSkeleton(0).joints[j] - r.worldSkeleton(0)[Joint::Torso]).norm(),
                  (r0.worldSkeleton(0).joints[j] - r0.worldSkeleton(0)[Joint::Torso]).norm(), 1e-4)
          << copy.name() << " joint " << j;
    EXPECT_NEAR(r.worldSkeleton(0)[Joint::Head].z(), r0.worldSkeleton(0)[Joint::Head].z(), 1e-4);
    const float distance = r.worldSkeleton(0)[Joint::Torso].head<2>().norm();
    EXPECT_GE(distance, 1.5f);
    EXPECT_LE(distance, 4.5f + 1e-4f);
    builds.insert(r.posedBody(0).shape.build);
    action_flow::Cloud cloud;
    std::vector<std::uint8_t> mask;
    r.render(r.frames() / 2, cloud, &mask);
    EXPECT_GT(std::count(mask.begin(), mask.end(), 1), 2000) << copy.name();
  }
  EXPECT_GE(frame_counts.size(), 2u) << "the pace is drawn per copy";
  // Some changes only: each draws what it draws with all of them.
  SampleSpec all = original, body = original, pace = original;
  all.copy = body.copy = pace.copy = 1;
  body.copy_changes = kCopyBody;
  pace.copy_changes = kCopyPace | kCopyDistance;
  EXPECT_EQ(body.name(), "a01_s01_e01_c1_b");
  EXPECT_EQ(pace.name(), "a01_s01_e01_c1_pd");
  const SampleRenderer ra(all), rb(body), rp(pace);
  EXPECT_EQ(rb.frames(), r0.frames()) << "without the pace";
  EXPECT_NEAR((rb.worldSkeleton(5)[Joint::Head] - r0.worldSkeleton(5)[Joint::Head]).norm(), 0.0f, 1e-5f)
      << "neither turned nor moved";
  EXPECT_EQ(rb.posedBody(0).shape.build, ra.posedBody(0).shape.build);
  EXPECT_EQ(rp.frames(), ra.frames());
  EXPECT_EQ(rp.posedBody(0).shape.build, r0.posedBody(0).shape.build);
  EXPECT_NEAR(rp.worldSkeleton(0)[Joint::Torso].head<2>().norm(), ra.worldSkeleton(0)[Joint::Torso].head<2>().norm(), 0.11f)
      << "the same distance drawn (the turn may move the body back once more to fit)";
  SampleSpec none = all;
  none.copy_changes = 0;
  EXPECT_THROW(SampleRenderer{ none }, std::invalid_argument);
  EXPECT_GE(builds.size(), 3u) << "each copy has a body of its own";
  // The recording itself is rendered as before copies existed: from the original's own draws.
  EXPECT_EQ(r0.frames(), 2 * n15 - 1);
  SampleSpec ias_copy = ias("p01", "wave", 1);
  ias_copy.copy = 1;
  EXPECT_THROW(SampleRenderer{ ias_copy }, std::invalid_argument);
  SampleSpec too_many = original;
  too_many.copy = 100;
  EXPECT_THROW(SampleRenderer{ too_many }, std::invalid_argument);
}

TEST(SceneRenderer, TwoPeopleGetTheirOwnMaskIds)
{
  const SampleRenderer a(ias("p01", "wave", 1, 5)), b(ias("p02", "walk", 1, 5));
  PosedBody first = a.posedBody(4, 1), second = b.posedBody(4, 2);
  // Put the second person 1.2 m to the side of the first.
  const Eigen::Vector3f shift = pelvis(first.joints) + Eigen::Vector3f(0, 1.2f, 0) - pelvis(second.joints);
  for (auto& j : second.joints.joints)
    j += Eigen::Vector3f(shift.x(), shift.y(), 0);
  CameraModel cam;
  const SceneRenderer scene(cam, Room::lab(1));
  FrameImages im;
  scene.render({ first, second }, 1, 0, im);
  const long ones = std::count(im.mask.begin(), im.mask.end(), 1), twos = std::count(im.mask.begin(), im.mask.end(), 2);
  EXPECT_GT(ones, 3000);
  EXPECT_GT(twos, 3000);
  // The second person stands on the camera's left (world +y): smaller image columns.
  double u1 = 0, u2 = 0;
  for (size_t i = 0; i < im.mask.size(); ++i)
  {
    if (im.mask[i] == 1)
      u1 += double(i % size_t(im.width)) / ones;
    if (im.mask[i] == 2)
      u2 += double(i % size_t(im.width)) / twos;
  }
  EXPECT_LT(u2, u1 - 50);
}
