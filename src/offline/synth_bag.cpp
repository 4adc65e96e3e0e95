// Bags in the layout of the 2012-13 ROS OpenNI driver, image encoding, previews.
#include "synth_bag.h"

#include "guarded_bag.h"

#include <action_flow/files.h>
#include <action_flow/kinect_depth.h>
#include <action_flow/ros/camera_info.h>

#include <geometry_msgs/TransformStamped.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
namespace
{
const char* kRgbFrame = "camera_rgb_optical_frame";

geometry_msgs::TransformStamped transform(const ros::Time& t, const std::string& parent, const std::string& child,
                                          const Eigen::Vector3f& p, const Eigen::Quaternionf& q)
{
  geometry_msgs::TransformStamped m;
  m.header.stamp = t;
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = p.x();
  m.transform.translation.y = p.y();
  m.transform.translation.z = p.z();
  m.transform.rotation.x = q.x();
  m.transform.rotation.y = q.y();
  m.transform.rotation.z = q.z();
  m.transform.rotation.w = q.w();
  return m;
}

std::vector<std::uint8_t> encode(const cv::Mat& m, const char* ext, const std::vector<int>& params)
{
  std::vector<std::uint8_t> out;
  if (!cv::imencode(ext, m, out, params))
    throw std::runtime_error(std::string("image encoding to ") + ext + " failed");
  return out;
}
}  // namespace

std::vector<std::uint8_t> encodeJpeg(const std::vector<std::uint8_t>& rgb, int width, int height, int quality)
{
  cv::Mat bgr(height, width, CV_8UC3);
  for (int i = 0; i < width * height; ++i)
  {
    bgr.data[3 * i] = rgb[3 * i + 2];
    bgr.data[3 * i + 1] = rgb[3 * i + 1];
    bgr.data[3 * i + 2] = rgb[3 * i];
  }
  return encode(bgr, ".jpg", { cv::IMWRITE_JPEG_QUALITY, quality });
}

std::vector<std::uint8_t> encodePng16(const std::vector<std::uint16_t>& data, int width, int height, int level)
{
  const cv::Mat m(height, width, CV_16UC1, const_cast<std::uint16_t*>(data.data()));
  return encode(m, ".png", { cv::IMWRITE_PNG_COMPRESSION, level });
}

std::vector<std::uint8_t> encodePng8(const std::vector<std::uint8_t>& data, int width, int height, int level)
{
  const cv::Mat m(height, width, CV_8UC1, const_cast<std::uint8_t*>(data.data()));
  return encode(m, ".png", { cv::IMWRITE_PNG_COMPRESSION, level });
}

std::vector<std::uint16_t> depthToMillimetres(const std::vector<float>& depth)
{
  std::vector<std::uint16_t> mm(depth.size());
  for (size_t i = 0; i < depth.size(); ++i)
    mm[i] = std::isfinite(depth[i]) ? std::uint16_t(std::lround(depth[i] * 1000.0f)) : 0;
  return mm;
}

std::vector<std::pair<std::string, std::string>> bagTopics(const BagOptions& o, const std::string& dataset)
{
  std::vector<std::pair<std::string, std::string>> t;
  if (o.raw_images)
  {
    t.emplace_back(o.rgb_topic, "sensor_msgs/Image");
    t.emplace_back(o.depth_topic, "sensor_msgs/Image");
    t.emplace_back(o.mask_topic, "sensor_msgs/Image");
  }
  else
  {
    t.emplace_back(o.rgb_topic + "/compressed", "sensor_msgs/CompressedImage");
    t.emplace_back(o.depth_topic + "/compressed", "sensor_msgs/CompressedImage");
    t.emplace_back(o.mask_topic + "/compressed", "sensor_msgs/CompressedImage");
  }
  t.emplace_back(o.info_topic, "sensor_msgs/CameraInfo");
  t.emplace_back(o.tf_topic, "tf2_msgs/TFMessage");
  if (o.points)
    t.emplace_back(o.points_topic, "sensor_msgs/PointCloud2");
  if (dataset == "stream" || dataset == "msr_stream")
    t.emplace_back(o.action_topic, "std_msgs/String");
  return t;
}

