// Rostest node for the nodelets, each test case run by its own .test file (--gtest_filter):
// each stage alone on hand-built input, lazy subscription, zero copy, the Dummy driver, bad input.
// This node is another process, so everything it reads or writes went through serialization.
#include "test_helpers.h"
#include "../core/scene.h"

#include <action_flow/ActionLabel.h>
#include <action_flow/Classify.h>
#include <action_flow/FrameDescriptorArray.h>
#include <action_flow/PersonFlowArray.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/ros/stage_types.h>

#include <gtest/gtest.h>
#include <nodelet/NodeletUnload.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <std_msgs/String.h>
#include <visualization_msgs/MarkerArray.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <action_flow/TrackedPeople.h>
#include <action_flow/ActionStateArray.h>
#include <diagnostic_msgs/DiagnosticArray.h>

#include <cmath>
#include <cstring>
#include <sstream>

using namespace action_flow;
using action_flow::test::Collector;
using action_flow::test::waitFor;

namespace
{
constexpr int kDescriptorSize = 192;

/** Counts /rosout messages of at least @p level containing @p text. */
class LogWatch
{
public:
  LogWatch(ros::NodeHandle& nh, std::string text, std::uint8_t level)
    : log_(nh, "/rosout", 1000), text_(std::move(text)), level_(level)
  {
  }
  std::size_t count() const
  {
    std::size_t n = 0;
    for (const auto& m : log_.messages())
      if (m->level >= level_ && m->msg.find(text_) != std::string::npos)
        ++n;
    return n;
  }

private:
  Collector<rosgraph_msgs::Log> log_;
  std::string text_;
  std::uint8_t level_;
};

FrameDescriptorArray descriptorFrame(std::uint32_t track, int axis, double stamp)
{
  FrameDescriptorArray m;
  m.header.stamp = ros::Time(stamp);
  m.header.frame_id = "camera_rgb_optical_frame";
  FrameDescriptor d;
  d.track_id = track;
  d.status = PersonFlow::FLOW;
  d.values.assign(kDescriptorSize, 0.0f);
  d.values[axis] = 1.0f;
  m.descriptors.push_back(d);
  return m;
}

/** Publishes @p n frames of track @p track whose descriptors are all e_axis, from @p t0 at 15 Hz. */
double publishTrack(ros::Publisher& pub, std::uint32_t track, int axis, int n, double t0)
{
  double t = t0;
  for (int i = 0; i < n; ++i, t += 1.0 / 15)
  {
    pub.publish(descriptorFrame(track, axis, t));
    ros::WallDuration(0.005).sleep();
  }
  return t;
}

void publishLost(ros::Publisher& pub, std::uint32_t track, double stamp)
{
  FrameDescriptorArray m;
  m.header.stamp = ros::Time(stamp);
  m.lost.push_back(track);
  pub.publish(m);
}

bool waitForSubscriber(const ros::Publisher& pub)
{
  return waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0);
}
}  // namespace

// ---- people tracker alone ------------------------------------------------------------------------
namespace
{
/** The person of the test scene: one track, its height and place (camera frame unless @p odom). */
void expectTheScenePerson(const Collector<TrackedPeople>& people, bool odom)
{
  const auto m = people.messages();
  ASSERT_GE(m.size(), 10u);
  std::set<std::uint32_t> ids;
  for (std::size_t i = m.size() - 5; i < m.size(); ++i)
  {
    EXPECT_EQ(m[i]->header.frame_id, odom ? "odom" : "camera_rgb_optical_frame");
    EXPECT_TRUE(m[i]->ground_valid);
    ASSERT_EQ(m[i]->people.size(), 1u) << "message " << i;
    const auto& p = m[i]->people[0];
    ids.insert(p.id);
    EXPECT_NEAR(p.height, test::kPersonHeight, 0.15);
    if (odom)  // camera 1.2 m above the odom origin looking along +x
    {
      EXPECT_NEAR(p.position.x, 2.5, 0.25);
      EXPECT_NEAR(p.position.y, 0.0, 0.25);
    }
    else
    {
      EXPECT_NEAR(p.position.x, 0.0, 0.25);
      EXPECT_NEAR(p.position.z, 2.5, 0.25);
    }
  }
  EXPECT_EQ(ids.size(), 1u) << "the track id changed";
}
}  // namespace

TEST(Tracker, HandBuiltSceneGivesOneTrackedPerson)
{
  ros::NodeHandle nh;
  Collector<TrackedPeople> people(nh, "people");
  Collector<PeopleClouds> clouds(nh, "person_clouds");
  ASSERT_TRUE(people.waitForCount(15, 20.0)) << "the tracker published " << people.size() << " messages";
  expectTheScenePerson(people, false);
  ASSERT_GT(clouds.size(), 0u);
  const auto last = clouds.messages().back();
  ASSERT_EQ(last->people.size(), 1u);
  ASSERT_TRUE(last->people[0].cloud);
  EXPECT_GT(last->people[0].cloud->size(), 500u);
}

