// The driver's device side without ROS: the libfreenect backend on fakenect dumps written here (no
// hardware: frames replayed with their depth in millimetres, the end of a dump, broken dumps
// refused with the file named, since fakenect itself would end the process, and an absent Kinect),
// and stamps from a device's own clock.
#include "../../src/driver/device_clock.h"
#include "../../src/driver/freenect_device.h"

#include <action_flow/kinect_depth.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

using namespace action_flow;
namespace fs = std::filesystem;

namespace
{
constexpr int kPixels = 640 * 480;

// A dump of @p frames frames: every depth pixel raw 743 but the first (no reading), colour (10, 20, 30)
// with frame k's first red byte k.
fs::path writeDump(const std::string& name, int frames)
{
  const fs::path dir = fs::path(::testing::TempDir()) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream index(dir / "INDEX.txt");
  std::vector<std::uint16_t> depth(kPixels, 743);
  depth[0] = kKinectRawNoReading;
  std::vector<std::uint8_t> rgb(3 * kPixels);
  for (int i = 0; i < kPixels; ++i)
    rgb[3 * i] = 10, rgb[3 * i + 1] = 20, rgb[3 * i + 2] = 30;
  for (int k = 0; k < frames; ++k)
  {
    rgb[0] = static_cast<std::uint8_t>(k);
    char r[64], d[64];
    std::snprintf(r, sizeof r, "r-%f-%u.ppm", 0.01 * k, 2000000u * k);
    std::snprintf(d, sizeof d, "d-%f-%u.pgm", 0.01 * k, 2000000u * k);
    std::ofstream(dir / r, std::ios::binary) << "P6 640 480 255\n"
                                             << std::string(reinterpret_cast<const char*>(rgb.data()), rgb.size());
    std::ofstream(dir / d, std::ios::binary) << "P5 640 480 65535\n"
                                             << std::string(reinterpret_cast<const char*>(depth.data()), 2 * depth.size());
    index << r << "\n" << d << "\n";
  }
  return dir;
}

std::string openError(const fs::path& dir)
{
  try
  {
    FreenectDevice device(dir.string(), "");
  }
  catch (const DeviceError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(FreenectDevice, ADumpIsReplayedFrameByFrameWithItsDepthInMillimetres)
{
  ASSERT_FALSE(FreenectDevice::builtInFakenectLibrary().empty()) << "the build found no fakenect library";
  const fs::path dir = writeDump("fakenect_good", 3);
  FreenectDevice device(dir.string(), "");
  device.start();
  RgbdFrame frame;
  for (int k = 0; k < 3; ++k)
  {
    ASSERT_TRUE(device.read(frame, 2000)) << "frame " << k;
    ASSERT_EQ(frame.width, 640);
    ASSERT_EQ(frame.height, 480);
    ASSERT_EQ(frame.depth_mm.size(), std::size_t(kPixels));
    EXPECT_EQ(frame.depth_mm[0], 0) << "no reading";
    EXPECT_EQ(frame.depth_mm[1], std::lround(kinectRawToMetres(743) * 1000.0f));  // 999 mm
    EXPECT_EQ(frame.depth_mm[kPixels - 1], 999);
    EXPECT_EQ(frame.rgb[0], k) << "the colour frame that came before this depth frame";
    EXPECT_EQ(frame.rgb[4], 20);
    EXPECT_FLOAT_EQ(frame.fx, 525.0f);
    EXPECT_FLOAT_EQ(frame.cx, 319.5f);
  }
  EXPECT_THROW(device.read(frame, 2000), EndOfRecording);
}

TEST(FreenectDevice, ABrokenDumpIsRefusedWithTheFileNamed)
{
  const fs::path dir = writeDump("fakenect_broken", 2);
  fs::rename(dir / "INDEX.txt", dir / "index.bak");
  EXPECT_NE(openError(dir).find("INDEX.txt"), std::string::npos) << openError(dir);
  fs::rename(dir / "index.bak", dir / "INDEX.txt");

  std::ifstream in(dir / "INDEX.txt");
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);  // the first depth frame
  std::ifstream depth_file(dir / second, std::ios::binary);
  const std::vector<char> whole((std::istreambuf_iterator<char>(depth_file)), std::istreambuf_iterator<char>());
  depth_file.close();
  std::ofstream(dir / second, std::ios::binary).write(whole.data(), long(whole.size()) / 2);  // cut short
  std::string error = openError(dir);
  EXPECT_NE(error.find(second), std::string::npos) << error;
  EXPECT_NE(error.find("INDEX.txt:2"), std::string::npos) << error;

  fs::remove(dir / second);
  error = openError(dir);
  EXPECT_NE(error.find("cannot be read"), std::string::npos) << error;
}

TEST(FreenectDevice, AnAbsentKinectOrABadIndexIsAnError)
{
  // No Kinect on a test machine: libfreenect finds none (or cannot start without USB).
  EXPECT_THROW(FreenectDevice("", ""), DeviceError);
  EXPECT_THROW(FreenectDevice("3", ""), DeviceError);
  try
  {
    FreenectDevice("not-a-number", "");
    ADD_FAILURE() << "no error";
  }
  catch (const DeviceError& e)
  {
    EXPECT_NE(std::string(e.what()).find("not-a-number"), std::string::npos) << e.what();
  }
}

TEST(DeviceClock, StampsKeepTheDevicesSpacingAndResyncWhenItJumps)
{
  DeviceClock clock(0.1);
  EXPECT_DOUBLE_EQ(clock.stamp(0, 50.0), 50.0) << "no device time: the host's";
  EXPECT_DOUBLE_EQ(clock.stamp(1000000, 100.0), 100.0) << "the first frame fixes the offset";
  // Frames 33.3 ms apart on the device, received with 0-20 ms of jitter: the device's spacing.
  EXPECT_NEAR(clock.stamp(1033333, 100.050), 100.033333, 1e-9);
  EXPECT_NEAR(clock.stamp(1066667, 100.070), 100.066667, 1e-9);
  // The device restarts its clock (a looping recording): never backwards, back to the host's time.
  EXPECT_DOUBLE_EQ(clock.stamp(1000, 100.2), 100.2);
  EXPECT_NEAR(clock.stamp(34333, 100.25), 100.233333, 1e-9);
  // The clocks part by more than 0.1 s: resynchronised.
  EXPECT_DOUBLE_EQ(clock.stamp(67667, 101.0), 101.0);
}