namespace
{
/** What a bag is written from: a single-person sample or a crowd scene. */
struct BagSource
{
  const CameraModel& camera;
  const SceneRenderer& scene;
  int frames;
  std::function<double(int)> stamp;
  std::function<void(int, FrameImages&)> render;
  /** openni_tracker's users in frame i: user number and joints (optical frame). */
  std::function<std::vector<std::pair<int, Skeleton>>(int)> users;
  /** The ground-truth action of frame i on options.action_topic; empty: no such topic. */
  std::function<std::string(int)> action;
};

/** The bag compression @p o names; throws on an unknown one or image settings out of range. */
rosbag::CompressionType bagCompression(const BagOptions& o)
{
  rosbag::CompressionType compression;
  if (o.compression == "none")
    compression = rosbag::compression::Uncompressed;
  else if (o.compression == "lz4")
    compression = rosbag::compression::LZ4;
  else if (o.compression == "bz2")
    compression = rosbag::compression::BZ2;
  else
    throw std::runtime_error("unknown bag compression '" + o.compression + "' (none, lz4, bz2)");
  if (o.jpeg_quality < 1 || o.jpeg_quality > 100 || o.png_level < 0 || o.png_level > 9)
    throw std::runtime_error("jpeg quality must be 1..100 and png level 0..9");
  return compression;
}

/** The camera_info of @p cam, without stamp and sequence number. */
sensor_msgs::CameraInfo cameraInfo(const CameraModel& cam)
{
  sensor_msgs::CameraInfo info = pinholeCameraInfo(cam.width, cam.height, cam.fx, cam.fy, cam.cx, cam.cy);
  info.header.frame_id = kRgbFrame;
  return info;
}

/** Writes @p im's colour, depth (@p mm, millimetres) and mask as raw sensor_msgs/Image. */
void writeRawImages(rosbag::Bag& bag, const BagOptions& o, const std_msgs::Header& header,
                    const FrameImages& im, const std::vector<std::uint16_t>& mm, int w, int h)
{
  sensor_msgs::Image rgb, depth, mask;
  rgb.header = depth.header = mask.header = header;
  rgb.width = depth.width = mask.width = std::uint32_t(w);
  rgb.height = depth.height = mask.height = std::uint32_t(h);
  rgb.encoding = "rgb8";
  rgb.step = std::uint32_t(3 * w);
  rgb.data = im.rgb;
  depth.encoding = "16UC1";
  depth.step = std::uint32_t(2 * w);
  depth.data.resize(mm.size() * 2);
  std::memcpy(depth.data.data(), mm.data(), depth.data.size());
  mask.encoding = "mono8";
  mask.step = std::uint32_t(w);
  mask.data = im.mask;
  bag.write(o.rgb_topic, header.stamp, rgb);
  bag.write(o.depth_topic, header.stamp, depth);
  bag.write(o.mask_topic, header.stamp, mask);
}

/** Writes @p im's colour (JPEG), depth (@p mm, 16-bit PNG) and mask (PNG) on /compressed topics. */
void writeCompressedImages(rosbag::Bag& bag, const BagOptions& o, const std_msgs::Header& header,
                           const FrameImages& im, const std::vector<std::uint16_t>& mm,
                           int w, int h)
{
  sensor_msgs::CompressedImage rgb, depth, mask;
  rgb.header = depth.header = mask.header = header;
  rgb.format = "rgb8; jpeg compressed bgr8";
  rgb.data = encodeJpeg(im.rgb, w, h, o.jpeg_quality);
  depth.format = "16UC1; png compressed 16UC1";
  depth.data = encodePng16(mm, w, h, o.png_level);
  mask.format = "mono8; png compressed mono8";
  mask.data = encodePng8(im.mask, w, h, o.png_level);
  bag.write(o.rgb_topic + "/compressed", header.stamp, rgb);
  bag.write(o.depth_topic + "/compressed", header.stamp, depth);
  bag.write(o.mask_topic + "/compressed", header.stamp, mask);
}

/**
 * The tf of one frame: the static camera frames as openni.launch published them, the camera's
 * pose over the floor ("world": origin on the floor below the camera, z up) as ground truth, and
 * openni_tracker's joints of @p users.
 */
tf2_msgs::TFMessage frameTransforms(const ros::Time& stamp, const CameraModel& cam,
                                    const std::vector<std::pair<int, Skeleton>>& users)
{
  const Eigen::Quaternionf optical(0.5f, -0.5f, 0.5f, -0.5f);  // rpy (-pi/2, 0, -pi/2)
  const Eigen::Quaternionf pitch(Eigen::AngleAxisf(float(cam.tilt), Eigen::Vector3f::UnitY()));
  const Eigen::Vector3f zero = Eigen::Vector3f::Zero();
  const Eigen::Quaternionf id = Eigen::Quaternionf::Identity();
  tf2_msgs::TFMessage tf;
  tf.transforms.push_back(transform(stamp, "world", "camera_link",
                                    Eigen::Vector3f(0, 0, float(cam.height_above_floor)), pitch));
  tf.transforms.push_back(transform(stamp, "camera_link", "camera_rgb_frame", zero, id));
  tf.transforms.push_back(transform(stamp, "camera_rgb_frame", kRgbFrame, zero, optical));
  tf.transforms.push_back(transform(stamp, "camera_link", "camera_depth_frame", zero, id));
  tf.transforms.push_back(
      transform(stamp, "camera_depth_frame", "camera_depth_optical_frame", zero, optical));
  tf.transforms.push_back(transform(stamp, "camera_link", "openni_depth_frame", zero, id));
  // openni_tracker's frames: each user's joints under openni_depth_frame (x forward, y left, z up).
  for (const auto& [user, sk] : users)
    for (int k = 0; k < kJointCount; ++k)
    {
      const Eigen::Vector3f& p = sk.joints[k];
      const std::string joint = jointName(Joint(k)) + "_" + std::to_string(user);
      const Eigen::Vector3f position(p.z(), -p.x(), -p.y());
      tf.transforms.push_back(transform(stamp, "openni_depth_frame", joint, position, id));
    }
  return tf;
}

/**
 * Renders frame @p i of @p src into @p im and writes its messages: images, camera_info (@p info,
 * restamped), tf, and the cloud (through @p cloud) and action when asked for.
 */
void writeFrame(rosbag::Bag& bag, const BagSource& src, const BagOptions& o, int i,
                sensor_msgs::CameraInfo& info, FrameImages& im, Cloud& cloud)
{
  const ros::Time stamp(src.stamp(i));
  src.render(i, im);

  std_msgs::Header header;
  header.stamp = stamp;
  header.seq = std::uint32_t(i);
  header.frame_id = kRgbFrame;
  const std::vector<std::uint16_t> mm = depthToMillimetres(im.depth);
  if (o.raw_images)
    writeRawImages(bag, o, header, im, mm, src.camera.width, src.camera.height);
  else
    writeCompressedImages(bag, o, header, im, mm, src.camera.width, src.camera.height);
  info.header.stamp = stamp;
  info.header.seq = std::uint32_t(i);
  bag.write(o.info_topic, stamp, info);
  bag.write(o.tf_topic, stamp, frameTransforms(stamp, src.camera, src.users(i)));

  if (o.points)
  {
    src.scene.toCloud(im, cloud);
    cloud.header.stamp = std::uint64_t(std::llround(src.stamp(i) * 1e6));
    sensor_msgs::PointCloud2 msg;
    pcl::toROSMsg(cloud, msg);
    msg.header = header;
    bag.write(o.points_topic, stamp, msg);
  }
  if (src.action)
  {
    std_msgs::String action;
    action.data = src.action(i);
    bag.write(o.action_topic, stamp, action);
  }
}

bool writeBag(const BagSource& src, const std::string& path, const BagOptions& o, const std::atomic<bool>* cancel,
              const std::function<void()>& on_frame)
{
  const rosbag::CompressionType compression = bagCompression(o);
  const std::string tmp = path + ".tmp";
  try
  {
    tools::GuardedBag guarded(tmp, rosbag::bagmode::Write);
    rosbag::Bag& bag = *guarded;
    bag.setCompression(compression);
    sensor_msgs::CameraInfo info = cameraInfo(src.camera);
    FrameImages im;
    Cloud cloud;
    for (int i = 0; i < src.frames; ++i)
    {
      if (cancel && cancel->load())
      {
        bag.close();
        std::remove(tmp.c_str());
        return false;
      }
      writeFrame(bag, src, o, i, info, im, cloud);
      if (on_frame)
        on_frame();
    }
    bag.close();
  }
  catch (const rosbag::BagException& e)
  {
    std::remove(tmp.c_str());
    throw std::runtime_error(tmp + ": " + e.what());
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the finished bag into place");
  }
  return true;
}

/** Rows "<prefix>action,first_frame,last_frame,start,end" of @p segments (stamps in seconds). */
std::string segmentRows(const std::vector<StreamSegment>& segments, const std::function<double(int)>& stamp,
                        const std::string& prefix)
{
  std::string rows;
  char buf[64];
  for (const StreamSegment& s : segments)
  {
    std::snprintf(buf, sizeof buf, ",%d,%d,%.6f,%.6f\n", s.first, s.last, stamp(s.first), stamp(s.last));
    rows += prefix + s.action + buf;
  }
  return rows;
}

/** Writes <prefix>_color.png and <prefix>_depth.png of rendered images. */
void writePreviewImages(const FrameImages& im, const CameraModel& cam, const std::string& prefix)
{
  const int w = im.width, h = im.height;
  cv::Mat bgr(h, w, CV_8UC3), grey(h, w, CV_8UC1);
  for (int k = 0; k < w * h; ++k)
  {
    bgr.data[3 * k] = im.rgb[3 * k + 2];
    bgr.data[3 * k + 1] = im.rgb[3 * k + 1];
    bgr.data[3 * k + 2] = im.rgb[3 * k];
    const float z = im.depth[k];
    // Near is bright, far is dark, no depth is black.
    grey.data[k] = std::isfinite(z) ? std::uint8_t(std::lround(255.0 - 215.0 * (z - cam.min_depth) / (cam.max_depth - cam.min_depth)))
                                    : 0;
  }
  for (const auto& [suffix, m] : { std::make_pair("_color.png", bgr), std::make_pair("_depth.png", grey) })
    if (!cv::imwrite(prefix + suffix, m, { cv::IMWRITE_PNG_COMPRESSION, 9 }))
      throw std::runtime_error(prefix + suffix + ": cannot write");
}
}  // namespace

