// Rostest node for the annotator nodelet: a hand-built image, camera_info and person cloud from this
// process (so through serialization), or the test scene through the people tracker in the manager.
// The box must lie where the person's points project; bad images give no output and no crash.
#include "test_helpers.h"

#include <action_flow/ActionStateArray.h>
#include <action_flow/TrackedPeople.h>
#include <action_flow/ros/stage_types.h>

#include <gtest/gtest.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>

using namespace action_flow;
using action_flow::test::Collector;
using action_flow::test::waitFor;

namespace
{
constexpr int kWidth = 320, kHeight = 240;
constexpr double kF = 262.5, kCx = 159.5, kCy = 119.5;
// The background: rgb8 on input, so (kB, kG, kR) in the bgr8 output.
constexpr std::uint8_t kR = 200, kG = 100, kB = 50;

using Bgr = std::array<std::uint8_t, 3>;

/** The annotator's colour of track @p id (BGR), as its palette has it. */
Bgr trackColour(std::uint32_t id)
{
  static const Bgr palette[] = { { 0, 255, 0 },   { 255, 128, 0 }, { 0, 128, 255 }, { 255, 0, 255 },
                                 { 0, 255, 255 }, { 255, 255, 0 }, { 128, 0, 255 }, { 0, 0, 255 } };
  return palette[id % 8];
}

Bgr pixel(const sensor_msgs::Image& m, int u, int v)
{
  const std::uint8_t* p = &m.data[v * m.step + 3 * u];
  return { p[0], p[1], p[2] };
}

bool background(const sensor_msgs::Image& m, int u, int v)
{
  return pixel(m, u, v) == Bgr{ kB, kG, kR };
}

sensor_msgs::Image colourImage(const std::string& encoding, int width, int height, const ros::Time& stamp)
{
  sensor_msgs::Image m;
  m.header.stamp = stamp;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.encoding = encoding;
  m.width = width;
  m.height = height;
  const int bytes = encoding == "32FC1" ? 4 : encoding == "mono8" ? 1 : 3;
  m.step = width * bytes;
  m.data.resize(m.step * height);
  for (std::size_t i = 0; i + 2 < m.data.size(); i += 3)
  {
    m.data[i] = kR;
    m.data[i + 1] = kG;
    m.data[i + 2] = kB;
  }
  return m;
}

sensor_msgs::CameraInfo cameraInfo()
{
  sensor_msgs::CameraInfo m;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.width = kWidth;
  m.height = kHeight;
  m.K = { kF, 0, kCx, 0, kF, kCy, 0, 0, 1 };
  m.P = { kF, 0, kCx, 0, 0, kF, kCy, 0, 0, 0, 1, 0 };
  return m;
}

/** A box-shaped person (x, y, z extents in the camera's optical frame) and its projected extent. */
struct HandBuiltPerson
{
  float x0 = -0.30f, x1 = 0.25f, y0 = -0.60f, y1 = 0.80f, z0 = 2.4f, z1 = 2.6f;
  std::uint32_t id = 3;

  PeopleClouds frame(const ros::Time& stamp) const
  {
    PeopleClouds out;
    out.header.stamp = stamp;
    out.header.frame_id = "camera_rgb_optical_frame";
    auto cloud = boost::make_shared<Cloud>();
    for (float x = x0; x <= x1 + 1e-4f; x += 0.05f)
      for (float y = y0; y <= y1 + 1e-4f; y += 0.05f)
        for (float z : { z0, z1 })
        {
          PointT p;
          p.x = x;
          p.y = y;
          p.z = z;
          p.r = p.g = p.b = 128;
          cloud->push_back(p);
        }
    cloud->header = pcl_conversions::toPCL(out.header);
    PeopleClouds::Person p;
    p.info.id = id;
    p.info.height = y1 - y0;
    p.info.position = Eigen::Vector3f(0.5f * (x0 + x1), 0.5f * (y0 + y1), 0.5f * (z0 + z1));
    p.info.frame = PersonFrame::fromGround(p.info.position, Eigen::Vector4f(0, -1, 0, y1), p.info.height,
                                           p.info.position);
    p.cloud = cloud;
    out.people.push_back(p);
    return out;
  }
  // The nearest face (z0) gives the widest extent.
  int u0() const { return static_cast<int>(std::lround(kF * x0 / z0 + kCx)); }
  int u1() const { return static_cast<int>(std::lround(kF * x1 / z0 + kCx)); }
  int v0() const { return static_cast<int>(std::lround(kF * y0 / z0 + kCy)); }
  int v1() const { return static_cast<int>(std::lround(kF * y1 / z0 + kCy)); }
};

/** Counts /rosout messages of at least ERROR containing @p text. */
class ErrorWatch
{
public:
  ErrorWatch(ros::NodeHandle& nh, std::string text) : log_(nh, "/rosout", 1000), text_(std::move(text)) {}
  std::size_t count() const
  {
    std::size_t n = 0;
    for (const auto& m : log_.messages())
      n += m->level >= rosgraph_msgs::Log::ERROR && m->msg.find(text_) != std::string::npos;
    return n;
  }

private:
  Collector<rosgraph_msgs::Log> log_;
  std::string text_;
};

/** Publishers of the annotator's inputs, connected. */
struct Inputs
{
  explicit Inputs(ros::NodeHandle& nh)
    : image(nh.advertise<sensor_msgs::Image>("rgb/image", 20)),
      info(nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 20, true)),
      people(nh.advertise<PeopleClouds>("person_clouds", 20)),
      states(nh.advertise<ActionStateArray>("states", 20))
  {
  }
  bool connected() const
  {
    return image.getNumSubscribers() > 0 && info.getNumSubscribers() > 0 && people.getNumSubscribers() > 0 &&
           states.getNumSubscribers() > 0;
  }
  ros::Publisher image, info, people, states;
};
}  // namespace

