// The tracker against the failures: the ground when little floor is seen (kept, given by the
// camera's mounting, corrected when wrong), walls and furniture that are no people, and bodies that
// are not upright keeping their track. Scenes from test/core/scene.h and the virtual Kinect.
#include "real_data.h"
#include "../core/scene.h"

#include <action_flow/people_tracker.h>
#include <action_flow/synth/scene.h>
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

using namespace action_flow;
using test::Figure;
using test::SceneCamera;
using test::Wall;

namespace
{
// A real sensor's tracker (kinect.launch): the defaults plus HOG with the shipped classifier.
TrackerParams sensorParams()
{
  TrackerParams p;
  p.hog_classifier_file = "default";
  return p;
}

/** Angle (rad) and camera-height difference (m) between two ground planes. */
float groundAngle(const Eigen::Vector4f& a, const Eigen::Vector4f& b)
{
  return std::acos(std::min(1.0f, a.head<3>().dot(b.head<3>())));
}

/** A counter across the room: its lower 0.4 m hidden (a dark plinth), so its visible bottom edge is a
 *  wide level row of points 0.4 m above the floor: what "assume the ground below the lowest points" takes. */
Wall counter()
{
  Wall w;
  w.a = Eigen::Vector2f(-3.0f, 5.0f);
  w.b = Eigen::Vector2f(3.0f, 5.0f);
  w.z0 = 0.4f;
  w.z1 = 1.0f;
  return w;
}

const Figure kPerson{{0.2f, 3.2f}, 1.78f};
}  // namespace

TEST(TrackerGround, FloorHiddenAfterFramesThatShowedItKeepsTheGround)
{
  SceneCamera cam(1.3f, 0.15f);
  const Eigen::Vector4f truth = cam.floorInCamera();
  PeopleTracker tracker;
  for (int k = 0; k < 3; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({kPerson}, true, {counter()}, 0.004f, k), 0.1 * k);
    ASSERT_TRUE(r.ground_valid);
    ASSERT_FALSE(r.ground_assumed);
  }
  for (int k = 3; k < 15; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({kPerson}, false, {counter()}, 0.004f, k), 0.1 * k);
    ASSERT_TRUE(r.ground_valid) << "frame " << k;
    EXPECT_FALSE(r.ground_assumed) << "frame " << k << ": the measured ground gave way to an assumed one";
    EXPECT_LT(groundAngle(r.ground, truth), 0.03f) << "frame " << k;
    EXPECT_NEAR(r.ground[3], truth[3], 0.03f) << "frame " << k;
    ASSERT_EQ(r.people.size(), 1u) << "frame " << k;
    EXPECT_NEAR(r.people[0].height, kPerson.height, 0.06f) << "frame " << k;
  }
}

TEST(TrackerGround, GivenCameraHeightAndPitchFindThePersonWithTheFloorHidden)
{
  SceneCamera cam(1.3f, 0.15f);
  const Eigen::Vector4f truth = cam.floorInCamera();
  const Cloud cloud = cam.render({kPerson}, false, {counter()}, 0.004f);

  TrackerParams params;
  params.camera_height = 1.3f;
  params.camera_pitch = 0.15f;
  PeopleTracker tracker(params);
  for (int k = 0; k < 5; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({kPerson}, false, {counter()}, 0.004f, k), 0.1 * k);
    ASSERT_TRUE(r.ground_valid);
    EXPECT_FALSE(r.ground_assumed);
    EXPECT_LT(groundAngle(r.ground, truth), 0.01f);
    EXPECT_NEAR(r.ground[3], truth[3], 0.01f);
    if (k == 0)
      continue;
    ASSERT_EQ(r.people.size(), 1u) << "frame " << k;
    EXPECT_NEAR(r.people[0].height, kPerson.height, 0.06f);
    EXPECT_LT((cam.toWorld(r.people[0].position).head<2>() - kPerson.feet).norm(), 0.15f);
  }
}

