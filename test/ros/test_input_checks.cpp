// The checks of messages entering the manager, on hand-made good and malformed messages; and the
// InputCloud wire path: a good PointCloud2 becomes the same cloud, a bad one an error and no cloud.
#include <action_flow/ros/input_checks.h>

#include <gtest/gtest.h>
#include <random>
#include <pcl_conversions/pcl_conversions.h>

using namespace action_flow;

namespace
{
sensor_msgs::PointCloud2 goodCloud(int width = 4, int height = 3)
{
  Cloud c(width, height);
  for (std::size_t i = 0; i < c.size(); ++i)
  {
    c[i].x = static_cast<float>(i);
    c[i].y = 1.0f;
    c[i].z = 2.0f;
    c[i].r = 10;
  }
  sensor_msgs::PointCloud2 m;
  pcl::toROSMsg(c, m);
  return m;
}

sensor_msgs::Image image(const std::string& encoding, int width, int height, int bytes)
{
  sensor_msgs::Image m;
  m.encoding = encoding;
  m.width = width;
  m.height = height;
  m.step = width * bytes;
  m.data.resize(m.step * height);
  return m;
}

sensor_msgs::CameraInfo info()
{
  sensor_msgs::CameraInfo m;
  m.width = 640;
  m.height = 480;
  m.K = { 525, 0, 319.5, 0, 525, 239.5, 0, 0, 1 };
  m.P = { 525, 0, 319.5, 0, 0, 525, 239.5, 0, 0, 0, 1, 0 };
  return m;
}

void expectRefused(const sensor_msgs::PointCloud2& m, const std::string& part)
{
  const std::string e = checkPointCloud2(m);
  EXPECT_NE(e.find(part), std::string::npos) << "expected '" << part << "', got '" << e << "'";
  InputCloud in;
  InputCloud::fromWire(m, in);
  EXPECT_FALSE(in.cloud);
  EXPECT_EQ(in.error, e);
}
}  // namespace

TEST(InputChecks, GoodCloudPassesAndConvertsExactly)
{
  const sensor_msgs::PointCloud2 m = goodCloud();
  EXPECT_EQ(checkPointCloud2(m), "");
  InputCloud in;
  InputCloud::fromWire(m, in);
  ASSERT_TRUE(in.cloud);
  EXPECT_EQ(in.error, "");
  EXPECT_EQ(in.cloud->width, 4u);
  EXPECT_EQ(in.cloud->height, 3u);
  EXPECT_EQ((*in.cloud)[5].x, 5.0f);
  EXPECT_EQ((*in.cloud)[5].r, 10);
}

TEST(InputChecks, EachKindOfMalformedCloudIsRefusedWithItsReason)
{
  sensor_msgs::PointCloud2 m = goodCloud();
  m.data.resize(m.data.size() + 16);
  expectRefused(m, "bytes of data");
  m = goodCloud();
  m.data.resize(100);
  expectRefused(m, "bytes of data");
  m = goodCloud();
  m.width = 10000000;
  expectRefused(m, "more than the");
  m = goodCloud();
  m.point_step = 1u << 30;
  expectRefused(m, "row_step");
  m = goodCloud();
  m.row_step += 4;
  expectRefused(m, "row_step");
  m = goodCloud();
  m.fields.erase(m.fields.begin());  // x
  expectRefused(m, "has no 'x' field");
  m = goodCloud();
  m.fields[1].offset = m.point_step;  // y outside the point
  expectRefused(m, "outside the point_step");
  m = goodCloud();
  m.fields[2].datatype = sensor_msgs::PointField::FLOAT64;
  expectRefused(m, "not one FLOAT32");
  m = goodCloud();
  m.is_bigendian = true;
  expectRefused(m, "big-endian");
  m = goodCloud(0, 0);
  EXPECT_EQ(checkPointCloud2(m), "") << "an empty cloud is well-formed (the tracker reports it empty)";
}

TEST(InputChecks, ImagesAndCameraInfo)
{
  EXPECT_EQ(checkImage(image("rgb8", 640, 480, 3)), "");
  EXPECT_EQ(checkImage(image("32FC1", 640, 480, 4)), "");
  EXPECT_NE(checkImage(image("rgb8", 0, 0, 3)).find("pixels"), std::string::npos);
  EXPECT_NE(checkImage(image("yuv422", 640, 480, 2)).find("encoding"), std::string::npos);
  sensor_msgs::Image m = image("16UC1", 640, 480, 2);
  m.data.clear();
  EXPECT_NE(checkImage(m).find("bytes of data"), std::string::npos);
  m = image("16UC1", 640, 480, 2);
  m.step = 1u << 31;
  EXPECT_NE(checkImage(m).find("step"), std::string::npos);
  m = image("16UC1", 640, 480, 2);
  m.step = 100;
  EXPECT_NE(checkImage(m).find("less than width"), std::string::npos);

  EXPECT_EQ(checkCameraInfo(info()), "");
  sensor_msgs::CameraInfo i = info();
  i.K[0] = 0.0;
  EXPECT_NE(checkCameraInfo(i).find("intrinsics"), std::string::npos);
  i = info();
  i.K[4] = std::nan("");
  EXPECT_NE(checkCameraInfo(i).find("intrinsics"), std::string::npos);
  i = info();
  i.P[5] = -1.0;
  EXPECT_NE(checkCameraInfo(i).find("projection"), std::string::npos);
  i = info();
  i.width = 0;
  EXPECT_NE(checkCameraInfo(i).find("images"), std::string::npos);
}

