// The tracker with its DEFAULT parameters in the virtual Kinect's cluttered rooms: a rendered person
// close in front of a wall is one detection, a chair alone is none, the ground seen in earlier frames
// is kept when furniture hides the floor; the walls it removes are the room's. (test_tracker_likeness.cpp has the same cases on the
// test camera's simple shapes, and the bending bodies.)
#include <action_flow/people_tracker.h>
#include "../../src/tracker/tracker_walls.h"
#include <action_flow/synth/clutter.h>
#include <action_flow/synth/scene.h>
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>
#include <pcl/filters/voxel_grid.h>

#include <algorithm>
#include <cmath>

using namespace action_flow;
using synth::Joint;

namespace
{
synth::Room emptyRoom()
{
  synth::Room room = synth::Room::lab(3);
  room.boxes.clear();
  return room;
}

/** The floor (world z = 0) in the camera's optical frame, normal up. */
Eigen::Vector4f floorInOptical(const synth::CameraModel& cam)
{
  const Eigen::Isometry3f w = cam.worldFromOptical();
  const Eigen::Vector3f n = w.linear().transpose() * Eigen::Vector3f::UnitZ();
  return Eigen::Vector4f(n.x(), n.y(), n.z(), static_cast<float>(cam.height_above_floor));
}

/** Frame @p i of a standing actor moved so that the torso stands at (x, y) of the world. */
synth::PosedBody standingAt(const synth::SampleRenderer& actor, int i, float x, float y)
{
  synth::PosedBody body = actor.posedBody(i, 1);
  const Eigen::Vector3f shift = Eigen::Vector3f(x, y, 0) - Eigen::Vector3f(body.joints[Joint::Torso].x(),
                                                                         body.joints[Joint::Torso].y(), 0);
  for (auto& j : body.joints.joints)
    j += shift;
  return body;
}

Cloud renderCloud(const synth::SceneRenderer& scene, const std::vector<synth::PosedBody>& bodies, int frame)
{
  synth::FrameImages im;
  scene.render(bodies, 7, frame, im);
  Cloud cloud;
  scene.toCloud(im, cloud);
  return cloud;
}

/** Six frames of @p scene (no person in it) give no detection and nobody. */
void expectNobodyIn(const synth::SceneRenderer& scene)
{
  PeopleTracker tracker;
  for (int k = 0; k < 6; ++k)
  {
    const TrackerResult r = tracker.update(renderCloud(scene, {}, k), 0.1 * k);
    EXPECT_EQ(r.detections, 0u) << "frame " << k;
    EXPECT_TRUE(r.people.empty()) << "frame " << k;
  }
}

synth::SampleSpec standing(const std::string& person)
{
  synth::SampleSpec spec;
  spec.person = person;
  spec.action = "standing";
  return spec;
}
}  // namespace

TEST(TrackerClutter, AWallCloseBehindARenderedPersonGivesOneDetectionThePerson)
{
  const synth::SampleRenderer actor(standing("p02"));
  for (const float gap : {0.2f, 0.5f, 1.0f})
  {
    SCOPED_TRACE("wall " + std::to_string(gap) + " m behind");
    synth::Room room = emptyRoom();
    room.back_wall = 3.0f + gap;  // beyond the Kinect's 4.5 m it would give no depth at all
    synth::CameraModel cam;
    const synth::SceneRenderer scene(cam, room);
    const Eigen::Isometry3f world = cam.worldFromOptical();
    PeopleTracker tracker;
    for (int k = 0; k < 8; ++k)
    {
      const TrackerResult r = tracker.update(renderCloud(scene, {standingAt(actor, k, 3.0f, 0.3f)}, k), 0.1 * k);
      if (k == 0)
        continue;
      EXPECT_EQ(r.detections, 1u) << "frame " << k;
      ASSERT_EQ(r.people.size(), 1u) << "frame " << k;
      EXPECT_LT(((world * r.people[0].position).head<2>() - Eigen::Vector2f(3.0f, 0.3f)).norm(), 0.3f);
    }
  }
}

TEST(TrackerClutter, AChairAloneGivesNone)
{
  synth::Material wood;
  wood.base = synth::Rgb(0.5f, 0.33f, 0.18f);
  int scenes = 0;
  for (const double height : {0.5, 1.1, 1.8})
    for (const double tilt : {-0.17, 0.1, 0.35})
      for (const float yaw : {3.14f, 2.2f})
      {
        SCOPED_TRACE("camera " + std::to_string(height) + " m, tilt " + std::to_string(tilt) + ", chair yaw " +
                     std::to_string(yaw));
        synth::Room room = emptyRoom();
        room.boxes = synth::Room::chair(2.0f + 0.6f * static_cast<float>(scenes % 3), 0.2f, yaw, 0.46f, wood);
        synth::CameraModel cam;
        cam.height_above_floor = height;
        cam.tilt = tilt;
        const synth::SceneRenderer scene(cam, room);
        expectNobodyIn(scene);
        ++scenes;
      }
}

