// The bags synth writes: readable with the rosbag API, with the promised topics, types, frame ids
// and message counts; byte-identical for the same seed; no partial file when cancelled; a stream's
// ground-truth action per frame and its segments CSV.
#include "../../src/offline/synth_bag.h"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

using namespace action_flow::synth;
namespace fs = std::filesystem;

namespace
{
struct TempDir
{
  TempDir()
  {
    path = fs::temp_directory_path() / ("synth_bag_test_" + std::to_string(::getpid()));
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  fs::path path;
};

SampleSpec spec(int frames)
{
  SampleSpec s;
  s.person = "p02";
  s.action = "kick";
  s.repetition = 1;
  s.max_frames = frames;
  return s;
}

std::string bytes(const fs::path& p)
{
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(SynthBag, HasTheTopicsTypesFramesAndCounts)
{
  TempDir dir;
  const SampleRenderer sample(spec(4));
  BagOptions options;
  options.points = true;
  const fs::path path = dir.path / "p02_kick_1.bag";
  int frames = 0;
  ASSERT_TRUE(writeSampleBag(sample, path.string(), options, nullptr, [&]() { ++frames; }));
  EXPECT_EQ(frames, 4);
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));

  rosbag::Bag bag(path.string(), rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, std::string> types;
  for (const auto* c : view.getConnections())
    types[c->topic] = c->datatype;
  const auto promised = bagTopics(options);
  ASSERT_EQ(types.size(), promised.size());
  for (const auto& [topic, type] : promised)
    EXPECT_EQ(types[topic], type) << topic;
  EXPECT_EQ(types["/camera/depth_registered/points"], "sensor_msgs/PointCloud2");
  EXPECT_EQ(types["/camera/rgb/image_color/compressed"], "sensor_msgs/CompressedImage");

  std::map<std::string, int> counts;
  FrameImages im;
  for (const rosbag::MessageInstance& m : view)
  {
    ++counts[m.getTopic()];
    if (auto pc = m.instantiate<sensor_msgs::PointCloud2>())
    {
      EXPECT_EQ(pc->header.frame_id, "camera_rgb_optical_frame");
      EXPECT_EQ(pc->width, 640u);
      EXPECT_EQ(pc->height, 480u);
    }
    if (auto ci = m.instantiate<sensor_msgs::CompressedImage>())
    {
      EXPECT_EQ(ci->header.frame_id, "camera_rgb_optical_frame");
      const int f = int(ci->header.seq);
      EXPECT_NEAR(ci->header.stamp.toSec(), sample.stamp(f), 1e-6);
      if (m.getTopic() == "/camera/depth_registered/image_raw/compressed")
      {
        // Lossless: the PNG decodes to the rendered depth in millimetres.
        const cv::Mat d = cv::imdecode(ci->data, cv::IMREAD_UNCHANGED);
        ASSERT_EQ(d.type(), CV_16UC1);
        sample.renderImages(f, im);
        const auto mm = depthToMillimetres(im.depth);
        ASSERT_EQ(std::memcmp(d.data, mm.data(), mm.size() * 2), 0);
      }
      if (m.getTopic() == "/camera/person_mask/compressed")
      {
        const cv::Mat d = cv::imdecode(ci->data, cv::IMREAD_UNCHANGED);
        ASSERT_EQ(d.type(), CV_8UC1);
        EXPECT_GT(cv::countNonZero(d), 3000);
      }
    }
    if (auto info = m.instantiate<sensor_msgs::CameraInfo>())
    {
      EXPECT_EQ(info->header.frame_id, "camera_rgb_optical_frame");
      EXPECT_DOUBLE_EQ(info->K[0], 525.0);
      EXPECT_DOUBLE_EQ(info->K[2], 319.5);
    }
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>())
    {
      std::set<std::string> children;
      for (const auto& t : tf->transforms)
      {
        children.insert(t.child_frame_id);
        if (t.child_frame_id == "head_1")
        {
          EXPECT_EQ(t.header.frame_id, "openni_depth_frame");
          EXPECT_GT(t.transform.translation.x, 2.0);  // in front of the camera
          EXPECT_GT(t.transform.translation.z, 0.3);  // above the camera: a head
        }
      }
      for (const char* joint : { "head_1", "neck_1", "torso_1", "left_hand_1", "right_foot_1" })
        EXPECT_TRUE(children.count(joint)) << joint;
      EXPECT_TRUE(children.count("camera_rgb_optical_frame"));
    }
  }
  for (const auto& [topic, type] : promised)
    EXPECT_EQ(counts[topic], 4) << topic;
}

TEST(SynthBag, SameSeedSameBytes)
{
  TempDir dir;
  const SampleRenderer a(spec(3)), b(spec(3));
  const BagOptions options;
  ASSERT_TRUE(writeSampleBag(a, (dir.path / "a.bag").string(), options));
  ASSERT_TRUE(writeSampleBag(b, (dir.path / "b.bag").string(), options));
  const std::string x = bytes(dir.path / "a.bag"), y = bytes(dir.path / "b.bag");
  ASSERT_GT(x.size(), 10000u);
  EXPECT_TRUE(x == y);
}

TEST(SynthBag, CancelledWriteLeavesNoFile)
{
  TempDir dir;
  const SampleRenderer sample(spec(5));
  std::atomic<bool> cancel{ false };
  int frames = 0;
  const fs::path path = dir.path / "x.bag";
  EXPECT_FALSE(writeSampleBag(sample, path.string(), BagOptions(), &cancel, [&]() {
    if (++frames == 2)
      cancel = true;
  }));
  EXPECT_EQ(frames, 2);
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path.string() + ".tmp"));
}

