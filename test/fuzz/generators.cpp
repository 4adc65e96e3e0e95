// Generators of malformed inputs for the fuzz suite (see generators.h). Everything here depends on
// the seed alone: no clock, no address, no global state.
#include "generators.h"

#include <action_flow/action_model.h>
#include <action_flow/linear_classifier.h>

#include <boost/crc.hpp>
#include <rosbag/bag.h>
#include <sensor_msgs/CompressedImage.h>
#include <std_msgs/String.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>

namespace action_flow
{
namespace fuzz
{
namespace
{
std::uint64_t splitMix(std::uint64_t x)
{
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

void putFloat(std::vector<std::uint8_t>& data, std::size_t at, float v)
{
  std::memcpy(&data[at], &v, 4);
}

std::string readFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void writeFile(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

std::string randomBytes(Rng& rng, std::size_t n)
{
  std::string s(n, '\0');
  for (char& c : s)
    c = static_cast<char>(rng.in(0, 255));
  return s;
}

std::string randomWord(Rng& rng, std::size_t lo, std::size_t hi, const char* alphabet = "abcdefghijklmnopqrstuvwxyz-_0123456789")
{
  const std::size_t n = rng.in(lo, hi), k = std::strlen(alphabet);
  std::string s;
  for (std::size_t i = 0; i < n; ++i)
    s += alphabet[rng.in(0, k - 1)];
  return s;
}
}  // namespace

Rng::Rng(std::uint64_t seed) : engine_(splitMix(seed))
{
}

std::uint64_t Rng::in(std::uint64_t lo, std::uint64_t hi)
{
  return std::uniform_int_distribution<std::uint64_t>(lo, hi)(engine_);
}

bool Rng::chance(double p)
{
  return std::uniform_real_distribution<double>(0.0, 1.0)(engine_) < p;
}

std::uint32_t Rng::edge32()
{
  switch (in(0, 5))
  {
    case 0: return 0;
    case 1: return 1;
    case 2: return 1u << in(0, 31);
    case 3: return 0xffffffffu - static_cast<std::uint32_t>(in(0, 3));
    case 4: return static_cast<std::uint32_t>(in(0, 4096));
    default: return static_cast<std::uint32_t>(in(0, 0xffffffffu));
  }
}

std::string printable(const std::string& text, std::size_t max)
{
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 32 && c < 127)
      out += static_cast<char>(c);
    else
    {
      char buf[8];
      std::snprintf(buf, sizeof(buf), "\\x%02x", c);
      out += buf;
    }
  }
  if (text.size() > max)
    out += "...";
  return out;
}

// ---- messages ---------------------------------------------------------------------------------

sensor_msgs::PointCloud2 goodCloud(std::uint32_t width, std::uint32_t height)
{
  sensor_msgs::PointCloud2 m;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.header.stamp = ros::Time(100.0);
  m.width = width;
  m.height = height;
  const auto field = [](const std::string& name, std::uint32_t offset) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    return f;
  };
  m.fields = { field("x", 0), field("y", 4), field("z", 8), field("rgb", 16) };
  m.point_step = 32;  // PCL's PointXYZRGB layout
  m.row_step = m.point_step * width;
  m.is_dense = true;
  m.data.assign(static_cast<std::size_t>(m.row_step) * height, 0);
  for (std::uint32_t v = 0; v < height; ++v)
    for (std::uint32_t u = 0; u < width; ++u)
    {
      const std::size_t at = static_cast<std::size_t>(v) * m.row_step + static_cast<std::size_t>(u) * m.point_step;
      putFloat(m.data, at, (u - width / 2.0f) * 0.01f);
      putFloat(m.data, at + 4, (v - height / 2.0f) * 0.01f);
      putFloat(m.data, at + 8, 2.0f);
      m.data[at + 16] = 200;
      m.data[at + 17] = 100;
      m.data[at + 18] = 50;
    }
  return m;
}

Generated<sensor_msgs::PointCloud2> badCloud(std::uint64_t seed)
{
  Rng rng(seed);
  const std::uint32_t w = static_cast<std::uint32_t>(rng.in(1, 40)), h = static_cast<std::uint32_t>(rng.in(1, 30));
  sensor_msgs::PointCloud2 m = goodCloud(w, h);
  m.header.stamp = ros::Time(100.0 + static_cast<double>(seed % 1000) * 0.01);
  static const std::vector<std::string> cases = { "wrong_width",  "wrong_height",   "wrong_point_step", "wrong_row_step",
                                                  "short_data",   "long_data",      "missing_xyz",      "huge_claim",
                                                  "nan_only",     "empty",          "field_offset",     "field_type",
                                                  "field_count",  "big_endian",     "inf_points",       "empty_with_data",
                                                  "zero_point_step", "unorganized", "duplicate_field",  "random_header",
                                                  "shadowed_colour" };
  const std::string c = rng.pick(cases);
  if (c == "wrong_width")
    m.width = rng.chance(0.5) ? rng.edge32() : w + static_cast<std::uint32_t>(rng.in(1, 5));
  else if (c == "wrong_height")
    m.height = rng.chance(0.5) ? rng.edge32() : h + static_cast<std::uint32_t>(rng.in(1, 5));
  else if (c == "wrong_point_step")
    m.point_step = rng.edge32();
  else if (c == "wrong_row_step")
    m.row_step = rng.chance(0.5) ? rng.edge32() : m.row_step + static_cast<std::uint32_t>(rng.in(1, 64));
  else if (c == "short_data")
    m.data.resize(rng.in(0, m.data.size() - 1));
  else if (c == "long_data")
    m.data.resize(m.data.size() + rng.in(1, 4096));
  else if (c == "missing_xyz")
  {
    const std::size_t drop = rng.in(0, 3);
    if (drop == 3)
      m.fields.clear();
    else
      m.fields.erase(m.fields.begin() + static_cast<long>(drop));
    if (rng.chance(0.3))
      m.fields[0].name = rng.pick(std::vector<std::string>{ "X", "", "x ", "xyz" });
  }
  else if (c == "huge_claim")
  {
    // A header claiming gigabytes that agrees with itself; the data stays small.
    m.width = static_cast<std::uint32_t>(rng.in(1u << 16, 0xffffffffu));
    m.height = static_cast<std::uint32_t>(rng.in(1, 1u << 16));
    m.row_step = static_cast<std::uint32_t>(static_cast<std::uint64_t>(m.width) * m.point_step);
  }
  else if (c == "nan_only" || c == "inf_points")
  {
    const float bad = c == "nan_only" ? kNaN : (rng.chance(0.5) ? kInf : -kInf);
    for (std::size_t at = 0; at + 12 <= m.data.size(); at += m.point_step)
      for (int k = 0; k < 3; ++k)
        if (c == "nan_only" || rng.chance(0.5))
          putFloat(m.data, at + 4 * k, bad);
        else
          putFloat(m.data, at + 4 * k, rng.chance(0.5) ? 3e38f : -3e38f);
    m.is_dense = rng.chance(0.5);
  }
  else if (c == "empty")
  {
    m.width = m.height = 0;
    m.row_step = 0;
    m.data.clear();
  }
  else if (c == "empty_with_data")
  {
    m.width = rng.chance(0.5) ? 0 : w;
    m.height = m.width ? 0 : h;
    m.row_step = m.width * m.point_step;
  }
  else if (c == "field_offset")
    m.fields[rng.in(0, m.fields.size() - 1)].offset = rng.edge32();
  else if (c == "field_type")
    m.fields[rng.in(0, m.fields.size() - 1)].datatype = static_cast<std::uint8_t>(rng.in(0, 255));
  else if (c == "field_count")
    m.fields[rng.in(0, m.fields.size() - 1)].count = rng.edge32();
  else if (c == "big_endian")
    m.is_bigendian = true;
  else if (c == "zero_point_step")
  {
    m.point_step = 0;
    m.row_step = 0;
    if (rng.chance(0.5))
      m.data.clear();
  }
  else if (c == "unorganized")
  {
    m.width = w * h;
    m.height = 1;
    m.row_step = m.width * m.point_step;
  }
  else if (c == "duplicate_field")
  {
    sensor_msgs::PointField f = m.fields[rng.in(0, 2)];
    f.offset = rng.chance(0.5) ? rng.edge32() : static_cast<std::uint32_t>(rng.in(0, 40));
    m.fields.insert(m.fields.begin() + static_cast<long>(rng.in(0, m.fields.size())), f);
  }
  else if (c == "shadowed_colour")
  {
    // A first 'rgb' that is no FLOAT32 at a good offset, then a FLOAT32 'rgb' far outside the point.
    m.fields[3].datatype = rng.pick(std::vector<std::uint8_t>{ sensor_msgs::PointField::UINT32, sensor_msgs::PointField::UINT8,
                                                               sensor_msgs::PointField::INT32 });
    sensor_msgs::PointField f = m.fields[3];
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    f.offset = rng.chance(0.5) ? static_cast<std::uint32_t>(rng.in(1u << 20, 1u << 30)) : m.point_step + static_cast<std::uint32_t>(rng.in(0, 64));
    m.fields.push_back(f);
  }
  else  // random_header: several fields at once
  {
    for (int k = 0, n = static_cast<int>(rng.in(2, 5)); k < n; ++k)
      switch (rng.in(0, 5))
      {
        case 0: m.width = rng.edge32(); break;
        case 1: m.height = rng.edge32(); break;
        case 2: m.point_step = rng.edge32(); break;
        case 3: m.row_step = rng.edge32(); break;
        case 4: m.data.resize(rng.in(0, 2 * m.data.size() + 16)); break;
        default: m.fields[rng.in(0, m.fields.size() - 1)].offset = rng.edge32();
      }
  }
  return { m, c };
}

sensor_msgs::Image goodImage(const std::string& encoding, std::uint32_t width, std::uint32_t height)
{
  const int bytes = encoding == "32FC1" || encoding == "rgba8" || encoding == "bgra8" ? 4 :
                    encoding == "16UC1" || encoding == "mono16"                     ? 2 :
                    encoding == "mono8"                                               ? 1 :
                                                                                        3;
  sensor_msgs::Image m;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.encoding = encoding;
  m.width = width;
  m.height = height;
  m.step = width * bytes;
  m.data.assign(static_cast<std::size_t>(m.step) * height, 0);
  if (encoding == "32FC1")
    for (std::size_t i = 0; i + 4 <= m.data.size(); i += 4)
      putFloat(m.data, i, 2.0f);
  else if (encoding == "16UC1")
    for (std::size_t i = 0; i + 2 <= m.data.size(); i += 2)
    {
      const std::uint16_t mm = 2000;
      std::memcpy(&m.data[i], &mm, 2);
    }
  else
    for (std::size_t i = 0; i < m.data.size(); ++i)
      m.data[i] = static_cast<std::uint8_t>(i * 7);
  return m;
}

sensor_msgs::CameraInfo goodInfo(std::uint32_t width, std::uint32_t height)
{
  sensor_msgs::CameraInfo m;
  m.header.frame_id = "camera_rgb_optical_frame";
  m.width = width;
  m.height = height;
  const double f = 0.82 * width, cx = (width - 1) / 2.0, cy = (height - 1) / 2.0;
  m.K = { f, 0, cx, 0, f, cy, 0, 0, 1 };
  m.R = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  m.P = { f, 0, cx, 0, 0, f, cy, 0, 0, 0, 1, 0 };
  m.distortion_model = "plumb_bob";
  m.D = { 0, 0, 0, 0, 0 };
  return m;
}

Generated<sensor_msgs::Image> badImage(std::uint64_t seed, bool depth, std::uint32_t width, std::uint32_t height)
{
  Rng rng(seed);
  const std::string enc = depth ? rng.pick(std::vector<std::string>{ "32FC1", "16UC1" }) :
                                  rng.pick(std::vector<std::string>{ "rgb8", "bgr8", "rgba8", "bgra8", "mono8" });
  sensor_msgs::Image m = goodImage(enc, width, height);
  static const std::vector<std::string> cases = { "unknown_encoding", "wrong_stream_encoding", "zero_size", "huge_step",
                                                  "step_too_small", "short_data", "long_data", "taller", "wider",
                                                  "smaller", "huge_side", "nan_depth", "big_endian", "random_header" };
  std::string c = rng.pick(cases);
  if (c == "nan_depth" && !depth)
    c = "taller";
  if (c == "unknown_encoding")
    m.encoding = rng.pick(std::vector<std::string>{ "", "yuv422", "bayer_rggb8", "8UC3", "RGB8", "rgb8 ", "64FC1",
                                                    randomWord(rng, 1, 12) });
  else if (c == "wrong_stream_encoding")
  {
    const sensor_msgs::Image other = goodImage(depth ? "rgb8" : rng.pick(std::vector<std::string>{ "32FC1", "16UC1", "mono16" }),
                                               width, height);
    m = other;
  }
  else if (c == "zero_size")
  {
    m.width = rng.chance(0.5) ? 0 : width;
    m.height = m.width ? 0 : (rng.chance(0.5) ? 0 : height);
    if (rng.chance(0.5))
      m.data.clear();
  }
  else if (c == "huge_step")
    m.step = rng.chance(0.5) ? 0xffffffffu - static_cast<std::uint32_t>(rng.in(0, 7)) : 1u << rng.in(16, 31);
  else if (c == "step_too_small")
    m.step = static_cast<std::uint32_t>(rng.in(0, m.step - 1));
  else if (c == "short_data")
    m.data.resize(rng.in(0, m.data.size() - 1));
  else if (c == "long_data")
    m.data.resize(m.data.size() + rng.in(1, 4096));
  else if (c == "taller" || c == "wider" || c == "smaller")
  {
    const std::uint32_t dw = c == "wider" ? static_cast<std::uint32_t>(rng.in(1, 32)) : 0;
    const std::uint32_t dh = c == "taller" ? static_cast<std::uint32_t>(rng.in(1, 32)) : 0;
    const std::uint32_t nw = c == "smaller" ? width / 2 : width + dw, nh = c == "smaller" ? height / 2 : height + dh;
    m = goodImage(enc, nw, nh);
  }
  else if (c == "huge_side")
  {
    m.width = static_cast<std::uint32_t>(rng.in(8193, 0xffffffffu));
    m.height = rng.chance(0.5) ? height : static_cast<std::uint32_t>(rng.in(8193, 0xffffffffu));
  }
  else if (c == "nan_depth")
  {
    if (enc == "32FC1")
      for (std::size_t i = 0; i + 4 <= m.data.size(); i += 4)
        putFloat(m.data, i, rng.pick(std::vector<float>{ kNaN, kInf, -kInf, -1.0f, 0.0f, 1e30f, 2.0f }));
    else
      for (std::size_t i = 0; i + 2 <= m.data.size(); i += 2)
        m.data[i] = m.data[i + 1] = 0xff;
  }
  else if (c == "big_endian")
    m.is_bigendian = 1;
  else  // random_header
    for (int k = 0, n = static_cast<int>(rng.in(2, 4)); k < n; ++k)
      switch (rng.in(0, 3))
      {
        case 0: m.width = rng.edge32(); break;
        case 1: m.height = rng.edge32(); break;
        case 2: m.step = rng.edge32(); break;
        default: m.data.resize(rng.in(0, 2 * m.data.size() + 16));
      }
  return { m, c };
}

Generated<sensor_msgs::CameraInfo> badInfo(std::uint64_t seed, std::uint32_t width, std::uint32_t height)
{
  Rng rng(seed);
  sensor_msgs::CameraInfo m = goodInfo(width, height);
  static const std::vector<std::string> cases = { "zero_focal", "nan_intrinsics", "negative_focal", "inf_centre",
                                                  "zero_size", "huge_size", "bad_projection", "weird_distortion",
                                                  "other_size" };
  const std::string c = rng.pick(cases);
  const std::vector<double> bad = { 0.0, -0.0, std::nan(""), std::numeric_limits<double>::infinity(),
                                    -std::numeric_limits<double>::infinity(), -525.0, -1e-300 };
  if (c == "zero_focal")
    m.K[rng.chance(0.5) ? 0 : 4] = 0.0;
  else if (c == "nan_intrinsics")
    m.K[rng.pick(std::vector<int>{ 0, 2, 4, 5 })] = std::nan("");
  else if (c == "negative_focal")
    m.K[rng.chance(0.5) ? 0 : 4] = -static_cast<double>(rng.in(1, 1000));
  else if (c == "inf_centre")
    m.K[rng.chance(0.5) ? 2 : 5] = rng.chance(0.5) ? std::numeric_limits<double>::infinity() : std::nan("");
  else if (c == "zero_size")
  {
    m.width = rng.chance(0.5) ? 0 : width;
    m.height = m.width ? 0 : height;
  }
  else if (c == "huge_size")
  {
    m.width = static_cast<std::uint32_t>(rng.in(8193, 0xffffffffu));
    m.height = static_cast<std::uint32_t>(rng.in(8193, 0xffffffffu));
  }
  else if (c == "bad_projection")
    m.P[rng.pick(std::vector<int>{ 0, 2, 5, 6 })] = rng.pick(bad);
  else if (c == "weird_distortion")
  {
    // Well-formed as far as the checks go (they do not read D): any length, any values.
    m.distortion_model = rng.pick(std::vector<std::string>{ "", "rational_polynomial", "equidistant", "nonsense" });
    m.D.assign(rng.in(0, 20), 0.0);
    for (double& d : m.D)
      d = rng.chance(0.3) ? rng.pick(bad) : static_cast<double>(rng.in(0, 1000)) - 500.0;
  }
  else  // other_size: a valid camera_info for other images than the stream's
  {
    m = goodInfo(static_cast<std::uint32_t>(rng.in(1, 200)), static_cast<std::uint32_t>(rng.in(1, 200)));
  }
  return { m, c };
}

// ---- bags ------------------------------------------------------------------------------------

std::string writeBadBag(const std::string& path, std::uint64_t seed)
{
  Rng rng(seed);
  static const std::vector<std::string> cases = {
    "short_image_data", "wrong_step", "huge_step", "missing_camera_info", "stamps_equal", "stamps_backwards",
    "zero_stamps", "size_mismatch", "bad_intrinsics", "wrong_encoding", "zero_size_images", "compressed_garbage",
    "points_malformed", "points_nan", "wrong_type_on_topic", "garbage_bytes", "truncated", "empty_file",
    "random_file", "nan_depth"
  };
  std::string c = rng.pick(cases);
  if (c == "points_malformed" || c == "points_nan")  // named after the malformed cloud inside, too
    c += ":" + badCloud(seed ^ 0x5eedull).variant;
  if (c == "empty_file")
  {
    writeFile(path, rng.chance(0.5) ? "" : "#ROSBAG V2.0\n");
    return c;
  }
  if (c == "random_file")
  {
    writeFile(path, (rng.chance(0.5) ? "#ROSBAG V2.0\n" : "") + randomBytes(rng, rng.in(1, 20000)));
    return c;
  }
  const BagLayout topics;
  const std::uint32_t w = 64, h = 48;
  const int frames = static_cast<int>(rng.in(2, 6));
  const int bad_frame = static_cast<int>(rng.in(0, frames - 1));
  {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    if (rng.chance(0.3))
      bag.setCompression(rosbag::compression::LZ4);
    for (int f = 0; f < frames; ++f)
    {
      double stamp = 1.0 + f / 15.0;
      if (c == "stamps_equal")
        stamp = 1.0;
      else if (c == "stamps_backwards")
        stamp = 10.0 - f / 15.0;
      else if (c == "zero_stamps")
        stamp = 0.0;
      const ros::Time t(stamp), when = std::max(t, ros::TIME_MIN);
      const bool bad = f == bad_frame;
      if (c.rfind("points_", 0) == 0)
      {
        sensor_msgs::PointCloud2 p = goodCloud(w, h);
        if (bad)
        {
          auto g = badCloud(seed ^ 0x5eedull);
          p = g.value;
          if (c.rfind("points_nan", 0) == 0)
            for (std::size_t at = 0; at + 12 <= p.data.size() && p.point_step > 0; at += p.point_step)
              putFloat(p.data, at, kNaN);
        }
        p.header.stamp = t;
        bag.write(topics.points, when, p);
        continue;
      }
      sensor_msgs::CameraInfo info = goodInfo(w, h);
      sensor_msgs::Image depth = goodImage(rng.chance(0.5) ? "32FC1" : "16UC1", w, h), rgb = goodImage("rgb8", w, h);
      if (bad)
      {
        sensor_msgs::Image& victim = rng.chance(0.5) ? depth : rgb;
        if (c == "short_image_data")
          victim.data.resize(rng.in(0, victim.data.size() - 1));
        else if (c == "wrong_step")
          victim.step = rng.chance(0.5) ? victim.step - static_cast<std::uint32_t>(rng.in(1, victim.step)) :
                                          victim.step + static_cast<std::uint32_t>(rng.in(1, 16));
        else if (c == "huge_step")
          victim.step = 0xffffffffu - static_cast<std::uint32_t>(rng.in(0, 100));
        else if (c == "size_mismatch")
          depth = goodImage(depth.encoding, w + static_cast<std::uint32_t>(rng.in(0, 8)),
                            h + static_cast<std::uint32_t>(rng.in(1, 8)));
        else if (c == "bad_intrinsics")
          info = badInfo(seed, w, h).value;
        else if (c == "wrong_encoding")
          victim.encoding = rng.pick(std::vector<std::string>{ "mono16", "rgba8", "8UC1", "", "bgra8", "mono8" });
        else if (c == "zero_size_images")
        {
          victim.width = victim.height = 0;
          victim.step = 0;
          victim.data.clear();
        }
        else if (c == "nan_depth" && depth.encoding == "32FC1")
          for (std::size_t i = 0; i + 4 <= depth.data.size(); i += 4)
            putFloat(depth.data, i, rng.pick(std::vector<float>{ kNaN, kInf, -kInf, -2.0f, 1e30f }));
      }
      info.header.stamp = depth.header.stamp = rgb.header.stamp = t;
      if (c != "missing_camera_info")
        bag.write(topics.info, when, info);
      if (c == "compressed_garbage" && bad)
      {
        sensor_msgs::CompressedImage ci;
        ci.header.stamp = t;
        ci.format = rng.pick(std::vector<std::string>{ "png", "jpeg", "16UC1; compressedDepth", "" });
        ci.data.resize(rng.in(0, 3000));
        for (auto& b : ci.data)
          b = static_cast<std::uint8_t>(rng.in(0, 255));
        if (rng.chance(0.5) && ci.data.size() >= 8)  // a PNG signature in front of the garbage
          std::memcpy(ci.data.data(), "\x89PNG\r\n\x1a\n", 8);
        bag.write((rng.chance(0.5) ? topics.depth : topics.rgb) + "/compressed", when, ci);
        continue;
      }
      if (c == "wrong_type_on_topic" && bad)
      {
        std_msgs::String s;
        s.data = randomWord(rng, 0, 64);
        bag.write(rng.chance(0.5) ? topics.depth : topics.info, when, s);
        bag.write(topics.rgb, when, rgb);
        continue;
      }
      bag.write(topics.depth, when, depth);
      bag.write(topics.rgb, when, rgb);
    }
    bag.close();
  }
  if (c == "garbage_bytes" || c == "truncated")
  {
    std::string bytes = readFile(path);
    if (c == "truncated")
      bytes.resize(rng.in(0, bytes.size() - 1));
    else
      for (int k = 0, n = static_cast<int>(rng.in(1, 64)); k < n && !bytes.empty(); ++k)
        bytes[rng.in(0, bytes.size() - 1)] = static_cast<char>(rng.in(0, 255));
    writeFile(path, bytes);
  }
  return c;
}

// ---- models ------------------------------------------------------------------------------------

std::string validModelBytes(const std::string& scratch_dir, bool posture_flow)
{
  const std::string path = scratch_dir + (posture_flow ? "/valid_posture_flow.afm" : "/valid_paper.afm");
  ActionModel model;
  if (posture_flow)
  {
    model.params = defaultRecognitionParams();
    model.params.pyramid.c = 1.0;
    model.params.pyramid.flow = FlowEncoding::Bins;
    model.params.pyramid.mirror = MirrorMode::Off;
    model.descriptors = Eigen::MatrixXf::Zero(2, model.sequenceLength());
    model.descriptors.row(1).setConstant(1.0f);
    model.labels = { "still", "moving" };
    model.persons = { "a", "b" };
    model.linear = LinearClassifier::train(model.descriptors, model.labels, model.params.pyramid.c);
  }
  else
  {
    const int per_frame = 3 * model.params.grid.cells(), frames = model.params.frames;
    model.descriptors = Eigen::MatrixXf::Zero(2, per_frame * frames);
    for (int f = 0; f < frames; ++f)
    {
      model.descriptors(0, f * per_frame) = 1.0f;
      model.descriptors(1, f * per_frame + 1) = 1.0f;
    }
    model.labels = { "raise", "push" };
    model.persons = { "a", "a" };
  }
  model.save(path);
  return readFile(path);
}

Generated<std::string> mutateModel(const std::string& model, std::uint64_t seed)
{
  Rng rng(seed);
  // The file: 8 bytes magic, u32 version, u64 payload size, u32 CRC-32, payload. Most damage is
  // caught by the size and checksum; the "resealed" cases fix both up afterwards so that the
  // payload's parser itself meets the damage.
  constexpr std::size_t kHead = 8 + 4 + 8 + 4;
  static const std::vector<std::string> cases = { "byte_flips", "truncated", "inserted", "removed", "huge_word",
                                                  "appended", "empty", "header_only", "version",
                                                  "resealed_flips", "resealed_huge_word", "resealed_truncated",
                                                  "resealed_small_word", "resealed_floats" };
  const std::string c = rng.pick(cases);
  std::string m = model;
  const auto somewhere = [&](std::size_t from) { return rng.in(from, m.size() - 1); };
  const std::size_t from = c.rfind("resealed", 0) == 0 ? kHead : 0;
  if (c == "byte_flips" || c == "resealed_flips")
    for (int k = 0, n = static_cast<int>(rng.in(1, 16)); k < n; ++k)
      m[somewhere(from)] ^= static_cast<char>(1u << rng.in(0, 7));
  else if (c == "truncated" || c == "resealed_truncated")
    m.resize(rng.in(from, m.size() - 1));
  else if (c == "inserted")
    m.insert(somewhere(0), randomBytes(rng, rng.in(1, 64)));
  else if (c == "removed")
    m.erase(somewhere(0), rng.in(1, 64));
  else if (c == "huge_word" || c == "resealed_huge_word" || c == "resealed_small_word")
  {
    // Sizes are u64 words at unknown offsets: overwrite 8 aligned-or-not bytes with an edge value.
    const std::uint64_t values[] = { ~0ull, 1ull << 63, 1ull << 40, 0x7fffffffull, 0xffffffffull, 1ull << 31 };
    std::uint64_t v = c == "resealed_small_word" ? rng.in(0, 5000) : values[rng.in(0, 5)];
    const std::size_t at = std::min(somewhere(from), m.size() >= 8 ? m.size() - 8 : 0);
    std::memcpy(&m[at], &v, std::min<std::size_t>(8, m.size() - at));
  }
  else if (c == "resealed_floats")
    for (int k = 0, n = static_cast<int>(rng.in(1, 32)); k < n && m.size() >= kHead + 4; ++k)
    {
      const float v = rng.pick(std::vector<float>{ kNaN, kInf, -kInf, 3e38f, -0.0f, 1e-45f });
      std::memcpy(&m[rng.in(kHead, m.size() - 4)], &v, 4);
    }
  else if (c == "appended")
    m += randomBytes(rng, rng.in(1, 1000));
  else if (c == "empty")
    m.clear();
  else if (c == "header_only")
    m.resize(rng.in(0, kHead));
  else  // version
  {
    const std::uint32_t v = rng.pick(std::vector<std::uint32_t>{ 0, 1, 3, 0xffffffffu });
    std::memcpy(&m[8], &v, 4);
  }
  if (from == kHead && m.size() >= kHead)
  {
    const std::uint64_t size = m.size() - kHead;
    boost::crc_32_type crc;
    crc.process_bytes(m.data() + kHead, size);
    const std::uint32_t sum = crc.checksum();
    std::memcpy(&m[12], &size, 8);
    std::memcpy(&m[20], &sum, 4);
  }
  return { m, c };
}

// ---- index CSVs --------------------------------------------------------------------------------

Generated<std::string> badIndex(std::uint64_t seed, const std::string& bag)
{
  Rng rng(seed);
  const std::string header = "path,person,action,repetition,frames\n";
  const std::string line = bag + ",p01,wave,1,5\n";
  static const std::vector<std::string> cases = { "missing_column", "extra_field", "missing_field", "non_numeric",
                                                  "huge_number", "negative", "empty_field", "duplicate",
                                                  "missing_file", "binary", "long_line", "no_header", "quotes",
                                                  "bom_crlf", "folder_as_sample", "header_only" };
  const std::string c = rng.pick(cases);
  std::string s;
  if (c == "missing_column")
  {
    std::vector<std::string> cols = { "path", "person", "action", "repetition", "frames" };
    cols.erase(cols.begin() + static_cast<long>(rng.in(0, 4)));
    if (rng.chance(0.3))
      cols.push_back(rng.pick(std::vector<std::string>{ "Path", "framez", "" }));
    for (std::size_t i = 0; i < cols.size(); ++i)
      s += (i ? "," : "") + cols[i];
    s += "\n" + line;
  }
  else if (c == "extra_field")
    s = header + bag + ",p01,wave,1,5," + randomWord(rng, 0, 8) + "\n";
  else if (c == "missing_field")
    s = header + rng.pick(std::vector<std::string>{ bag + ",p01,wave,1", bag + ",p01", bag, "" + std::string(",") }) + "\n";
  else if (c == "non_numeric")
    s = header + bag + ",p01,wave," +
        rng.pick(std::vector<std::string>{ "one", "1.5", "0x10", "1e3", " 1", "1a", "--1", "+" }) + ",5\n";
  else if (c == "huge_number")
    s = header + bag + ",p01,wave," +
        rng.pick(std::vector<std::string>{ "99999999999999999999", "2147483648", "4294967296",
                                           "-9223372036854775809" }) +
        "," + (rng.chance(0.5) ? "5" : "99999999999999999999") + "\n";
  else if (c == "negative")
    s = header + bag + ",p01,wave,-1," + (rng.chance(0.5) ? "-5" : "5") + "\n";
  else if (c == "empty_field")
  {
    const int k = static_cast<int>(rng.in(0, 4));
    std::vector<std::string> f = { bag, "p01", "wave", "1", "5" };
    f[k].clear();
    s = header + f[0] + "," + f[1] + "," + f[2] + "," + f[3] + "," + f[4] + "\n";
  }
  else if (c == "duplicate")
    s = header + line + line;
  else if (c == "missing_file")
    s = header + rng.pick(std::vector<std::string>{ "no_such.bag", "/nonexistent/x.bag", "../../../../x.bag", " .bag" }) +
        ",p01,wave,1,5\n";
  else if (c == "binary")
    s = (rng.chance(0.5) ? header : std::string()) + randomBytes(rng, rng.in(1, 2000));
  else if (c == "long_line")
    s = header + bag + "," + std::string(rng.in(10000, 200000), 'p') + ",wave,1,5\n" +
        std::string(rng.in(10000, 100000), ',') + "\n";
  else if (c == "no_header")
    s = line + line;
  else if (c == "quotes")
    s = header + "\"" + bag + "\",\"p01\",wave,1,5\n\"unterminated," + bag + ",p02,wave,1,5\n";
  else if (c == "bom_crlf")
    s = "\xef\xbb\xbfpath,person,action,repetition,frames\r\n" + bag + ",p01,wave,1,5\r\n" + bag + ",p02,wave,x,5\r\n";
  else if (c == "folder_as_sample")
    s = header + rng.pick(std::vector<std::string>{ "/", ".", "/tmp", "/dev/null", "/proc/self/status" }) +
        ",p01,wave,1,5\n";
  else  // header_only
    s = rng.chance(0.5) ? header : "# only a comment\n" + header + "\n\n# and another\n";
  return { s, c };
}

// ---- MSR skeletons ---------------------------------------------------------------------------

std::string validSkeleton(int frames)
{
  // A standing person 2.5 m from the camera, in the files' numbering (1-based): 1,2 shoulders; 3
  // neck; 4 spine; 5,6 hips; 7 hip centre; 8,9 elbows; 10,11 wrists; 12,13 hands; 14,15 knees;
  // 16,17 ankles; 18,19 feet; 20 head. Metres, y up; the right arm swings.
  static const float joints[20][3] = {
    { -0.18f, 0.45f, 2.5f }, { 0.18f, 0.45f, 2.5f },  { 0.0f, 0.5f, 2.5f },    { 0.0f, 0.2f, 2.5f },
    { -0.1f, -0.05f, 2.5f }, { 0.1f, -0.05f, 2.5f },  { 0.0f, 0.0f, 2.5f },    { -0.22f, 0.2f, 2.5f },
    { 0.22f, 0.2f, 2.5f },   { -0.24f, -0.02f, 2.5f }, { 0.24f, -0.02f, 2.5f }, { -0.25f, -0.08f, 2.5f },
    { 0.25f, -0.08f, 2.5f }, { -0.1f, -0.45f, 2.5f },  { 0.1f, -0.45f, 2.5f },  { -0.1f, -0.85f, 2.5f },
    { 0.1f, -0.85f, 2.5f },  { -0.1f, -0.9f, 2.4f },   { 0.1f, -0.9f, 2.4f },   { 0.0f, 0.7f, 2.5f }
  };
  std::ostringstream s;
  for (int f = 0; f < frames; ++f)
    for (int j = 0; j < 20; ++j)
    {
      const float lift = (j == 8 || j == 10 || j == 12) ? 0.03f * f : 0.0f;
      s << joints[j][0] << " " << joints[j][1] + lift << " " << joints[j][2] << " " << (j == 19 ? 0.5 : 1) << "\n";
    }
  return s.str();
}

Generated<std::string> badSkeleton(std::uint64_t seed)
{
  Rng rng(seed);
  const int frames = static_cast<int>(rng.in(1, 6));
  std::vector<std::string> lines;
  {
    std::istringstream in(validSkeleton(frames));
    std::string l;
    while (std::getline(in, l))
      lines.push_back(l);
  }
  static const std::vector<std::string> cases = { "nan", "inf", "confidence", "missing_column", "extra_column",
                                                  "missing_lines", "extra_lines", "not_numbers", "empty", "all_zero",
                                                  "huge_coordinates", "collapsed", "binary", "behind_camera",
                                                  "long_line", "hex_and_exponents" };
  const std::string c = rng.pick(cases);
  const auto at = [&]() -> std::string& { return lines[rng.in(0, lines.size() - 1)]; };
  std::string text;
  if (c == "nan" || c == "inf")
    at() = c == "nan" ? "nan 0.1 2.5 1" : rng.pick(std::vector<std::string>{ "inf 0 2 1", "0 -inf 2 1", "0 0 1e999 1" });
  else if (c == "confidence")
    at() = "0.1 0.2 2.5 " + rng.pick(std::vector<std::string>{ "-0.5", "1.5", "1e9", "-1e-9" });
  else if (c == "missing_column")
    at() = "0.1 0.2 2.5";
  else if (c == "extra_column")
    at() += rng.pick(std::vector<std::string>{ " 1", " x", " 0 0 0" });
  else if (c == "missing_lines")
    lines.erase(lines.begin() + static_cast<long>(rng.in(0, lines.size() - 1)));
  else if (c == "extra_lines")
    for (int k = 0, n = static_cast<int>(rng.in(1, 19)); k < n; ++k)
      lines.push_back("0.1 0.2 2.5 1");
  else if (c == "not_numbers")
    at() = rng.pick(std::vector<std::string>{ "a b c d", "0,1,2,1", "--1 0 0 1", "", "   ", "0.1 0.2 2.5 1 # note" });
  else if (c == "all_zero")
    for (auto& l : lines)
      l = "0 0 0 " + std::string(rng.chance(0.5) ? "0" : "1");
  else if (c == "huge_coordinates")
    for (auto& l : lines)
      l = rng.pick(std::vector<std::string>{ "1e30", "-3e38", "1e300", "1e-300" }) + " " +
          rng.pick(std::vector<std::string>{ "1e30", "0.1", "-1e300" }) + " " +
          rng.pick(std::vector<std::string>{ "2.5", "1e38", "-1e30", "1e300" }) + " 1";
  else if (c == "collapsed")
    for (auto& l : lines)
      l = "0.1 0.2 2.5 1";
  else if (c == "behind_camera")
    for (auto& l : lines)
    {
      std::istringstream ls(l);
      double x, y, z, conf;
      ls >> x >> y >> z >> conf;
      std::ostringstream o;
      o << x << " " << y << " " << rng.pick(std::vector<double>{ -z, 0.0, 0.001, 1e6 }) << " " << conf;
      l = o.str();
    }
  else if (c == "long_line")
    at() = std::string(rng.in(10000, 200000), '1');
  else if (c == "hex_and_exponents")
    at() = rng.pick(std::vector<std::string>{ "0x1p3 0 2 1", "1e 0 2 1", ".5 .5 .5 .5", "1e+ 0 2 1" });
  if (c == "empty")
    text = rng.pick(std::vector<std::string>{ "", "\n", "\n\n\n", "\r\n" });
  else if (c == "binary")
    text = randomBytes(rng, rng.in(1, 3000));
  else
    for (const auto& l : lines)
      text += l + (rng.chance(0.05) ? "\r\n" : "\n");
  return { text, c };
}

// ---- command lines ------------------------------------------------------------------------------

namespace
{
struct IntOption
{
  std::string name;
  long lo, hi;
};

// The tools' options and their documented ranges (train/evaluate: cli.h and sample_sources.cpp;
// synth: synth.cpp). A value outside them, or not a decimal number, must be refused.
const std::vector<IntOption>& intOptions(const std::string& tool)
{
  static const std::vector<IntOption> train = { { "jobs", 1, 64 },       { "frames", 1, 1000 },
                                                { "neighbours", 1, 1000 }, { "k", 1, 1000 },
                                                { "temporal-levels", 1, 4 }, { "people", 1, 1000 },
                                                { "repetitions", 1, 100 }, { "seed", 0, 1000000000 },
                                                { "max-frames", 0, 100000 } };
  static std::vector<IntOption> evaluate;
  if (evaluate.empty())
  {
    evaluate = train;
    evaluate.push_back({ "sweep", 0, 200 });
  }
  static const std::vector<IntOption> synth = {
    { "people", 1, 99 },   { "repetitions", 1, 99 }, { "first-person", 1, 99 }, { "streams", 1, 99 },
    { "stream-actions", 1, 99 }, { "seed", 0, 2147483647 }, { "repetition", 1, 99 }, { "every", 1, 1000000 },
    { "limit", 1, 1000000 }, { "frames", 1, 1000000 }, { "jobs", 1, 64 },  { "jpeg-quality", 1, 100 }
  };
  return tool == "synth" ? synth : tool == "evaluate" ? evaluate : train;
}

std::set<std::string> knownOptions(const std::string& tool)
{
  if (tool == "synth")
    return { "help",        "dataset",     "skeletons",  "all-msr",    "people",       "repetitions", "first-person",
             "streams",     "stream-actions", "seed",    "person",     "action",       "repetition",  "every",
             "limit",       "frames",      "out",        "jobs",       "skip-existing", "points",     "raw-images",
             "compression", "jpeg-quality", "points-topic", "rgb-topic", "depth-topic", "info-topic", "mask-topic",
             "tf-topic",    "action-topic", "list",      "preview",    "preview-at",   "montage",     "quiet" };
  std::set<std::string> o = { "help", "output", "index", "jobs", "cache", "exclude-person", "allow-empty",
                              "points-topic", "depth-topic", "rgb-topic", "info-topic", "synth", "people",
                              "repetitions", "seed", "msr-dir", "max-frames", "actions", "recognizer", "descriptor",
                              "frames", "pca-variance", "neighbours", "k", "classifier", "c", "temporal-levels", "pca",
                              "no-outlier-rejection", "no-posture", "no-direction-histogram", "single-level",
                              "no-mirror", "mirror", "direction-histogram" };
  if (tool == "evaluate")
    o.insert({ "protocol", "train-persons", "variants", "sweep", "no-plots", "stream-people", "streams",
               "stream-actions", "tuning-people" });
  return o;
}

// Values that are no whole number in [lo, hi] as the tools read them.
std::string badInteger(Rng& rng, const IntOption& o, bool synth)
{
  std::vector<std::string> v = { std::to_string(o.hi + 1), "99999999999999999999", "-99999999999999999999",
                                 "0x10", "1.5", "", "12abc", "1e3", "--", "٣", "0x" };
  if (o.lo > -1000000000)
    v.push_back(std::to_string(o.lo - 1));
  if (o.lo >= 0)
    v.push_back("-" + std::to_string(rng.in(1, 1000)));
  if (!synth)  // train/evaluate read decimal digits only; synth's strtol also takes " 5" and "+5"
  {
    v.push_back(" 5");
    v.push_back("+5");
    v.push_back(std::to_string(o.hi) + " ");
  }
  return rng.pick(v);
}
}  // namespace

Generated<BadCommand> badCommand(const std::string& tool, std::uint64_t seed, const std::string& scratch)
{
  Rng rng(seed);
  const bool synth = tool == "synth";
  // A cheap valid base: if the bad element were ignored, the tool would quickly exit 1 for another
  // reason (nobody tracked in 2 frames) or 0 (synth renders 2 frames), which the suite catches.
  std::vector<std::pair<std::string, std::string>> base;
  if (synth)
    base = { { "--out", scratch + "/synth_out" }, { "--people", "1" },  { "--repetitions", "1" },
             { "--action", "wave" },             { "--frames", "2" },  { "--quiet", "" },
             { "--limit", "1" } };
  else
  {
    base = { { "--output", scratch + (tool == "train" ? "/m.afm" : "/report") }, { "--synth", "ias" },
             { "--people", "1" },  { "--repetitions", "1" },  { "--max-frames", "2" },
             { "--actions", "wave" }, { "--cache", scratch + "/cache" }, { "--jobs", "1" } };
    if (tool == "evaluate")
      base.push_back({ "--sweep", "0" });
    if (rng.chance(0.3))
      base.push_back({ "--recognizer", "paper" });
    if (rng.chance(0.3))
      base.push_back({ "--no-mirror", "" });
  }
  static const std::vector<std::string> cases = { "unknown_option", "bad_integer", "bad_number", "bad_choice",
                                                  "missing_value", "stray_argument" };
  std::string c = rng.pick(cases);
  if (synth && c == "bad_number")
    c = "bad_integer";
  BadCommand cmd;
  std::pair<std::string, std::string> bad;
  bool last = false;  // the bad element must be the last argument
  if (c == "unknown_option")
  {
    const auto known = knownOptions(tool);
    std::string name;
    do
      name = randomWord(rng, 1, 24);
    while (known.count(name) || name.empty());
    if (rng.chance(0.2))
      name += "=" + randomWord(rng, 0, 6);
    bad = { "--" + name, "" };  // a flag: a value after it would be refused as a stray argument first
    cmd.culprit = "--" + name;
  }
  else if (c == "bad_integer")
  {
    const IntOption o = rng.pick(intOptions(tool));
    bad = { "--" + o.name, badInteger(rng, o, synth) };
    cmd.culprit = "--" + o.name;
  }
  else if (c == "bad_number")
  {
    const bool pca = rng.chance(0.5);
    bad = { pca ? "--pca-variance" : "--c",
            pca ? rng.pick(std::vector<std::string>{ "nan", "0", "-0.5", "1.0001", "inf", "abc", "", "0.5x", "1e999" }) :
                  rng.pick(std::vector<std::string>{ "nan", "-1", "1e7", "inf", "-inf", "x", "", "1,5", "0x1p30" }) };
    cmd.culprit = bad.first;
  }
  else if (c == "bad_choice")
  {
    const std::string value = rng.pick(std::vector<std::string>{ "", "nonsense", "IAS", "paper ", "posture-flow",
                                                                 randomWord(rng, 1, 12) });
    if (synth)
    {
      bad = { "--" + rng.pick(std::vector<std::string>{ "dataset", "compression", "action" }), value };
      if (bad.first == "--action" && value.empty())  // synth reads an empty --action as "every action"
        bad.second = "nonsense";
      cmd.culprit = bad.first;
    }
    else
    {
      std::vector<std::string> names = { "recognizer", "classifier", "descriptor", "synth" };
      if (tool == "evaluate")
      {
        names.push_back("protocol");
        names.push_back("variants");
      }
      bad = { "--" + rng.pick(names), value };
      // The choice's error quotes the value, or names the option when it is empty ("unknown protocol ''").
      cmd.culprit = value.empty() ? bad.first.substr(2) : value;
    }
  }
  else if (c == "missing_value")
  {
    std::vector<std::string> valued;
    for (const auto& o : intOptions(tool))
      valued.push_back(o.name);
    valued.push_back(synth ? "out" : "output");
    bad = { "--" + rng.pick(valued), "" };
    cmd.culprit = bad.first;
    last = true;
  }
  else  // stray_argument
  {
    const std::string word = rng.pick(std::vector<std::string>{ "foo", "-x", "-", "x=1", randomWord(rng, 1, 12) });
    bad = { word, "" };
    cmd.culprit = word;
  }
  // The bad element replaces the base's option of the same name (a repeated option: the last wins).
  base.erase(std::remove_if(base.begin(), base.end(), [&](const auto& b) { return b.first == bad.first; }), base.end());
  if (c == "bad_choice" && bad.first == "--synth")
    base.erase(std::remove_if(base.begin(), base.end(), [&](const auto& b) { return b.first == "--synth"; }),
               base.end());
  std::shuffle(base.begin(), base.end(), rng.engine());
  const std::size_t where = last ? base.size() : rng.in(0, base.size());
  base.insert(base.begin() + static_cast<long>(where), bad);
  for (const auto& [name, value] : base)
  {
    cmd.args.push_back(name);
    const bool flag = name == "--quiet" || name == "--no-mirror" ||
                      (name == bad.first && (c == "unknown_option" || c == "stray_argument" || c == "missing_value"));
    if (!flag)
      cmd.args.push_back(value);
  }
  return { cmd, c };
}

}  // namespace fuzz
}  // namespace action_flow