TEST(Tracker, FixedFrameExpressesPeopleInIt)
{
  ros::NodeHandle nh;
  tf2_ros::StaticTransformBroadcaster broadcaster;
  geometry_msgs::TransformStamped t;
  t.header.stamp = ros::Time::now();
  t.header.frame_id = "odom";
  t.child_frame_id = "camera_rgb_optical_frame";
  t.transform.translation.z = 1.2;
  // optical axes in odom: x = -y_odom, y = -z_odom, z = +x_odom
  t.transform.rotation.x = -0.5;
  t.transform.rotation.y = 0.5;
  t.transform.rotation.z = -0.5;
  t.transform.rotation.w = 0.5;
  broadcaster.sendTransform(t);
  Collector<TrackedPeople> people(nh, "people");
  ASSERT_TRUE(people.waitForCount(15, 20.0)) << "the tracker published " << people.size() << " messages";
  expectTheScenePerson(people, true);
}

TEST(Tracker, BadCloudsAreReportedAndTheTrackerKeepsServing)
{
  ros::NodeHandle nh;
  LogWatch no_transform(nh, "no transform from 'no_such_frame'", rosgraph_msgs::Log::ERROR);
  Collector<TrackedPeople> empty(nh, "empty/people"), nan(nh, "nan/people"), unorganized(nh, "unorganized/people"),
      floorless(nh, "floorless/people"), wrong(nh, "wrong_frame/people"), back(nh, "time_back/people");
  for (auto* c : { &empty, &nan, &floorless })
    EXPECT_TRUE(c->waitForCount(5, 20.0)) << "a tracker stopped on bad input";
  for (auto* c : { &empty, &nan })
    for (const auto& m : c->messages())
      EXPECT_TRUE(m->people.empty());
  // Without NaN placeholders the same scene still shows its person.
  EXPECT_TRUE(waitFor([&] { const auto m = unorganized.messages(); return !m.empty() && m.back()->people.size() == 1; }, 20.0))
      << "no person in the unorganized scene";
  EXPECT_TRUE(waitFor([&] { return no_transform.count() > 0; }, 10.0)) << "no clear error for an unknown frame";
  EXPECT_EQ(wrong.size(), 0u) << "clouds in an unknown frame were used";
  bool reset = false;
  waitFor([&] { for (const auto& m : back.messages()) reset = reset || m->reset; return reset; }, 20.0);
  EXPECT_TRUE(reset) << "time going back did not reset the tracker";
  const std::size_t before = back.size();
  EXPECT_TRUE(back.waitForCount(before + 3, 5.0)) << "the tracker stopped after time went back";
}

namespace
{
// A good organized scene cloud on the wire, and malformed variants of it as a hostile or broken
// publisher in another process could send them.
sensor_msgs::PointCloud2 wireScene(std::uint32_t seq)
{
  const Cloud scene = test::renderScene(test::SceneOptions(), 0.5f);
  sensor_msgs::PointCloud2 m;
  pcl::toROSMsg(scene, m);
  m.header.frame_id = "camera_rgb_optical_frame";
  m.header.stamp = ros::Time(100.0 + 0.1 * seq);
  return m;
}

std::vector<sensor_msgs::PointCloud2> malformed(const sensor_msgs::PointCloud2& good)
{
  std::vector<sensor_msgs::PointCloud2> out(8, good);
  out[0].data.resize(good.data.size() + 4096);  // longer than width x height x point_step
  out[1].data.resize(100);                      // shorter
  out[2].width = 1000000;                       // claims a huge cloud
  out[3].point_step = 1u << 28;                 // reads far past each point
  out[4].row_step += 16;
  out[5].fields.clear();                        // no x/y/z
  out[6].fields[0].offset = good.point_step + 8;
  out[7].height = 0;
  out[7].width = 0;                             // empty but data left over
  return out;
}
}  // namespace

TEST(Tracker, MalformedWireCloudsAreDroppedAndTheNextGoodOneIsServed)
{
  ros::NodeHandle nh;
  LogWatch dropped(nh, "dropped a malformed point cloud", rosgraph_msgs::Log::ERROR);
  Collector<TrackedPeople> people(nh, "wire/people");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("wire/cloud", 50);
  ASSERT_TRUE(waitForSubscriber(pub));
  std::uint32_t seq = 0;
  for (int round = 0; round < 3; ++round)
    for (const auto& bad : malformed(wireScene(seq++)))
    {
      pub.publish(bad);
      ros::WallDuration(0.02).sleep();
    }
  EXPECT_TRUE(waitFor([&] { return dropped.count() > 0; }, 10.0)) << "no error for a malformed cloud";
  EXPECT_EQ(people.size(), 0u) << "a malformed cloud was tracked";
  // The manager survived: good clouds are tracked again.
  EXPECT_TRUE(waitFor(
      [&] {
        pub.publish(wireScene(seq++));
        return people.size() >= 3;
      },
      20.0))
      << "the tracker stopped serving after malformed clouds";
}

// ---- image guard in front of depth_image_proc ------------------------------------------------------
namespace
{
sensor_msgs::Image testImage(const std::string& encoding, int width, int height, int bytes, const ros::Time& stamp)
{
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.encoding = encoding;
  m.width = width;
  m.height = height;
  m.step = width * bytes;
  m.data.assign(m.step * height, 0);
  if (encoding == "32FC1")
    for (std::size_t i = 0; i + 4 <= m.data.size(); i += 4)
    {
      const float d = 2.0f;
      std::memcpy(&m.data[i], &d, 4);
    }
  return m;
}

sensor_msgs::CameraInfo testInfo(const ros::Time& stamp)
{
  sensor_msgs::CameraInfo m;
  m.header.stamp = stamp;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.width = 64;
  m.height = 48;
  m.K = { 52.5, 0, 31.5, 0, 52.5, 23.5, 0, 0, 1 };
  m.P = { 52.5, 0, 31.5, 0, 0, 52.5, 23.5, 0, 0, 0, 1, 0 };
  return m;
}
}  // namespace