TEST(TrackerClutter, AFloorHiddenByFurnitureAfterFramesThatShowedItKeepsTheGround)
{
  // A sideboard across the room, 1.3 m in front of the camera and 0.9 m high, hides the whole floor
  // (the lowest points then seen are on its front, 0.5 m up): first frames without it, then with it.
  const synth::SampleRenderer actor(standing("p04"));
  synth::CameraModel cam;
  const Eigen::Vector4f truth = floorInOptical(cam);
  synth::Room open = emptyRoom(), hidden = open;
  synth::Box sideboard;
  sideboard.center = Eigen::Vector3f(1.5f, 0.0f, 0.45f);
  sideboard.half = Eigen::Vector3f(0.22f, 2.5f, 0.45f);
  hidden.boxes.push_back(sideboard);
  const synth::SceneRenderer before(cam, open), after(cam, hidden);
  PeopleTracker tracker;
  for (int k = 0; k < 16; ++k)
  {
    const auto& scene = k < 4 ? before : after;
    const TrackerResult r = tracker.update(renderCloud(scene, {standingAt(actor, k, 3.2f, 0.0f)}, k), 0.1 * k);
    ASSERT_TRUE(r.ground_valid) << "frame " << k;
    const float angle = std::acos(std::min(1.0f, r.ground.head<3>().dot(truth.head<3>())));
    EXPECT_LT(angle, 0.03f) << "frame " << k;
    EXPECT_NEAR(r.ground[3], truth[3], 0.04f) << "frame " << k;
    if (k == 0)
      continue;
    ASSERT_EQ(r.people.size(), 1u) << "frame " << k;
    EXPECT_NEAR(r.people[0].height, actor.posedBody(k).shape.height, 0.12f) << "frame " << k;
  }
}

TEST(TrackerWalls, FindsTheRoomsWallsAndNoFurniture)
{
  // The lab room seen from 1.1 m: the back wall 4.3 m ahead and the left wall 2.3 m aside are in
  // view; a 1.9 m cabinet (0.8 m wide) and a chair are not walls.
  synth::Room room = emptyRoom();
  synth::Box cabinet;
  cabinet.center = Eigen::Vector3f(3.0f, -1.0f, 0.95f);
  cabinet.half = Eigen::Vector3f(0.3f, 0.4f, 0.95f);
  room.boxes.push_back(cabinet);
  synth::Material wood;
  for (const auto& b : synth::Room::chair(2.5f, 0.8f, 2.0f, 0.46f, wood))
    room.boxes.push_back(b);
  synth::CameraModel cam;
  cam.tilt = 0.05;
  const synth::SceneRenderer scene(cam, room);
  const Cloud cloud = renderCloud(scene, {}, 0);
  const Eigen::Isometry3f world = cam.worldFromOptical();
  const Eigen::Vector4f floor = floorInOptical(cam);
  Cloud above;
  for (const auto& p : cloud.points)
    if (std::isfinite(p.z) && floor.head<3>().dot(p.getVector3fMap()) + floor[3] > 0.05f)
      above.push_back(p);
  Cloud voxels;
  pcl::VoxelGrid<PointT> grid;
  grid.setInputCloud(above.makeShared());
  grid.setLeafSize(0.06f, 0.06f, 0.06f);
  grid.filter(voxels);
  const auto walls = findWalls(voxels, floor, Eigen::Vector3f::Zero());
  ASSERT_FALSE(walls.empty());
  bool back = false;
  for (const auto& w : walls)
  {
    // Each is one of the room's walls: it passes through two points of that wall in view (world),
    // within 5 cm.
    const auto through = [&](const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
      const Eigen::Isometry3f optical = world.inverse();
      return std::abs(w.head<3>().dot(optical * a) + w[3]) < 0.05f && std::abs(w.head<3>().dot(optical * b) + w[3]) < 0.05f;
    };
    const float x = room.back_wall;
    const bool is_back = through({x, 0.0f, 1.0f}, {x, 1.0f, 2.0f});
    const bool is_side = through({x - 0.5f, room.left_wall, 1.0f}, {x - 0.1f, room.left_wall, 2.0f}) ||
                         through({x - 0.5f, room.right_wall, 1.0f}, {x - 0.1f, room.right_wall, 2.0f});
    EXPECT_TRUE(is_back || is_side) << "not a wall of the room: " << w.transpose();
    back = back || is_back;
  }
  EXPECT_TRUE(back) << "the back wall was not found";
}