TEST(Annotator, SubscribesToItsInputsOnlyWhileWatched)
{
  const std::vector<std::string> inputs = { "/rgb/image", "/rgb/camera_info", "/person_clouds", "/states" };
  auto subscribed = [&](bool all) {
    for (const auto& t : inputs)
      if (test::subscribersOf(t).empty() == all)
        return false;
    return true;
  };
  ros::WallDuration(1.0).sleep();  // the annotator is loaded
  EXPECT_TRUE(subscribed(false)) << "with nobody on annotated/image, the annotator subscribed to an input";
  {
    ros::NodeHandle nh;
    Collector<sensor_msgs::Image> out(nh, "annotated/image");
    EXPECT_TRUE(waitFor([&] { return subscribed(true); }, 5.0)) << "a listener did not wake the annotator up";
    out.shutdown();
  }
  EXPECT_TRUE(waitFor([&] { return subscribed(false); }, 5.0))
      << "the annotator kept an input subscription after the last listener left";
}

TEST(Annotator, BoxIsDrawnWhereThePersonsPointsProject)
{
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> out(nh, "annotated/image");
  Collector<sensor_msgs::PointCloud2> points(nh, "annotated/people_points");
  Inputs in(nh);
  ASSERT_TRUE(waitFor([&] { return in.connected(); }, 10.0)) << "the annotator did not subscribe to its inputs";
  in.info.publish(cameraInfo());
  ActionStateArray states;
  ActionState s;
  s.track_id = 3;
  s.label = "wave";
  states.tracks.push_back(s);
  const HandBuiltPerson person;
  double t = 100.0;
  ASSERT_TRUE(waitFor(
      [&] {
        const ros::Time stamp(t += 0.1);
        states.header.stamp = stamp;
        in.states.publish(states);
        in.image.publish(colourImage("rgb8", kWidth, kHeight, stamp));
        in.people.publish(person.frame(stamp));
        ros::WallDuration(0.05).sleep();
        return out.size() > 0;
      },
      10.0))
      << "no annotated image";
  const auto m = out.messages().back();
  ASSERT_EQ(m->encoding, "bgr8");
  ASSERT_EQ(m->width, unsigned(kWidth));
  ASSERT_EQ(m->height, unsigned(kHeight));
  ASSERT_EQ(m->step, 3u * kWidth);
  EXPECT_EQ(m->header.frame_id, "camera_rgb_optical_frame");
  EXPECT_GT(m->header.stamp.toSec(), 100.0);

  const int u0 = person.u0(), u1 = person.u1(), v0 = person.v0(), v1 = person.v1();
  ASSERT_GT(u0, 10);
  ASSERT_LT(u1, kWidth - 10);
  ASSERT_GT(v0, 30);
  ASSERT_LT(v1, kHeight - 10);
  const Bgr colour = trackColour(person.id);
  // Each side of the expected box carries the box's colour within 2 pixels of it.
  auto near = [&](int u, int v, int du, int dv) {
    for (int k = -2; k <= 2; ++k)
      if (pixel(*m, u + k * du, v + k * dv) == colour)
        return true;
    return false;
  };
  int misses = 0;
  for (int u = u0 + 3; u <= u1 - 3; ++u)
    misses += !near(u, v0, 0, 1) + !near(u, v1, 0, 1);
  for (int v = v0 + 3; v <= v1 - 3; ++v)
    misses += !near(u0, v, 1, 0) + !near(u1, v, 1, 0);
  EXPECT_EQ(misses, 0) << "the box is not at u " << u0 << ".." << u1 << ", v " << v0 << ".." << v1;
  // Nothing is drawn away from the box and the label above its top left corner.
  int stray = 0, inside = 0;
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
    {
      const bool on_box = u >= u0 - 3 && u <= u1 + 3 && v >= v0 - 3 && v <= v1 + 3;
      const bool on_label = u >= u0 - 3 && u <= u0 + 120 && v >= v0 - 30 && v <= v0;
      const bool in_box = u > u0 + 3 && u < u1 - 3 && v > v0 + 3 && v < v1 - 3;
      if (!on_box && !on_label)
        stray += !background(*m, u, v);
      if (in_box)
        inside += !background(*m, u, v);
    }
  EXPECT_EQ(stray, 0) << "pixels changed away from the person";
  EXPECT_EQ(inside, 0) << "the box is filled or misplaced";
  // The label: a filled patch of the box's colour with dark text above the box.
  int label = 0, text = 0;
  for (int v = std::max(0, v0 - 30); v < v0; ++v)
    for (int u = u0; u <= u0 + 120 && u < kWidth; ++u)
    {
      label += pixel(*m, u, v) == colour;
      text += pixel(*m, u, v)[0] < 100 && pixel(*m, u, v)[1] < 100 && pixel(*m, u, v)[2] < 100;
    }
  EXPECT_GT(label, 100) << "no label patch above the box";
  EXPECT_GT(text, 20) << "no text in the label";

  // For rviz: the person's points, in the box's colour.
  ASSERT_TRUE(points.waitForCount(1, 5.0)) << "no people_points";
  const auto c = points.messages().back();
  EXPECT_EQ(c->header.frame_id, "camera_rgb_optical_frame");
  ASSERT_EQ(std::size_t(c->width) * c->height, person.frame(ros::Time(1.0)).people[0].cloud->size());
  Cloud cloud;
  pcl::fromROSMsg(*c, cloud);
  for (const auto& p : cloud.points)
    ASSERT_EQ((Bgr{ p.b, p.g, p.r }), colour);
}