TEST(SynthBag, BadOptionsAreRejected)
{
  TempDir dir;
  const SampleRenderer sample(spec(1));
  BagOptions options;
  options.compression = "zip";
  EXPECT_THROW(writeSampleBag(sample, (dir.path / "y.bag").string(), options), std::runtime_error);
  EXPECT_THROW(writeSampleBag(sample, (dir.path / "no_such_dir" / "y.bag").string(), BagOptions()), std::runtime_error);
}

TEST(SynthBag, StreamHasTheGroundTruthActionAndTheSegmentsCsv)
{
  TempDir dir;
  // p10's first stream, cut 8 frames into its first action (66 frames of idle before it): quick,
  // with idle and action frames.
  SampleSpec s;
  s.dataset = "stream";
  s.person = "p10";
  s.action = "stream";
  s.repetition = 1;
  s.max_frames = SampleRenderer(s).segments().front().first + 8;
  ASSERT_LT(s.max_frames, 120);
  const SampleRenderer sample(s);
  ASSERT_EQ(sample.segments().size(), 1u);
  const BagOptions options;
  const fs::path path = dir.path / "p10_stream_1.bag";
  ASSERT_TRUE(writeSampleBag(sample, path.string(), options));

  rosbag::Bag bag(path.string(), rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, std::string> types;
  for (const auto* c : view.getConnections())
    types[c->topic] = c->datatype;
  const auto promised = bagTopics(options, "stream");
  ASSERT_EQ(types.size(), promised.size());
  for (const auto& [topic, type] : promised)
    EXPECT_EQ(types[topic], type) << topic;
  EXPECT_EQ(types["/ground_truth/action"], "std_msgs/String");
  std::map<std::string, int> counts;
  int i = 0, idle = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    ++counts[m.getTopic()];
    if (m.getTopic() != options.action_topic)
      continue;
    const auto action = m.instantiate<std_msgs::String>();
    ASSERT_TRUE(action);
    ASSERT_LT(i, sample.frames());
    EXPECT_NEAR(m.getTime().toSec(), sample.stamp(i), 1e-6) << i;
    EXPECT_EQ(action->data, sample.actionAt(i)) << i;
    idle += action->data.empty() ? 1 : 0;
    ++i;
  }
  for (const auto& [topic, type] : promised)
    EXPECT_EQ(counts[topic], sample.frames()) << topic;
  EXPECT_EQ(idle, sample.frames() - 8);

  const fs::path csv = dir.path / "p10_stream_1_segments.csv";
  writeSegmentsCsv(sample, csv.string());
  EXPECT_FALSE(fs::exists(csv.string() + ".tmp"));
  std::ifstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "action,first_frame,last_frame,start,end");
  size_t rows = 0;
  while (std::getline(in, line))
  {
    ASSERT_LT(rows, sample.segments().size());
    const StreamSegment& seg = sample.segments()[rows++];
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string action;
    int first = -1, last = -1;
    double start = 0, end = 0;
    ASSERT_TRUE(fields >> action >> first >> last >> start >> end) << line;
    EXPECT_EQ(action, seg.action);
    EXPECT_EQ(first, seg.first);
    EXPECT_EQ(last, seg.last);
    EXPECT_EQ(last, sample.frames() - 1);  // clipped by max_frames
    EXPECT_NEAR(start, sample.stamp(seg.first), 1e-6);
    EXPECT_NEAR(end, sample.stamp(seg.last), 1e-6);
  }
  EXPECT_EQ(rows, sample.segments().size());
  EXPECT_THROW(writeSegmentsCsv(sample, (dir.path / "no_such_dir" / "x.csv").string()), std::runtime_error);
}

