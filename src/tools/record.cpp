// record: one sample of your own for `train`, from a live sensor (launch/record.launch starts the
// driver and this node). Subscribes to the driver's colour and registered depth images and colour
// camera_info, writes them as the virtual Kinect writes its bags (JPEG colour and PNG depth on
// <topic>/compressed, camera_info), and adds the sample to the folder's index.csv, which `train
// --index` reads. Each frame takes about 0.13 MB instead of a cloud's 10 MB.
#include "../offline/cli.h"
#include "../offline/guarded_bag.h"
#include "../offline/synth_bag.h"

#include <action_flow/files.h>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using namespace action_flow;

namespace
{
const char* kSynopsis = R"(usage: record --person ID --action NAME [options]
Records one sample from the driver (roslaunch action_flow record.launch does it for you) until
Ctrl-C, --seconds or --idle-stop, then adds it to OUT/index.csv for `train --index OUT/index.csv`.
Topics (remap them): rgb/image_raw (rgb8), depth_registered/image_raw (16UC1 mm), rgb/camera_info.
Exit codes: 0 recorded, 1 error (nothing recorded: no file is left), 2 usage, 130 interrupted before a frame.)";

tools::Options options()
{
  tools::Options o(kSynopsis);
  o.value("person", "ID", "who performs (index column person)")
      .value("action", "NAME", "what they perform (index column action)")
      .value("out", "DIR", "folder of the samples and their index.csv (default action_flow_recordings)")
      .value("repetition", "N", "the sample's repetition (default: the next free one for this person and action)")
      .value("seconds", "S", "stop after S seconds of frames (default 0: until Ctrl-C)")
      .value("idle-stop", "S", "stop when no frame came for S seconds after the first (default 0: never)")
      .value("jpeg-quality", "Q", "colour JPEG quality 1-100 (default 90)");
  return o;
}

volatile std::sig_atomic_t g_stop = 0;
void onSignal(int) { g_stop = 1; }

// The rows of OUT/index.csv (header first), or a new header.
std::vector<std::string> readRows(const fs::path& index)
{
  std::vector<std::string> rows;
  std::ifstream in(index);
  for (std::string line; std::getline(in, line);)
    if (!line.empty())
      rows.push_back(line);
  if (rows.empty())
    rows.push_back("path,person,action,repetition,frames");
  return rows;
}

int nextRepetition(const std::vector<std::string>& rows, const std::string& person, const std::string& action)
{
  int next = 1;
  for (std::size_t i = 1; i < rows.size(); ++i)
  {
    std::stringstream ss(rows[i]);
    std::string path, p, a, rep;
    std::getline(ss, path, ',');
    std::getline(ss, p, ',');
    std::getline(ss, a, ',');
    std::getline(ss, rep, ',');
    if (p == person && a == action)
      next = std::max(next, std::atoi(rep.c_str()) + 1);
  }
  return next;
}

// What a recording got: depth frames, and the bytes of its compressed images.
struct Recorded
{
  int frames = 0;
  double bytes = 0.0;
};

// Writes the driver's frames into the bag @p tmp, as the virtual Kinect lays its bags out, until
// Ctrl-C, @p seconds of frames or @p idle_stop seconds without one (0 = no such limit).
Recorded recordFrames(ros::NodeHandle& nh, const fs::path& tmp, int quality, double seconds, double idle_stop)
{
  const synth::BagOptions topics;  // the layout train reads by default
  Recorded out;
  double first = -1.0, last_wall = 0.0;
  tools::GuardedBag guarded(tmp.string(), rosbag::bagmode::Write);
  rosbag::Bag& bag = *guarded;
  bag.setCompression(rosbag::compression::LZ4);
  const auto onRgb = [&](const sensor_msgs::ImageConstPtr& m) {
    if (m->encoding != "rgb8" || m->step != 3 * m->width || m->data.size() != std::size_t(m->step) * m->height)
    {
      ROS_ERROR_THROTTLE(5, "record: colour image is not packed rgb8 (%s): skipped", m->encoding.c_str());
      return;
    }
    sensor_msgs::CompressedImage c;
    c.header = m->header;
    c.format = "rgb8; jpeg compressed bgr8";
    c.data = synth::encodeJpeg(m->data, int(m->width), int(m->height), quality);
    out.bytes += c.data.size();
    bag.write(topics.rgb_topic + "/compressed", m->header.stamp, c);
  };
  const auto onDepth = [&](const sensor_msgs::ImageConstPtr& m) {
    if (m->encoding != "16UC1" || m->step != 2 * m->width || m->data.size() != std::size_t(m->step) * m->height)
    {
      ROS_ERROR_THROTTLE(5, "record: depth image is not packed 16UC1 (%s): skipped", m->encoding.c_str());
      return;
    }
    std::vector<std::uint16_t> mm(m->width * m->height);
    std::memcpy(mm.data(), m->data.data(), m->data.size());
    sensor_msgs::CompressedImage c;
    c.header = m->header;
    c.format = "16UC1; png compressed 16UC1";
    c.data = synth::encodePng16(mm, int(m->width), int(m->height), 3);
    out.bytes += c.data.size();
    bag.write(topics.depth_topic + "/compressed", m->header.stamp, c);
    if (first < 0.0)
      first = m->header.stamp.toSec();
    last_wall = ros::WallTime::now().toSec();
    if (++out.frames % 30 == 0)
      std::cout << "record: " << out.frames << " frames" << std::endl;
  };
  const auto onInfo = [&](const sensor_msgs::CameraInfoConstPtr& m) { bag.write(topics.info_topic, m->header.stamp, *m); };
  ros::Subscriber s1 = nh.subscribe<sensor_msgs::Image>("rgb/image_raw", 10, onRgb);
  ros::Subscriber s2 = nh.subscribe<sensor_msgs::Image>("depth_registered/image_raw", 10, onDepth);
  ros::Subscriber s3 = nh.subscribe<sensor_msgs::CameraInfo>("rgb/camera_info", 10, onInfo);
  const double start = ros::WallTime::now().toSec();
  while (!g_stop && ros::ok())
  {
    ros::spinOnce();
    const double now = ros::WallTime::now().toSec();
    if (out.frames > 0 && ((seconds > 0.0 && ros::Time::now().toSec() - first >= seconds) ||
                           (idle_stop > 0.0 && now - last_wall >= idle_stop)))
      break;
    if (out.frames == 0 && idle_stop > 0.0 && now - start > 60.0)
      break;  // a driver that never delivers: give up after a minute
    ros::WallDuration(0.005).sleep();
  }
  return out;
}