bool writeSampleBag(const SampleRenderer& sample, const std::string& path, const BagOptions& options,
                    const std::atomic<bool>* cancel, const std::function<void()>& on_frame)
{
  BagSource src{ sample.camera(), sample.scene(), sample.frames(), [&](int i) { return sample.stamp(i); },
                 [&](int i, FrameImages& im) { sample.renderImages(i, im); },
                 [&](int i) {
                   // none in a scene without a person (clutter: furniture only)
                   std::vector<std::pair<int, Skeleton>> users;
                   if (sample.bodies() > 0)
                     users.emplace_back(1, sample.skeleton(i));
                   return users;
                 },
                 {} };
  if (sample.spec().dataset == "stream" || sample.spec().dataset == "msr_stream")
    src.action = [&](int i) { return sample.actionAt(i); };
  return writeBag(src, path, options, cancel, on_frame);
}

bool writeFakenectDump(const SampleRenderer& sample, const std::string& dir, const std::atomic<bool>* cancel,
                       const std::function<void()>& on_frame)
{
  namespace fs = std::filesystem;
  const fs::path tmp = dir + ".tmp";
  std::error_code ec;
  fs::remove_all(tmp, ec);
  if (!fs::create_directories(tmp, ec))
    throw std::runtime_error(tmp.string() + ": cannot create the folder: " + ec.message());
  std::ofstream index(tmp / "INDEX.txt");
  FrameImages im;
  std::vector<std::uint16_t> raw;
  const auto write = [&](char type, double time, std::uint32_t ts, const std::string& header, const void* data,
                         std::size_t bytes) {
    char name[64];
    std::snprintf(name, sizeof name, "%c-%f-%u.%s", type, time, ts, type == 'd' ? "pgm" : "ppm");
    std::ofstream f(tmp / name, std::ios::binary);
    f << header;
    f.write(static_cast<const char*>(data), std::streamsize(bytes));
    index << name << "\n";
    if (!f || !index)
      throw std::runtime_error((tmp / name).string() + ": cannot write");
  };
  for (int i = 0; i < sample.frames(); ++i)
  {
    if (cancel && *cancel)
    {
      index.close();
      fs::remove_all(tmp, ec);
      return false;
    }
    sample.renderImages(i, im);
    if (im.width != 640 || im.height != 480)
      throw std::runtime_error(dir + ": fakenect replays 640x480 only, the camera renders " + std::to_string(im.width) +
                               "x" + std::to_string(im.height));
    raw.resize(im.depth.size());
    for (std::size_t k = 0; k < raw.size(); ++k)
      raw[k] = metresToKinectRaw(im.depth[k]);
    // The sensor's clock counts at 60 MHz: 2,000,000 ticks a frame at 30 Hz.
    const auto ts = static_cast<std::uint32_t>(std::uint64_t(i) * 2000000u);
    write('r', sample.stamp(i), ts, "P6 640 480 255\n", im.rgb.data(), im.rgb.size());
    write('d', sample.stamp(i), ts, "P5 640 480 65535\n", raw.data(), 2 * raw.size());
    if (on_frame)
      on_frame();
  }
  index.close();
  if (!index)
    throw std::runtime_error((tmp / "INDEX.txt").string() + ": cannot write");
  fs::remove_all(dir, ec);
  fs::rename(tmp, dir, ec);
  if (ec)
    throw std::runtime_error(dir + ": cannot rename the dump into place: " + ec.message());
  return true;
}