namespace
{
// A random mutation of a good message's header and data length, as a fuzzer would make it.
sensor_msgs::PointCloud2 mutatedCloud(const sensor_msgs::PointCloud2& good, std::mt19937& rng)
{
  sensor_msgs::PointCloud2 m = good;
  std::uniform_int_distribution<int> what(0, 9);
  const auto big = [&]() { return std::uniform_int_distribution<std::uint32_t>(0, 1u << 31)(rng); };
  const auto small = [&]() { return std::uniform_int_distribution<std::uint32_t>(0, 64)(rng); };
  for (int k = 0, n = 1 + what(rng) % 3; k < n; ++k)
    switch (what(rng))
    {
      case 0: m.width = what(rng) < 5 ? big() : small(); break;
      case 1: m.height = what(rng) < 5 ? big() : small(); break;
      case 2: m.point_step = what(rng) < 5 ? big() : small(); break;
      case 3: m.row_step = what(rng) < 5 ? big() : small(); break;
      case 4: m.data.resize(std::uniform_int_distribution<std::size_t>(0, 2 * good.data.size())(rng)); break;
      case 5:
        if (!m.fields.empty())
          m.fields[what(rng) % m.fields.size()].offset = what(rng) < 5 ? big() : small();
        break;
      case 6:
        if (!m.fields.empty())
          m.fields[what(rng) % m.fields.size()].datatype = static_cast<std::uint8_t>(what(rng));
        break;
      case 7: m.fields.resize(what(rng) % (m.fields.size() + 1)); break;
      case 8: m.is_bigendian = !m.is_bigendian; break;
      default:
        if (!m.fields.empty())
          m.fields[what(rng) % m.fields.size()].count = small();
    }
  return m;
}
}  // namespace

// A bounded fuzz corpus: 20,000 mutated headers. Each is refused with a reason or converts to a
// cloud of exactly its declared size; none crashes, reads out of bounds or allocates beyond it.
TEST(InputChecks, FuzzedCloudHeadersNeverGetPastTheCheckWrong)
{
  std::mt19937 rng(2026);
  const sensor_msgs::PointCloud2 good = goodCloud(8, 6);
  int refused = 0, converted = 0;
  for (int i = 0; i < 20000; ++i)
  {
    const sensor_msgs::PointCloud2 m = mutatedCloud(good, rng);
    InputCloud in;
    InputCloud::fromWire(m, in);
    if (in.cloud)
    {
      ++converted;
      ASSERT_EQ(in.error, "");
      ASSERT_EQ(static_cast<std::uint64_t>(in.cloud->size()), static_cast<std::uint64_t>(m.width) * m.height);
      ASSERT_EQ(m.data.size(), static_cast<std::size_t>(m.row_step) * m.height);
    }
    else
    {
      ++refused;
      ASSERT_FALSE(in.error.empty());
    }
  }
  EXPECT_GT(refused, 10000);
  EXPECT_GT(converted, 0) << "some mutations (of unused fields) are harmless and must pass";
  std::printf("fuzzed clouds: %d refused, %d converted\n", refused, converted);
}

// checkPng walks the chunks of a PNG before libpng sees it. A 1x1 16-bit grey PNG built by hand:
// its CRCs computed with zlib (IEND's is the well-known AE 42 60 82).
TEST(InputChecks, APngIsCheckedChunkByChunk)
{
  const std::vector<std::uint8_t> png = {
    0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n',
    0, 0, 0, 13, 'I', 'H', 'D', 'R', 0, 0, 0, 1, 0, 0, 0, 1, 16, 0, 0, 0, 0, 0x6a, 0xee, 0x47, 0x16,
    0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82 };
  EXPECT_EQ(checkPng(png), "");
  EXPECT_EQ(checkPng({ 0xff, 0xd8, 0xff, 0xe0, 1, 2, 3 }), "") << "not a PNG (a JPEG's start): left to the decoder";

  std::vector<std::uint8_t> flipped = png;
  flipped[20] ^= 0x01;  // the width's last byte
  EXPECT_NE(checkPng(flipped).find("CRC error in its chunk at byte 8"), std::string::npos) << checkPng(flipped);

  const std::vector<std::uint8_t> cut(png.begin(), png.end() - 12);
  EXPECT_NE(checkPng(cut).find("cut short at byte 33"), std::string::npos) << checkPng(cut);

  std::vector<std::uint8_t> huge = png;
  huge[8] = 0x7f;  // IHDR claims about 2 GB
  EXPECT_NE(checkPng(huge).find("past the end"), std::string::npos) << checkPng(huge);

  std::vector<std::uint8_t> no_header = png;
  no_header[12] = 'X';
  EXPECT_NE(checkPng(no_header).find("does not start with an IHDR"), std::string::npos) << checkPng(no_header);
}