// Adds @p row to the index (header first if it is new), keeping its rows; written atomically.
void appendToIndex(const fs::path& index, const std::string& row)
{
  std::vector<std::string> rows = readRows(index);
  rows.push_back(row);
  std::string text;
  for (const std::string& r : rows)
    text += r + "\n";
  writeTextAtomically(index.string(), text);
}

int record(const tools::Args& args)
{
  const std::string person = args.get("person"), action = args.get("action");
  if (person.empty() || action.empty())
    throw tools::UsageError("--person and --action are required");
  for (const std::string& v : { person, action })
    if (v.find_first_of(",\"\n/") != std::string::npos)
      throw tools::UsageError("--person and --action must not contain commas, quotes, slashes or newlines: '" + v + "'");
  const fs::path out = fs::absolute(args.get("out", "action_flow_recordings"));
  const double seconds = args.number("seconds", 0.0), idle_stop = args.number("idle-stop", 0.0);
  const int quality = int(args.integer("jpeg-quality", 90, 1, 100));
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec)
    throw std::runtime_error(out.string() + ": cannot create the folder: " + ec.message());
  const fs::path index = out / "index.csv";
  const int repetition = int(args.integer("repetition", nextRepetition(readRows(index), person, action), 0, 100000));
  const std::string name = person + "_" + action + "_" + std::to_string(repetition) + ".bag";
  const fs::path bag_path = out / name, tmp = out / (name + ".tmp");
  if (fs::exists(bag_path))
    throw std::runtime_error(bag_path.string() + " exists already: give another --repetition");

  ros::NodeHandle nh;
  std::cout << "record: " << person << " performing " << action << " into " << bag_path.string()
            << " (Ctrl-C stops)" << std::endl;
  const Recorded recorded = recordFrames(nh, tmp, quality, seconds, idle_stop);
  const int frames = recorded.frames;
  if (frames == 0)
  {
    fs::remove(tmp, ec);
    throw std::runtime_error("no depth frame came on " + nh.resolveName("depth_registered/image_raw") +
                             ": nothing recorded (is the driver running and its device open?)");
  }
  fs::rename(tmp, bag_path, ec);
  if (ec)
    throw std::runtime_error(bag_path.string() + ": cannot rename the recording into place: " + ec.message());
  appendToIndex(index, name + "," + person + "," + action + "," + std::to_string(repetition) + "," +
                           std::to_string(frames));
  std::cout << "record: " << frames << " frames (" << int(recorded.bytes / 1e6 + 0.5) << " MB) in " << bag_path.string()
            << ", added to " << index.string() << std::endl;
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "record", ros::init_options::NoSigintHandler | ros::init_options::AnonymousName);
  std::vector<std::string> rest;
  ros::removeROSArgs(argc, argv, rest);
  std::vector<char*> plain;
  for (std::string& a : rest)
    plain.push_back(a.data());
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  return tools::runTool("record", [&] {
    const tools::Options o = options();
    const tools::Args args(int(plain.size()), plain.data(), o);
    if (args.has("help"))
      return o.printHelp();
    return record(args);
  });
}