// A low camera sees the wall close behind a person only up to 1.9-2.05 m, not to the 2.1 m
// that tells a wall from a row of people: it is a wall because it goes on above the image's top edge.
// Without that, the person joined the wall's cluster and was missed (the clutter scenes' largest cause
// of misses).
TEST(TrackerClutter, AWallCutByTheImagesTopEdgeBehindAPersonFromALowCameraGivesThePerson)
{
  const synth::SampleRenderer actor(standing("p02"));
  for (const float gap : {0.2f, 0.3f})
    for (const double height : {0.65, 0.75})
    {
      SCOPED_TRACE("wall " + std::to_string(gap) + " m behind, camera " + std::to_string(height) + " m high");
      synth::Room room = emptyRoom();
      room.back_wall = 3.0f + gap;
      synth::CameraModel cam;
      cam.height_above_floor = height;
      cam.tilt = 0.05;  // pitched down 3 degrees: the person's head is in view
      const synth::SceneRenderer scene(cam, room);
      const Eigen::Isometry3f world = cam.worldFromOptical();
      // The wall's top in view is below 2.1 m (what this test is about).
      const Eigen::Vector3f top_ray = world.linear() * Eigen::Vector3f(0.0f, -static_cast<float>(cam.cy / cam.fy), 1.0f);
      ASSERT_LT(height + (room.back_wall - world.translation().x()) * top_ray.z() / top_ray.x(), 2.1);
      PeopleTracker tracker;
      int found = 0;
      for (int k = 0; k < 8; ++k)
      {
        const TrackerResult r = tracker.update(renderCloud(scene, {standingAt(actor, k, 3.0f, 0.3f)}, k), 0.1 * k);
        if (k == 0)
          continue;
        ASSERT_LE(r.people.size(), 1u) << "frame " << k;
        found += r.people.size() == 1 &&
                 ((world * r.people[0].position).head<2>() - Eigen::Vector2f(3.0f, 0.3f)).norm() < 0.3f;
      }
      EXPECT_EQ(found, 7);
    }
}

// What is not a body cannot start a person: a head-and-shoulders shape hanging in the air (0.55 m
// from its top to its bottom: a raised hand and forearm split off their body look so to the
// clustering), a post 0.12 m wide and 1.9 m tall (a sliver of a shelf's side seen edge-on).
TEST(TrackerClutter, AShapeInTheAirOrASliverStartsNoPerson)
{
  synth::Material wood;
  wood.base = synth::Rgb(0.5f, 0.33f, 0.18f);
  const auto box = [&](float y, float z, float half_y, float half_z) {
    synth::Box b;
    b.material = wood;
    b.center = Eigen::Vector3f(3.0f, y, z);
    b.half = Eigen::Vector3f(0.1f, half_y, half_z);
    return b;
  };
  for (const bool sliver : {false, true})
  {
    SCOPED_TRACE(sliver ? "a sliver" : "a shape in the air");
    synth::Room room = emptyRoom();
    room.back_wall = 5.5f;  // beyond the Kinect's depth: nothing behind
    if (sliver)
      room.boxes.push_back(box(0.2f, 0.95f, 0.06f, 0.95f));
    else
    {
      room.boxes.push_back(box(0.2f, 1.25f, 0.3f, 0.1f));    // shoulders, 1.15-1.35 m
      room.boxes.push_back(box(0.2f, 1.525f, 0.1f, 0.175f));  // a head above them, to 1.7 m
    }
    synth::CameraModel cam;
    const synth::SceneRenderer scene(cam, room);
    expectNobodyIn(scene);
  }
}