TEST(TrackerGround, AWrongAssumptionIsCorrectedOnceTheFloorIsSeen)
{
  SceneCamera cam(1.3f, 0.15f);
  const Eigen::Vector4f truth = cam.floorInCamera();
  PeopleTracker tracker;
  for (int k = 0; k < 4; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({kPerson}, false, {counter()}, 0.004f, k), 0.1 * k);
    ASSERT_TRUE(r.ground_valid);
    ASSERT_TRUE(r.ground_assumed);
  }
  int corrected_at = -1;
  for (int k = 4; k < 30 && corrected_at < 0; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({kPerson}, true, {counter()}, 0.004f, k), 0.1 * k);
    if (!r.ground_assumed && std::abs(r.ground[3] - truth[3]) < 0.03f && groundAngle(r.ground, truth) < 0.03f)
      corrected_at = k;
  }
  ASSERT_GE(corrected_at, 0) << "the wrong assumed ground was kept";
  EXPECT_LE(corrected_at, 4 + 10) << "within one search interval";
}

TEST(TrackerGround, AWrongGivenGroundYieldsToAWideFloor)
{
  SceneCamera cam(1.3f, 0.15f);
  const Eigen::Vector4f truth = cam.floorInCamera();
  TrackerParams params;
  params.camera_height = 1.0f;  // 0.3 m wrong
  params.camera_pitch = 0.0f;   // 0.15 rad wrong
  PeopleTracker tracker(params);
  TrackerResult r;
  for (int k = 0; k < 3; ++k)
    r = tracker.update(cam.render({kPerson}, true, {}, 0.004f, k), 0.1 * k);
  ASSERT_TRUE(r.ground_valid);
  EXPECT_LT(groundAngle(r.ground, truth), 0.03f);
  EXPECT_NEAR(r.ground[3], truth[3], 0.03f);
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_NEAR(r.people[0].height, kPerson.height, 0.06f);
}

TEST(TrackerLikeness, AWallBehindAPersonGivesOneDetectionThePerson)
{
  // The wall rises beyond the top of the image (the back wall, cut into columns by the
  // top of the image); the person stands 0.5 m in front of it.
  SceneCamera cam(1.3f, 0.15f);
  Wall back;
  back.a = Eigen::Vector2f(-4.0f, 3.7f);
  back.b = Eigen::Vector2f(4.0f, 3.7f);
  back.z0 = 0.0f;
  back.z1 = 4.0f;
  Wall door;  // a door-sized panel standing out from the wall at the side, its top below the image's
  door.a = Eigen::Vector2f(-1.9f, 3.6f);
  door.b = Eigen::Vector2f(-1.1f, 3.6f);
  door.z0 = 0.0f;
  door.z1 = 2.05f;
  const Figure person{{0.3f, 3.2f}, 1.75f};
  PeopleTracker tracker;
  for (int k = 0; k < 5; ++k)
  {
    const TrackerResult r = tracker.update(cam.render({person}, true, {back, door}, 0.004f, k), 0.1 * k);
    if (k == 0)
      continue;
    EXPECT_EQ(r.detections, 1u) << "frame " << k;
    ASSERT_EQ(r.people.size(), 1u) << "frame " << k;
    EXPECT_LT((cam.toWorld(r.people[0].position).head<2>() - person.feet).norm(), 0.15f);
    EXPECT_NEAR(r.people[0].height, person.height, 0.06f);
  }
}