bool writeCrowdBag(const CrowdRenderer& crowd, const std::string& path, const BagOptions& options,
                   std::vector<std::vector<CrowdTruth>>* truth, const std::atomic<bool>* cancel,
                   const std::function<void()>& on_frame)
{
  if (truth)
    truth->assign(size_t(crowd.frames()), {});
  const auto users = [&](int i) {
    std::vector<std::pair<int, Skeleton>> out;
    for (size_t k = 0; k < crowd.people().size(); ++k)
      if (crowd.present(k, i))
        out.emplace_back(crowd.people()[k].mask_id, crowd.skeleton(k, i));
    return out;
  };
  const auto render = [&](int i, FrameImages& im) {
    crowd.renderImages(i, im);
    if (truth)
      (*truth)[size_t(i)] = crowd.truth(i, im);
  };
  const BagSource src{ crowd.camera(), crowd.scene(), crowd.frames(), [&](int i) { return crowd.stamp(i); }, render,
                       users, {} };
  return writeBag(src, path, options, cancel, on_frame);
}

void writeSegmentsCsv(const SampleRenderer& sample, const std::string& path)
{
  writeTextAtomically(path, "action,first_frame,last_frame,start,end\n" +
                                segmentRows(sample.segments(), [&](int i) { return sample.stamp(i); }, ""));
}