TEST(ImageGuard, MalformedImagesNeverReachDepthImageProc)
{
  ros::NodeHandle nh;
  LogWatch dropped(nh, "dropped a", rosgraph_msgs::Log::ERROR);
  Collector<sensor_msgs::PointCloud2> clouds(nh, "points");
  ros::Publisher rgb = nh.advertise<sensor_msgs::Image>("rgb_in", 20), depth = nh.advertise<sensor_msgs::Image>("depth_in", 20),
                 info = nh.advertise<sensor_msgs::CameraInfo>("info_in", 20);
  ASSERT_TRUE(waitForSubscriber(rgb) && waitForSubscriber(depth) && waitForSubscriber(info));
  double t = 10.0;
  const auto frame = [&](const sensor_msgs::Image& c, const sensor_msgs::Image& d, const sensor_msgs::CameraInfo& i) {
    info.publish(i);
    rgb.publish(c);
    depth.publish(d);
    ros::WallDuration(0.03).sleep();
  };
  // A good camera_info first, then every kind of bad frame that kills depth_image_proc unguarded.
  for (int round = 0; round < 2; ++round)
  {
    const ros::Time s(t += 0.1);
    frame(testImage("rgb8", 64, 48, 3, s), testImage("32FC1", 64, 48, 4, s), testInfo(s));
    sensor_msgs::Image empty = testImage("32FC1", 64, 48, 4, ros::Time(t += 0.1));
    empty.data.clear();
    sensor_msgs::Image huge_step = testImage("32FC1", 64, 48, 4, ros::Time(t));
    huge_step.step = 1u << 30;
    const ros::Time s2(t += 0.1);
    frame(testImage("rgb8", 0, 0, 3, s2), empty, testInfo(s2));
    frame(testImage("rgb8", 64, 48, 3, ros::Time(t)), huge_step, testInfo(ros::Time(t)));
    const ros::Time s3(t += 0.1);
    frame(testImage("rgb8", 64, 48, 3, s3), testImage("32FC1", 64, 60, 4, s3), testInfo(s3));  // depth taller
    sensor_msgs::CameraInfo bad = testInfo(ros::Time(t += 0.1));
    bad.K[0] = std::nan("");
    frame(testImage("rgb8", 64, 48, 3, ros::Time(t)), testImage("32FC1", 64, 48, 4, ros::Time(t)), bad);
  }
  EXPECT_TRUE(waitFor([&] { return dropped.count() > 0; }, 10.0)) << "no error for a malformed image";
  // The manager and depth_image_proc survived: good frames become clouds.
  clouds.clear();
  EXPECT_TRUE(waitFor(
      [&] {
        const ros::Time s(t += 0.1);
        frame(testImage("rgb8", 64, 48, 3, s), testImage("32FC1", 64, 48, 4, s), testInfo(s));
        return clouds.size() >= 2;
      },
      20.0))
      << "no cloud from good images after malformed ones";
  for (const auto& c : clouds.messages())
    EXPECT_EQ(c->width * c->height, 64u * 48u);
}

// ---- flow stage alone ----------------------------------------------------------------------------
TEST(Flow, WavingForearmGivesFlowOnTheForearm)
{
  ros::NodeHandle nh;
  Collector<PeopleFlow> flow(nh, "flow");
  ASSERT_TRUE(flow.waitForCount(30, 15.0)) << "flow stage published " << flow.size() << " messages";
  // The elbow of the test scene in the camera frame; the forearm (0.3 m) turns about it.
  const Eigen::Vector3f elbow(0.45f, 0.06f, 2.5f);
  std::size_t vectors = 0, near_forearm = 0, frames_with_flow = 0;
  float fastest = 0.0f;
  const auto messages = flow.messages();
  for (std::size_t i = 0; i < messages.size(); ++i)
  {
    ASSERT_EQ(messages[i]->people.size(), 1u);
    const auto& p = messages[i]->people[0];
    EXPECT_EQ(p.info.id, 1u);
    if (i > 0)
      EXPECT_EQ(p.status, PeopleFlow::kFlow) << "message " << i;
    if (!p.flow || p.flow->empty())
      continue;
    ++frames_with_flow;
    for (const auto& f : *p.flow)
    {
      ++vectors;
      near_forearm += (f.position - elbow).norm() < 0.36f;
      EXPECT_GE(f.velocity.norm(), 0.3f - 1e-4f) << "slower than min_speed survived";
      fastest = std::max(fastest, f.velocity.norm());
    }
  }
  EXPECT_GE(frames_with_flow, 10u);
  EXPECT_GE(near_forearm, 0.8 * vectors) << near_forearm << " of " << vectors << " flow vectors on the forearm";
  // Forearm tip: 0.3 m x 0.9 rad x 2 pi x 0.8 Hz = 1.36 m/s at most.
  EXPECT_GT(fastest, 0.5f);
  EXPECT_LT(fastest, 2.5f);
}