TEST(SynthBag, ACrowdBagHasEveryonesJointsAndTheTruthFiles)
{
  TempDir dir;
  SampleSpec spec = crowdSamples(2, 1, 60.0).back();
  spec.max_frames = 6;
  const CrowdRenderer crowd(spec);
  const fs::path path = dir.path / "crowd2_1.bag";
  std::vector<std::vector<CrowdTruth>> truth;
  ASSERT_TRUE(writeCrowdBag(crowd, path.string(), BagOptions(), &truth));
  ASSERT_EQ(truth.size(), 6u);
  writeCrowdTruth(crowd, truth, (dir.path / "crowd2_1").string());

  // openni_tracker's frames of every person present, numbered by mask id; no action topic.
  rosbag::Bag bag(path.string(), rosbag::bagmode::Read);
  int frames = 0;
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    EXPECT_NE(m.getTopic(), BagOptions().action_topic);
    const auto tf = m.instantiate<tf2_msgs::TFMessage>();
    if (!tf)
      continue;
    std::set<std::string> heads;
    for (const auto& t : tf->transforms)
      if (t.child_frame_id.rfind("head_", 0) == 0)
        heads.insert(t.child_frame_id);
    std::set<std::string> expected;
    for (const CrowdPerson& p : crowd.people())
      if (crowd.present(size_t(p.mask_id - 1), frames))
        expected.insert("head_" + std::to_string(p.mask_id));
    EXPECT_EQ(heads, expected) << "frame " << frames;
    ++frames;
  }
  EXPECT_EQ(frames, 6);

  // One people row per person present per frame, as the truth; the segments' header has the person.
  std::ifstream people(dir.path / "crowd2_1_people.csv");
  std::string line;
  ASSERT_TRUE(std::getline(people, line));
  EXPECT_EQ(line, "frame,stamp,person,mask_id,x,y,z,yaw,visible_pixels,visible_area,head_visible,counted");
  size_t rows = 0, expected_rows = 0;
  while (std::getline(people, line))
    ++rows;
  for (const auto& f : truth)
    expected_rows += f.size();
  EXPECT_EQ(rows, expected_rows);
  EXPECT_GT(rows, 0u);
  std::ifstream segments(dir.path / "crowd2_1_segments.csv");
  ASSERT_TRUE(std::getline(segments, line));
  EXPECT_EQ(line, "person,action,first_frame,last_frame,start,end");
  EXPECT_THROW(writeCrowdTruth(crowd, {}, (dir.path / "x").string()), std::invalid_argument);
}