TEST(TrackerLikeness, FurnitureAloneGivesNone)
{
  // A low camera (0.54 m, pitched down 8 degrees, as in the issue) in a furnished room: chairs,
  // a table, a cabinet and a monitor on the table; no one there.
  synth::CameraModel camera;
  camera.height_above_floor = 0.54;
  camera.tilt = 0.14;
  synth::Room room;
  synth::Material wood;
  wood.base = synth::Rgb(0.5f, 0.35f, 0.2f);
  for (const auto& b : synth::Room::chair(2.2f, 0.6f, 3.1f, 0.46f, wood))
    room.boxes.push_back(b);
  for (const auto& b : synth::Room::chair(2.6f, -0.9f, 2.4f, 0.46f, wood))
    room.boxes.push_back(b);
  synth::Box table;  // top at 0.75 m
  table.center = Eigen::Vector3f(3.0f, 0.0f, 0.72f);
  table.half = Eigen::Vector3f(0.4f, 0.7f, 0.03f);
  table.material = wood;
  room.boxes.push_back(table);
  for (const float y : {-0.6f, 0.6f})
  {
    synth::Box leg;
    leg.center = Eigen::Vector3f(3.0f, y, 0.35f);
    leg.half = Eigen::Vector3f(0.35f, 0.03f, 0.35f);
    leg.material = wood;
    room.boxes.push_back(leg);
  }
  synth::Box monitor;  // 0.5 m on the table
  monitor.center = Eigen::Vector3f(3.2f, 0.1f, 1.0f);
  monitor.half = Eigen::Vector3f(0.03f, 0.3f, 0.22f);
  room.boxes.push_back(monitor);
  synth::Box cabinet;  // 1.9 m tall, against the left wall
  cabinet.center = Eigen::Vector3f(3.5f, 1.9f, 0.95f);
  cabinet.half = Eigen::Vector3f(0.3f, 0.35f, 0.95f);
  room.boxes.push_back(cabinet);
  const synth::SceneRenderer scene(camera, room);
  if (defaultHogClassifierFile().empty())
    GTEST_SKIP() << "the default HOG classifier is not found (see docs/tracker.md)";
  // With the tracker's defaults alone (no HOG) the 1.9 m cabinet is reported: HOG is what a real
  // sensor's configuration adds against furniture.
  PeopleTracker tracker(sensorParams());
  for (int k = 0; k < 5; ++k)
  {
    synth::FrameImages images;
    scene.render({}, 1, k, images);
    Cloud cloud;
    scene.toCloud(images, cloud);
    const TrackerResult r = tracker.update(cloud, 0.1 * k);
    EXPECT_EQ(r.detections, 0u) << "frame " << k;
    EXPECT_TRUE(r.people.empty()) << "frame " << k;
  }
}

namespace
{
/**
 * Tracks one synthetic actor's sample from its first frame: how many frames show the actor as a
 * tracked person (within 0.6 m of the pelvis on the floor), under how many ids, and how many other
 * people were reported.
 */
struct SampleTrack
{
  int frames = 0, seen = 0, others = 0;
  std::set<std::uint32_t> ids;
};

SampleTrack trackSample(const synth::SampleSpec& spec, const TrackerParams& params)
{
  const synth::SampleRenderer sample(spec);
  PeopleTracker tracker(params);
  SampleTrack out;
  out.frames = sample.frames();
  Cloud cloud;
  for (int i = 0; i < sample.frames(); ++i)
  {
    sample.render(i, cloud);
    const TrackerResult r = tracker.update(cloud, sample.stamp(i));
    const auto skeleton = sample.skeleton(i);
    // The torso joint in the camera frame (pelvis of the 15-joint skeleton: the mean of all joints
    // is close enough for a 0.6 m gate).
    Eigen::Vector3f centre = Eigen::Vector3f::Zero();
    for (const auto& j : skeleton.joints)
      centre += j;
    centre /= static_cast<float>(skeleton.joints.size());
    bool found = false;
    for (const auto& p : r.people)
    {
      const Eigen::Vector3f d = p.position - centre;
      if (std::hypot(d.x(), d.z()) < 0.6f)
      {
        found = true;
        out.ids.insert(p.id);
      }
      else
        ++out.others;
    }
    out.seen += found;
  }
  return out;
}

// Each (action, person) sample keeps one track id, is seen in 95 % of the frames after the first
// (at the deepest bend of a pick-up a few frames give no cluster above tracked_min_height: measured
// 3 of 122 and 124) and nobody else is reported.
void expectOneTrackThroughout(const std::vector<std::pair<std::string, std::string>>& samples,
                              const TrackerParams& params)
{
  for (const auto& [action, person] : samples)
  {
    SCOPED_TRACE(action + " " + person);
    synth::SampleSpec spec;
    spec.person = person;
    spec.action = action;
    const SampleTrack t = trackSample(spec, params);
    ASSERT_GT(t.frames, 20);
    EXPECT_EQ(t.ids.size(), 1u) << "the actor changed track id";
    EXPECT_GE(t.seen, (t.frames - 1) * 95 / 100) << "the actor was missed in " << t.frames - 1 - t.seen << " frames";
    EXPECT_EQ(t.others, 0);
  }
}
}  // namespace