TEST(Flow, LostTrackAndTimeGoingBackDropState)
{
  ros::NodeHandle nh;
  Collector<PeopleFlow> flow(nh, "flow");
  ASSERT_TRUE(flow.waitForCount(40, 15.0));
  bool saw_lost = false, saw_reset = false;
  const auto m = flow.messages();
  for (std::size_t i = 1; i < m.size(); ++i)
  {
    ASSERT_EQ(m[i]->people.size(), 1u);
    const auto& p = m[i]->people[0];
    if (!m[i]->lost.empty())
    {
      saw_lost = true;
      EXPECT_NE(m[i]->lost[0], p.info.id);
      EXPECT_EQ(p.status, PeopleFlow::kFirst) << "a new track must start without flow";
    }
    if (m[i]->reset)
    {
      saw_reset = true;
      EXPECT_LT(m[i]->header.stamp, m[i - 1]->header.stamp);
      EXPECT_EQ(p.status, PeopleFlow::kFirst) << "after time went back the state must be dropped";
      EXPECT_TRUE(!p.flow || p.flow->empty());
    }
    else if (m[i]->lost.empty() && m[i - 1]->lost.empty() && !m[i - 1]->reset &&
             m[i - 1]->people[0].info.id == p.info.id)
      EXPECT_EQ(p.status, PeopleFlow::kFlow) << "message " << i;
  }
  EXPECT_TRUE(saw_lost);
  EXPECT_TRUE(saw_reset);
}

TEST(Flow, BadPersonCloudsKeepTheStageServing)
{
  ros::NodeHandle nh;
  Collector<PeopleFlow> nan(nh, "nan/flow"), empty(nh, "empty/flow");
  ASSERT_TRUE(nan.waitForCount(5, 15.0)) << "the flow stage stopped on NaN-only person clouds";
  ASSERT_TRUE(empty.waitForCount(5, 15.0)) << "the flow stage stopped on empty person clouds";
  for (const auto& c : { &nan, &empty })
    for (const auto& m : c->messages())
      for (const auto& p : m->people)
        EXPECT_TRUE(!p.flow || p.flow->empty());
}

// ---- descriptor stage alone ------------------------------------------------------------------------
TEST(Descriptor, HandBuiltFlowGivesTheCoreDescriptor)
{
  ros::NodeHandle nh;
  Collector<FrameDescriptorArray> out(nh, "descriptors");
  ros::Publisher pub = nh.advertise<PersonFlowArray>("flow", 10);
  ASSERT_TRUE(waitForSubscriber(pub)) << "the descriptor stage did not subscribe to flow";

  action_flow::PersonFrame where;  // grid axes = the frame's axes, feet at the origin
  where.height = 1.75f;
  FlowVectors vectors = { { Eigen::Vector3f(0.3f, 1.0f, 0.1f), Eigen::Vector3f(1.0f, 0.0f, 0.0f) },
                          { Eigen::Vector3f(-0.3f, 0.5f, 0.0f), Eigen::Vector3f(0.0f, 2.0f, 0.0f) } };
  PeopleFlow in;
  in.header.stamp = ros::Time(100.0);
  in.header.frame_id = "camera_rgb_optical_frame";
  in.lost = { 3 };
  PeopleFlow::Person moving;
  moving.info.id = 5;
  moving.info.height = 1.75f;
  moving.info.frame = where;
  moving.status = PeopleFlow::kFlow;
  moving.flow = boost::make_shared<const FlowVectors>(vectors);
  PeopleFlow::Person first = moving;
  first.info.id = 6;
  first.status = PeopleFlow::kFirst;
  first.flow.reset();
  in.people = { moving, first };
  pub.publish(toMessage(in));
  ASSERT_TRUE(out.waitForCount(1, 5.0));

  const auto m = out.messages()[0];
  EXPECT_EQ(m->header.stamp, in.header.stamp);
  EXPECT_EQ(m->lost, in.lost);
  ASSERT_EQ(m->descriptors.size(), 2u);
  EXPECT_EQ(m->descriptors[0].track_id, 5u);
  ASSERT_EQ(m->descriptors[0].values.size(), static_cast<std::size_t>(kDescriptorSize));
  const Eigen::VectorXf expected = GridDescriptor().compute(vectors, where);
  int nonzero = 0;
  for (int i = 0; i < kDescriptorSize; ++i)
  {
    EXPECT_NEAR(m->descriptors[0].values[i], expected[i], 1e-6f) << "value " << i;
    nonzero += m->descriptors[0].values[i] != 0.0f;
  }
  EXPECT_EQ(nonzero, 2);  // two vectors along one axis each, in two different cubes
  EXPECT_NEAR(Eigen::Map<const Eigen::VectorXf>(m->descriptors[0].values.data(), kDescriptorSize).norm(), 1.0f, 1e-5f);
  // head: 1.75 m up the frame's y axis from the origin
  EXPECT_NEAR(m->descriptors[0].head.y, 1.75, 1e-5);
  EXPECT_EQ(m->descriptors[1].track_id, 6u);
  EXPECT_EQ(m->descriptors[1].status, PersonFlow::FIRST);
  EXPECT_TRUE(m->descriptors[1].values.empty());
}