void writeCrowdTruth(const CrowdRenderer& crowd, const std::vector<std::vector<CrowdTruth>>& truth,
                     const std::string& prefix)
{
  if (truth.size() != size_t(crowd.frames()))
    throw std::invalid_argument("writeCrowdTruth: one truth list per frame expected");
  std::string segments = "person,action,first_frame,last_frame,start,end\n";
  for (const CrowdPerson& p : crowd.people())
    segments += segmentRows(p.segments, [&](int i) { return crowd.stamp(i); }, p.actor + ",");
  std::string people = "frame,stamp,person,mask_id,x,y,z,yaw,visible_pixels,visible_area,head_visible,counted\n";
  char buf[160];
  for (size_t f = 0; f < truth.size(); ++f)
    for (const CrowdTruth& t : truth[f])
    {
      std::snprintf(buf, sizeof buf, "%zu,%.6f,%s,%d,%.4f,%.4f,%.4f,%.4f,%d,%.4f,%d,%d\n", f, crowd.stamp(int(f)),
                    crowd.people()[size_t(t.mask_id - 1)].actor.c_str(), int(t.mask_id), t.position.x(),
                    t.position.y(), t.position.z(), t.yaw, t.visible_pixels, t.visible_area, int(t.head_visible),
                    int(t.counted));
      people += buf;
    }
  writeTextAtomically(prefix + "_segments.csv", segments);
  writeTextAtomically(prefix + "_people.csv", people);
}

void writePreview(const SampleRenderer& sample, int i, const std::string& prefix)
{
  FrameImages im;
  sample.renderImages(i, im);
  writePreviewImages(im, sample.camera(), prefix);
}

void writeCrowdPreview(const CrowdRenderer& crowd, int i, const std::string& prefix)
{
  FrameImages im;
  crowd.renderImages(i, im);
  writePreviewImages(im, crowd.camera(), prefix);
}

}  // namespace synth
}  // namespace action_flow