TEST(Annotator, BadImagesGiveNoOutputAndTheNextGoodOneDoes)
{
  ros::NodeHandle nh;
  ErrorWatch dropped(nh, "dropped a colour image");
  Collector<sensor_msgs::Image> out(nh, "annotated/image");
  Inputs in(nh);
  ASSERT_TRUE(waitFor([&] { return in.connected(); }, 10.0));
  in.info.publish(cameraInfo());
  ros::WallDuration(0.3).sleep();
  const HandBuiltPerson person;
  double t = 200.0;
  std::vector<sensor_msgs::Image> bad;
  bad.push_back(colourImage("32FC1", kWidth, kHeight, ros::Time()));  // a depth image on the colour topic
  bad.push_back(colourImage("mono8", kWidth, kHeight, ros::Time()));
  bad.push_back(colourImage("rgb8", 2 * kWidth, 2 * kHeight, ros::Time()));  // not the camera_info's size
  bad.push_back(colourImage("rgb8", kWidth, kHeight, ros::Time()));
  bad.back().data.clear();  // empty
  bad.push_back(colourImage("bgr8", kWidth, kHeight, ros::Time()));
  bad.back().step = 1u << 30;  // a step that does not fit the data
  for (int round = 0; round < 2; ++round)
    for (auto& b : bad)
    {
      b.header.stamp = ros::Time(t += 0.1);
      in.people.publish(person.frame(b.header.stamp));
      in.image.publish(b);
      ros::WallDuration(0.05).sleep();
    }
  EXPECT_TRUE(waitFor([&] { return dropped.count() > 0; }, 5.0)) << "no error for a bad colour image";
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(out.size(), 0u) << "a bad colour image was annotated";
  // The annotator still serves: a good frame is annotated.
  const ros::Time good(t += 0.1);
  EXPECT_TRUE(waitFor(
      [&] {
        const ros::Time stamp(t += 0.1);
        in.image.publish(colourImage("bgr8", kWidth, kHeight, stamp));
        in.people.publish(person.frame(stamp));
        ros::WallDuration(0.05).sleep();
        return out.size() > 0;
      },
      10.0))
      << "no annotated image after bad ones";
  for (const auto& m : out.messages())
    EXPECT_GT(m->header.stamp.toSec(), good.toSec() - 1e-6) << "a bad frame's stamp came out";
}