// ---- classifier stage alone (model: "raise" = all frames e_0, "push" = all frames e_1, F = 30) ----
TEST(Classifier, SegmentedTrackEndServiceAndEndOfInput)
{
  ros::NodeHandle nh;
  Collector<ActionLabel> labels(nh, "labels");
  ros::Publisher pub = nh.advertise<FrameDescriptorArray>("descriptors", 200);
  ASSERT_TRUE(waitForSubscriber(pub)) << "the classifier did not subscribe to descriptors";

  // 1. A track ends: its whole sequence is classified.
  double t = publishTrack(pub, 7, 0, 12, 10.0);
  publishLost(pub, 7, t);
  ASSERT_TRUE(labels.waitForCount(1, 5.0));
  auto l = labels.messages()[0];
  EXPECT_EQ(l->track_id, 7u);
  EXPECT_EQ(l->label, "raise");
  EXPECT_NEAR(l->distance, 0.0f, 1e-3f);
  EXPECT_NEAR(l->margin, std::sqrt(2.0f * 30), 1e-3f);  // |e_0 - e_1| over 30 frames
  EXPECT_NEAR(l->window_start.toSec(), 10.0, 1e-6);
  EXPECT_NEAR(l->window_end.toSec(), 10.0 + 11.0 / 15, 1e-6);
  EXPECT_EQ(l->mode, ActionLabel::SEGMENTED);

  // 2. A service call classifies the open sequences.
  t = publishTrack(pub, 8, 1, 10, t + 0.1);
  ros::WallDuration(0.3).sleep();
  ros::ServiceClient client = nh.serviceClient<Classify>("classifier/classify");
  Classify srv;
  ASSERT_TRUE(client.call(srv));
  ASSERT_EQ(srv.response.labels.size(), 1u) << srv.response.message;
  EXPECT_EQ(srv.response.labels[0].track_id, 8u);
  EXPECT_EQ(srv.response.labels[0].label, "push");
  ASSERT_TRUE(labels.waitForCount(2, 5.0));

  // 3. Input stops: after end_of_input_timeout the open sequence is classified.
  t = publishTrack(pub, 9, 0, 10, t + 0.1);
  ASSERT_TRUE(labels.waitForCount(3, 5.0)) << "no label at the end of input";
  EXPECT_EQ(labels.messages()[2]->track_id, 9u);
  EXPECT_EQ(labels.messages()[2]->label, "raise");

  // 4. Time goes back within a track: what came before is dropped. 20 "raise" frames, then 8
  //    "push" frames stamped earlier: only the latter may count.
  t = publishTrack(pub, 10, 0, 20, t + 0.1);
  t = publishTrack(pub, 10, 1, 8, t - 5.0);
  publishLost(pub, 10, t);
  ASSERT_TRUE(labels.waitForCount(4, 5.0));
  EXPECT_EQ(labels.messages()[3]->track_id, 10u);
  EXPECT_EQ(labels.messages()[3]->label, "push");
  EXPECT_NEAR(labels.messages()[3]->distance, 0.0f, 1e-3f);
}

TEST(Classifier, OnlinePublishesEachStableLabelOnce)
{
  ros::NodeHandle nh;
  Collector<ActionLabel> labels(nh, "labels");
  ros::Publisher pub = nh.advertise<FrameDescriptorArray>("descriptors", 200);
  ASSERT_TRUE(waitForSubscriber(pub));
  double t = publishTrack(pub, 4, 1, 40, 50.0);
  ASSERT_TRUE(labels.waitForCount(1, 5.0));
  t = publishTrack(pub, 4, 0, 40, t);
  ASSERT_TRUE(labels.waitForCount(3, 5.0));
  ros::WallDuration(0.5).sleep();
  const auto all = labels.messages();
  // push, then push's end (ONLINE_END, its span) when raise takes over, then raise.
  ASSERT_EQ(all.size(), 3u) << "a stable label was published more than once";
  EXPECT_EQ(all[1]->mode, ActionLabel::ONLINE_END);
  EXPECT_EQ(all[1]->label, "push");
  EXPECT_GE(all[1]->window_end, all[0]->window_end);
  const std::vector<ActionLabel::ConstPtr> l = { all[0], all[2] };
  EXPECT_EQ(l[0]->label, "push");
  EXPECT_EQ(l[1]->label, "raise");
  for (const auto& m : l)
  {
    EXPECT_EQ(m->mode, ActionLabel::ONLINE);
    EXPECT_EQ(m->track_id, 4u);
    const double span = (m->window_end - m->window_start).toSec();
    EXPECT_GE(span, 0.8 - 1e-6);  // min_coverage x window
    EXPECT_LE(span, 1.0 + 1e-6);  // window
  }
}

TEST(Classifier, MissingCorruptOrMismatchedModelIsReportedAndTheRestRuns)
{
  ros::NodeHandle nh;
  struct Case
  {
    std::string name, expect;
  };
  const std::vector<Case> cases = { { "missing", "does not exist" },
                                    { "corrupt", "checksum mismatch" },
                                    { "mismatch", "flow/k: model 50, runtime 30" } };
  std::vector<std::unique_ptr<Collector<ActionStates>>> states;
  for (const auto& c : cases)
    states.push_back(std::make_unique<Collector<ActionStates>>(nh, c.name + "/states"));
  ros::Publisher pub = nh.advertise<FrameDescriptorArray>("descriptors", 200);
  // The three classifiers share one connection (one process), so wait for their states instead.
  ASSERT_TRUE(waitForSubscriber(pub));
  double t = 1.0;
  const bool all_serving = waitFor(
      [&] {
        t = publishTrack(pub, 3, 0, 2, t);
        for (const auto& s : states)
          if (s->size() < 10)
            return false;
        return true;
      },
      10.0);
  EXPECT_TRUE(all_serving) << "a classifier without a usable model stopped publishing its per-frame state";
  for (std::size_t i = 0; i < cases.size(); ++i)
  {
    ros::ServiceClient client = nh.serviceClient<Classify>("classifier_" + cases[i].name + "/classify");
    Classify srv;
    ASSERT_TRUE(client.call(srv)) << cases[i].name << ": the classifier is not serving";
    EXPECT_NE(srv.response.message.find("not classifying"), std::string::npos) << srv.response.message;
    EXPECT_NE(srv.response.message.find(cases[i].expect), std::string::npos) << srv.response.message;
    EXPECT_TRUE(srv.response.labels.empty());
  }
}