TEST(TrackerPostures, BendingAndKickingPeopleKeepTheirTrack)
{
  if (defaultHogClassifierFile().empty())
    GTEST_SKIP() << "the default HOG classifier is not found (see docs/tracker.md)";
  // A real sensor's configuration: with the defaults alone (no HOG) the room's chair is reported too.
  expectOneTrackThroughout({ { "pick_up", "p01" }, { "pick_up", "p02" }, { "kick", "p03" } }, sensorParams());
}

TEST(TrackerLikeness, ARaisedHandLeavingTheImageKeepsThePerson)
{
  // MSR Action3D's high arm wave of subject 8 (real motion, the virtual Kinect's room and camera):
  // the hand rises above the image's top edge for most of the sequence. A top at the edge used to
  // mean "a wall cut by the image" and the performer was lost in 99 of 115 frames.
  synth::SampleSpec spec;
  spec.dataset = "msr";
  spec.person = "s08";
  spec.action = "high_arm_wave";
  spec.skeleton_file = test::dataDir() + "/msr_action3d_skeletons/a01_s08_e01_skeleton3D.txt";
  if (!test::fileExists(spec.skeleton_file))
    GTEST_SKIP() << "MSR Action3D skeletons absent: " << spec.skeleton_file;
  const SampleTrack t = trackSample(spec, TrackerParams());
  ASSERT_GT(t.frames, 100);
  // Measured: missed in 8 of 115 frames (the hand beside the head: its rows are not free on both
  // sides), and the waving arm split off as a second person in 6 (a raised hand's top is taken for
  // a second head: a known weakness of the head-based split, docs/tracker.md).
  EXPECT_GE(t.seen, (t.frames - 1) * 90 / 100) << "the performer was missed in " << t.frames - 1 - t.seen << " frames";
  EXPECT_LE(t.ids.size(), 2u);
  EXPECT_LE(t.others, t.frames / 10);
}

// BendingAndKickingPeopleKeepTheirTrack with the tracker's defaults (no HOG: what the tools, the demo and the synthetic data run).
TEST(TrackerPostures, BendingAndKickingPeopleKeepTheirTrackWithTheDefaults)
{
  expectOneTrackThroughout({ { "pick_up", "p01" }, { "pick_up", "p02" }, { "pick_up", "p05" }, { "kick", "p03" } },
                           TrackerParams());
}

// A raised or thrown arm gives the body a second "head" beside the real one, and the head-based
// split cut the thrower in two: before TrackerParams::split_max_distance, 8 of these 8 throws
// over the head (and 1 of 8 waves) changed track id (a second track confirmed on the arm's half).
TEST(TrackerPostures, AThrowOverTheHeadKeepsOneTrack)
{
  std::vector<std::pair<std::string, std::string>> samples;
  for (const char* person : { "p01", "p02", "p03", "p04" })
    samples.emplace_back("throw_over_head", person);
  expectOneTrackThroughout(samples, TrackerParams());
  TrackerParams off;
  off.split_max_distance = 0.0f;
  synth::SampleSpec spec;
  spec.person = "p01";
  spec.action = "throw_over_head";
  EXPECT_GT(trackSample(spec, off).ids.size(), 1u) << "the split this guards against no longer happens: revisit the test";
}