// A person stands beside a chair for 0.6 s and leaves the view; the chair stays. Runs the tracker
// over @p frames frames 0.1 s apart and returns the stamps at which a track was reported on the
// chair (after the person left); the person must have been tracked before leaving.
namespace
{
std::vector<double> stampsOnTheChair(const TrackerParams& params, int frames)
{
  const synth::SampleRenderer actor(standing("p03"));
  synth::Material wood;
  wood.base = synth::Rgb(0.5f, 0.33f, 0.18f);
  synth::Room room = emptyRoom();
  const Eigen::Vector2f person(3.0f, 0.3f), chair(3.0f, -0.25f);
  room.boxes = synth::Room::chair(chair.x(), chair.y(), 1.57f, 0.46f, wood);
  synth::CameraModel cam;
  const synth::SceneRenderer scene(cam, room);
  const Eigen::Isometry3f world = cam.worldFromOptical();
  PeopleTracker tracker(params);
  int on_person = 0;
  std::vector<double> on_chair;
  for (int k = 0; k < frames; ++k)
  {
    std::vector<synth::PosedBody> bodies;
    if (k < 6)
      bodies.push_back(standingAt(actor, k, person.x(), person.y()));
    const double stamp = 0.1 * k;
    for (const auto& p : tracker.update(renderCloud(scene, bodies, k), stamp).people)
    {
      const Eigen::Vector2f at = (world * p.position).head<2>();
      on_person += k < 6 && (at - person).norm() < 0.3f;
      if (k >= 6 && (at - chair).norm() < 0.3f)
        on_chair.push_back(stamp);
    }
  }
  EXPECT_GE(on_person, 4);  // the person was tracked before leaving
  return on_chair;
}
}  // namespace

// A person beside a chair leaves the view: their track does not move onto the chair (a weak
// detection, low like a bending body, but in other colours; TrackerParams::weak_max_colour_distance).
// With the colour test off, the same scene shows that it would: the track jumps to the chair and is
// reported there for as long as the chair stands.
TEST(TrackerClutter, APersonsTrackDoesNotMoveOntoTheChairBesideThemWhenTheyLeave)
{
  EXPECT_EQ(stampsOnTheChair(TrackerParams(), 16).size(), 0u);
  TrackerParams off;
  off.weak_max_colour_distance = 1.0f;
  EXPECT_GT(stampsOnTheChair(off, 16).size(), 5u) << "the scene no longer tests the colours: the chair is not taken for the person";
}

// The same scene with the colour test off, so that the track does move onto the chair (as it did on
// a stream where the chair's colours were close to the actor's clothes): a track continued only by
// clusters lower than min_height (the chair, 0.9 m) ends after low_lost_after (4 s), where it used
// to stay on the chair for as long as the chair stood.
TEST(TrackerClutter, ATrackLeftOnAChairEndsAfterLowLostAfter)
{
  TrackerParams params;
  params.weak_max_colour_distance = 1.0f;
  const std::vector<double> on = stampsOnTheChair(params, 80);
  ASSERT_FALSE(on.empty()) << "the scene no longer tests the rule: the track does not move onto the chair";
  // The person was last seen at 0.5 s.
  EXPECT_LE(on.back(), 0.5 + params.low_lost_after + 0.05) << "the track stayed on the chair";
  params.low_lost_after = 0.0;  // off
  const std::vector<double> off = stampsOnTheChair(params, 80);
  ASSERT_FALSE(off.empty());
  EXPECT_GE(off.back(), 7.9) << "without the rule the track should stay on the chair";
}

// A person scratching their head beside a shelf (clutter scene shelf_05 of seed 2, the scenes the
// tracker's cues were developed on): the hand at the head breaks the free-standing head test, which
// used to drop the person's detection, and their track (the person was found within 0.5 m in 37 of
// the 90 frames). A head that is not free now only keeps a new person from starting: the track goes
// on (77 of 90; the first frames confirm the track, and in 3 the track is beside them by 0.5-0.6 m).
TEST(TrackerClutter, AHandAtTheHeadBesideAShelfKeepsThePersonsTrack)
{
  const std::vector<synth::SampleSpec> specs = synth::clutterSamples(10, 2);
  const auto spec = std::find_if(specs.begin(), specs.end(), [](const synth::SampleSpec& s) { return s.name() == "shelf_05"; });
  ASSERT_NE(spec, specs.end());
  ASSERT_EQ(spec->action, "scratch_head");
  const synth::SampleRenderer sample(*spec);
  const Eigen::Isometry3f world = sample.camera().worldFromOptical();
  PeopleTracker tracker;
  synth::FrameImages im;
  Cloud cloud;
  int found = 0, others = 0;
  for (int i = 0; i < sample.frames(); ++i)
  {
    sample.renderImages(i, im);
    sample.scene().toCloud(im, cloud);
    const TrackerResult r = tracker.update(cloud, sample.stamp(i));
    const Eigen::Vector2f torso = sample.worldSkeleton(i)[Joint::Torso].head<2>();
    bool here = false;
    for (const auto& p : r.people)
      ((world * p.position).head<2>() - torso).norm() < 0.5f ? here = true : ++others;
    found += here;
  }
  EXPECT_GE(found, 70) << "of " << sample.frames() << " frames";
  EXPECT_LE(others, 5);
}