// ---- lazy subscription ---------------------------------------------------------------------------
TEST(Lazy, NobodyOnTheOutputsMeansNoUpstreamSubscription)
{
  ros::NodeHandle nh, pnh("~");
  std::vector<std::string> upstream;
  ASSERT_TRUE(pnh.getParam("upstream", upstream));
  auto idle = [&] {
    for (const auto& t : upstream)
      if (!test::subscribersOf(t).empty())
        return false;
    return true;
  };
  auto busy = [&] {
    for (const auto& t : upstream)
      if (test::subscribersOf(t).empty())
        return false;
    return true;
  };
  ros::WallDuration(1.0).sleep();  // every nodelet loaded
  EXPECT_TRUE(idle()) << "with nobody listening to labels, a stage subscribed upstream";
  {
    Collector<ActionLabel> labels(nh, "labels");
    EXPECT_TRUE(waitFor(busy, 5.0)) << "a listener on labels did not wake the stages up";
    labels.shutdown();
  }
  EXPECT_TRUE(waitFor(idle, 5.0)) << "the stages kept their subscriptions after the listener left";
}

// ---- zero copy -------------------------------------------------------------------------------------
TEST(ZeroCopy, EveryStageReceivesThePublishedObject)
{
  ros::NodeHandle nh, pnh("~");
  std::vector<std::string> links;
  ASSERT_TRUE(pnh.getParam("links", links));
  Collector<std_msgs::String> report(nh, "probe/report");
  auto counts = [&](const std::string& link, int& same, int& other) {
    const auto m = report.messages();
    if (m.empty())
      return false;
    const std::string& r = m.back()->data;
    const auto at = r.find(link + " ");
    if (at == std::string::npos)
      return false;
    std::istringstream in(r.substr(at + link.size()));
    return static_cast<bool>(in >> same >> other);
  };
  auto enough = [&] {
    for (const auto& l : links)
    {
      int same = 0, other = 0;
      if (!counts(l, same, other) || same < 10)
        return false;
    }
    return true;
  };
  EXPECT_TRUE(waitFor(enough, 20.0)) << (report.size() ? report.messages().back()->data : "no report");
  ASSERT_GT(report.size(), 0u);
  for (const std::string l : { "cloud>person_clouds", "person_clouds>flow", "flow>descriptors", "descriptors>states" })
  {
    int same = 0, other = 0;
    ASSERT_TRUE(counts(l, same, other)) << report.messages().back()->data;
    EXPECT_EQ(other, 0) << l << ": a stage received a copy, not the published object";
  }
}

TEST(ZeroCopy, TheProbeSeesACopyWhenAStageRunsInAnotherProcess)
{
  // The flow stage runs as a standalone node here: what it receives was serialized and rebuilt,
  // so its output's source is not the object the previous stage published.
  ros::NodeHandle nh;
  Collector<std_msgs::String> report(nh, "probe/report");
  auto copies = [&] {
    if (report.size() == 0)
      return 0;
    const std::string r = report.messages().back()->data;
    std::istringstream in(r.substr(r.find("person_clouds>flow ") + 19));
    int same = -1, other = -1;
    in >> same >> other;
    return same == 0 ? other : -1;
  };
  EXPECT_TRUE(waitFor([&] { return copies() >= 10; }, 20.0))
      << (report.size() ? report.messages().back()->data : "no report");
}

// ---- rviz markers ----------------------------------------------------------------------------------
TEST(Markers, FlowArrowsOnTheForearmAndTheLabelAboveTheHead)
{
  ros::NodeHandle nh;
  Collector<visualization_msgs::MarkerArray> markers(nh, "markers");
  bool arrows = false, label = false;
  const Eigen::Vector3f elbow(0.45f, 0.06f, 2.5f);
  waitFor(
      [&] {
        for (const auto& a : markers.messages())
          for (const auto& m : a->markers)
          {
            EXPECT_EQ(m.header.frame_id, "camera_rgb_optical_frame");
            if (m.ns == "flow" && m.type == visualization_msgs::Marker::LINE_LIST && m.points.size() >= 2)
            {
              arrows = true;
              EXPECT_EQ(m.points.size() % 2, 0u);
              EXPECT_LT((Eigen::Vector3f(m.points[0].x, m.points[0].y, m.points[0].z) - elbow).norm(), 0.5f)
                  << "a flow arrow off the forearm";
            }
            if (m.ns == "label" && m.type == visualization_msgs::Marker::TEXT_VIEW_FACING)
            {
              label = true;
              EXPECT_EQ(m.text.rfind(std::to_string(m.id) + ": ", 0), 0u) << m.text;
              // the head's top is 1.75 - 1.2 = 0.55 m above the camera (y down); the label 0.2 m higher
              EXPECT_NEAR(m.pose.position.y, -0.75, 0.15);
              EXPECT_NEAR(m.pose.position.z, 2.5, 0.3);
            }
          }
        return arrows && label;
      },
      20.0);
  EXPECT_TRUE(arrows) << "no flow arrows";
  EXPECT_TRUE(label) << "no label marker";
}