TEST(Annotator, TrackerInputCloudIsAnnotatedWithTheScenePerson)
{
  // The test scene (320x240, f 262.5, person 2.5 m away, head top 0.55 m above the camera) through
  // the people tracker; the annotator draws on the tracker's own input cloud (image_source cloud).
  ros::NodeHandle nh;
  Collector<sensor_msgs::Image> out(nh, "annotated/image");
  Collector<PeopleClouds> people(nh, "person_clouds");
  // An annotated image and the person clouds of the same frame, with one person.
  sensor_msgs::Image::ConstPtr m;
  PeopleClouds::ConstPtr frame;
  ASSERT_TRUE(waitFor(
      [&] {
        const auto images = out.messages();
        const auto clouds = people.messages();
        for (auto i = images.rbegin(); i != images.rend(); ++i)
          for (const auto& c : clouds)
            if (c->header.stamp == (*i)->header.stamp && c->people.size() == 1 && c->people[0].cloud)
            {
              m = *i;
              frame = c;
              return true;
            }
        return false;
      },
      30.0))
      << "no annotated image of a frame with one tracked person (" << out.size() << " images, " << people.size()
      << " people frames)";
  ASSERT_EQ(m->encoding, "bgr8");
  ASSERT_EQ(m->width, unsigned(kWidth));
  ASSERT_EQ(m->height, unsigned(kHeight));
  // Where that frame's person cloud projects with the scene's camera.
  double pu0 = 1e9, pu1 = -1e9, pv0 = 1e9, pv1 = -1e9;
  for (const auto& p : frame->people[0].cloud->points)
  {
    pu0 = std::min(pu0, kF * p.x / p.z + kCx);
    pu1 = std::max(pu1, kF * p.x / p.z + kCx);
    pv0 = std::min(pv0, kF * p.y / p.z + kCy);
    pv1 = std::max(pv1, kF * p.y / p.z + kCy);
  }
  pv1 = std::min(pv1, kHeight - 1.0);
  // The scene puts the person there: centred (u 159.5), the head's top (y -0.55 m, front face at
  // z 2.4 m) at v = 119.5 - 60.2 = 59.3, at least the torso's width (x +-0.2 m: 22 px each side).
  EXPECT_NEAR(pv0, 59.3, 4.0);
  EXPECT_LT(pu0, 159.5 - 20);
  EXPECT_GT(pu1, 159.5 + 20);
  // The box in the image: the columns with a long run of the track's colour, the rows at its right side.
  const Bgr colour = trackColour(frame->people[0].info.id);
  int left = kWidth, right = -1, top = kHeight, bottom = -1;
  for (int u = 0; u < kWidth; ++u)
  {
    int run = 0, longest = 0;
    for (int v = 0; v < kHeight; ++v)
    {
      run = pixel(*m, u, v) == colour ? run + 1 : 0;
      longest = std::max(longest, run);
    }
    if (longest >= 40)
    {
      left = std::min(left, u);
      right = std::max(right, u);
    }
  }
  if (const char* dump = std::getenv("ANNOTATOR_TEST_DUMP"))  // a PPM of the image, to look at
  {
    std::ofstream f(dump, std::ios::binary);
    f << "P6\n" << kWidth << " " << kHeight << "\n255\n";
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u)
      {
        const Bgr p = pixel(*m, u, v);
        f.put(char(p[2])).put(char(p[1])).put(char(p[0]));
      }
  }
  ASSERT_LT(left, right) << "no box of track " << frame->people[0].info.id << "'s colour";
  for (int v = 0; v < kHeight; ++v)  // the label sits at the left: read the top and bottom at the right
    if (pixel(*m, right, v) == colour)
    {
      top = std::min(top, v);
      bottom = std::max(bottom, v);
    }
  // The line is 2 px wide, centred on the extent.
  EXPECT_NEAR(left, pu0, 2.5);
  EXPECT_NEAR(right, pu1, 2.5);
  EXPECT_NEAR(top, pv0, 2.5);
  EXPECT_NEAR(bottom, pv1, 2.5);
  // Outside the box the scene's own colours stay: the floor's grey bottom left, black sky top right.
  EXPECT_EQ(pixel(*m, 5, kHeight - 2)[0], pixel(*m, 5, kHeight - 2)[2]);
  EXPECT_EQ(pixel(*m, kWidth - 5, 5), (Bgr{ 0, 0, 0 }));
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_annotator");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