// ---- diagnostics -----------------------------------------------------------------------------------
TEST(Diagnostics, EachStageReportsItsRatesPeopleAndModel)
{
  ros::NodeHandle nh;
  Collector<action_flow::ActionStateArray> states(nh, "states", 10);  // a listener: the lazy chain runs
  Collector<diagnostic_msgs::DiagnosticArray> diagnostics(nh, "/diagnostics", 200);
  // The latest status of each stage whose name contains the key.
  const auto latest = [&](const std::string& key) {
    diagnostic_msgs::DiagnosticStatus found;
    for (const auto& a : diagnostics.messages())
      for (const auto& st : a->status)
        if (st.name.find(key) != std::string::npos)
          found = st;
    return found;
  };
  const auto value = [](const diagnostic_msgs::DiagnosticStatus& st, const std::string& key) {
    for (const auto& kv : st.values)
      if (kv.key == key)
        return kv.value;
    return std::string("(none)");
  };
  // Rates are per report (about a second); wait for one taken while the chain ran throughout.
  ASSERT_TRUE(states.waitForCount(20, 20.0)) << "the chain did not run";
  const std::size_t reports = diagnostics.size();
  ASSERT_TRUE(waitFor([&] { return diagnostics.size() >= reports + 10; }, 10.0)) << "no /diagnostics";
  const auto tracker = latest("people tracker");
  EXPECT_EQ(tracker.level, diagnostic_msgs::DiagnosticStatus::OK) << tracker.message;
  EXPECT_EQ(value(tracker, "tracked people"), "1");
  const double in = std::stod(value(tracker, "input rate (Hz)")), out = std::stod(value(tracker, "output rate (Hz)"));
  EXPECT_NEAR(in, 15.0, 4.0) << "the scene is published at 15 Hz";
  EXPECT_NEAR(out, in, 2.0);
  EXPECT_GE(std::stod(value(tracker, "latency max (ms)")), std::stod(value(tracker, "latency mean (ms)")));
  for (const std::string stage : { "flow", "descriptor" })
    EXPECT_NEAR(std::stod(value(latest(": " + stage), "output rate (Hz)")), 15.0, 4.0) << stage;
  const auto classifier = latest("classifier");
  EXPECT_EQ(classifier.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(classifier.message.find("no model"), std::string::npos) << classifier.message;
  EXPECT_NE(classifier.message.find("/nonexistent/model.afm"), std::string::npos) << classifier.message;
}

// ---- driver ----------------------------------------------------------------------------------------
TEST(Driver, DummyDevicePublishesImagesCloudsAndFramesWhileSubscribed)
{
  ros::NodeHandle nh;
  LogWatch started(nh, "streaming from", rosgraph_msgs::Log::INFO);
  LogWatch stopped(nh, "streams stopped", rosgraph_msgs::Log::INFO);
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(started.count(), 0u) << "streams ran with nobody subscribed";
  {
    Collector<sensor_msgs::PointCloud2> clouds(nh, "camera/depth_registered/points", 5);
    Collector<sensor_msgs::CameraInfo> info(nh, "camera/rgb/camera_info", 5);
    Collector<sensor_msgs::Image> rgb(nh, "camera/rgb/image_raw", 5);
    Collector<sensor_msgs::Image> depth(nh, "camera/depth_registered/image_raw", 5);
    ASSERT_TRUE(clouds.waitForCount(5, 10.0)) << "no clouds from the Dummy device";
    ASSERT_TRUE(info.waitForCount(1, 5.0));
    ASSERT_TRUE(rgb.waitForCount(1, 5.0));
    ASSERT_TRUE(depth.waitForCount(1, 5.0));
    const auto c = clouds.messages().back();
    EXPECT_EQ(c->width, 320u);
    EXPECT_EQ(c->height, 240u);
    EXPECT_EQ(c->header.frame_id, "camera_rgb_optical_frame");
    std::size_t finite = 0;
    for (sensor_msgs::PointCloud2ConstIterator<float> z(*c, "z"); z != z.end(); ++z)
      finite += std::isfinite(*z);
    EXPECT_GT(finite, 0u) << "the Dummy device's depth gave no point";
    const auto i = info.messages().back();
    EXPECT_EQ(i->header.frame_id, c->header.frame_id);
    EXPECT_NEAR(i->K[0], 300.0, 1e-6) << "the calibration file's focal length, not the Kinect default (262.5)";
    EXPECT_NEAR(i->P[5], 300.0, 1e-6);
    const auto r = rgb.messages().back();
    EXPECT_EQ(r->encoding, "rgb8");
    EXPECT_EQ(r->width, 320u);
    EXPECT_EQ(r->step, 3u * 320u);
    EXPECT_EQ(r->header.frame_id, c->header.frame_id);
    // A cloud and the depth image of the same frame (one stamp).
    sensor_msgs::ImageConstPtr d;
    sensor_msgs::PointCloud2ConstPtr c_of_d;
    ASSERT_TRUE(waitFor(
        [&] {
          for (const auto& cm : clouds.messages())
            for (const auto& m : depth.messages())
              if (m->header.stamp == cm->header.stamp)
                d = m, c_of_d = cm;
          return bool(d);
        },
        5.0))
        << "no depth image with a cloud's stamp";
    EXPECT_EQ(d->encoding, "16UC1");
    ASSERT_EQ(d->data.size(), 2u * 320u * 240u);
    // Each pixel's depth and its cloud point agree, and x follows the calibration's fx and cx.
    std::size_t compared = 0;
    sensor_msgs::PointCloud2ConstIterator<float> x(*c_of_d, "x"), z(*c_of_d, "z");
    for (std::size_t k = 0; k < 320u * 240u; ++k, ++x, ++z)
    {
      std::uint16_t mm = 0;
      std::memcpy(&mm, &d->data[2 * k], 2);
      ASSERT_EQ(std::isfinite(*z), mm > 0) << "pixel " << k;
      if (mm == 0)
        continue;
      ASSERT_NEAR(*z, mm * 0.001f, 1e-4) << "pixel " << k;
      ASSERT_NEAR(*x, (double(k % 320) - 159.5) * *z / 300.0, 1e-4) << "pixel " << k;
      ++compared;
    }
    EXPECT_GT(compared, 0u);
    tf2_ros::Buffer buffer;
    tf2_ros::TransformListener listener(buffer);
    std::string error;
    EXPECT_TRUE(buffer.canTransform("camera_link", "camera_rgb_optical_frame", ros::Time(0), ros::Duration(3.0), &error))
        << error;
    clouds.shutdown();
    info.shutdown();
    rgb.shutdown();
    depth.shutdown();
  }
  EXPECT_TRUE(waitFor([&] { return started.count() > 0; }, 3.0));
  EXPECT_TRUE(waitFor([&] { return stopped.count() > 0; }, 5.0)) << "streams kept running after the last subscriber left";
}

TEST(Driver, AbsentDeviceIsRetriedAndTheNodeletUnloads)
{
  ros::NodeHandle nh;
  LogWatch errors(nh, "cannot open OpenNI2 device", rosgraph_msgs::Log::ERROR);
  Collector<sensor_msgs::PointCloud2> clouds(nh, "camera/depth_registered/points", 5);
  EXPECT_TRUE(waitFor([&] { return errors.count() >= 2; }, 8.0)) << "no repeated clear error for an absent device";
  ros::ServiceClient unload = nh.serviceClient<nodelet::NodeletUnload>("manager/unload_nodelet");
  nodelet::NodeletUnload srv;
  srv.request.name = "/camera/driver";
  const auto before = ros::WallTime::now();
  ASSERT_TRUE(unload.call(srv));
  EXPECT_TRUE(srv.response.success);
  EXPECT_LT((ros::WallTime::now() - before).toSec(), 3.0) << "the driver's thread did not stop promptly";
  EXPECT_EQ(clouds.size(), 0u);
}

// kinect.launch with backend:=freenect on a fakenect dump that synth wrote (an actor waving, 60
// frames): the driver replays it, the tracker finds the person, and the classifier labels them when
// the dump ends (segmented mode, with the two-class posture_flow test model).
TEST(Kinect, FakenectDumpThroughKinectLaunchGivesLabels)
{
  ros::NodeHandle nh;
  LogWatch ended(nh, "has no more frames", rosgraph_msgs::Log::INFO);
  Collector<action_flow::TrackedPeople> people(nh, "action_flow/people", 100);
  Collector<action_flow::ActionLabel> labels(nh, "action_flow/labels", 10);
  Collector<sensor_msgs::PointCloud2> clouds(nh, "camera/depth_registered/points", 2);
  Collector<sensor_msgs::CameraInfo> info(nh, "camera/rgb/camera_info", 2);
  ASSERT_TRUE(clouds.waitForCount(1, 30.0)) << "no cloud from the fakenect dump";
  ASSERT_TRUE(info.waitForCount(1, 5.0));
  EXPECT_NEAR(info.messages().front()->K[0], 525.0, 1e-6) << "the Kinect v1's colour camera";
  info.shutdown();
  const auto c = clouds.messages().front();
  clouds.shutdown();
  EXPECT_EQ(c->width, 640u);
  EXPECT_EQ(c->height, 480u);
  std::size_t finite = 0;
  for (sensor_msgs::PointCloud2ConstIterator<float> z(*c, "z"); z != z.end(); ++z)
    finite += std::isfinite(*z) && *z > 0.3f && *z < 10.0f;
  EXPECT_GT(finite, 640u * 480u / 2) << "the room's depth did not come through";
  ASSERT_TRUE(labels.waitForCount(1, 60.0)) << "no label after the dump ended";
  EXPECT_GT(ended.count(), 0u) << "the driver did not report the end of the dump";
  bool seen = false;
  for (const auto& p : people.messages())
    for (const auto& person : p->people)
      seen |= person.id == labels.messages().front()->track_id;
  EXPECT_TRUE(seen) << "the labelled track was never among the tracked people";
  const std::string label = labels.messages().front()->label;
  EXPECT_TRUE(label == "still" || label == "moving") << label;
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_stages");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
