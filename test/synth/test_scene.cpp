// Known-answer tests of the virtual Kinect: geometry of known scenes, the depth noise model, the
// projector shadow, and the MSR skeleton parser.
#include <action_flow/synth/scene.h>
#include <action_flow/synth/skeleton.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

using namespace action_flow::synth;

namespace
{
CameraModel exactCamera(double tilt)
{
  CameraModel cam;
  cam.noise = false;
  cam.tilt = tilt;
  cam.height_above_floor = 1.1;
  return cam;
}

Room emptyRoom()
{
  Room room;
  room.walls = false;
  return room;
}

Box wall(float x, float half_height = 1.5f)
{
  Box b;
  b.center = Eigen::Vector3f(x + 0.25f, 0, 1.1f);
  b.half = Eigen::Vector3f(0.25f, 3.0f, half_height);
  return b;
}

float at(const FrameImages& im, int u, int v) { return im.depth[size_t(v) * im.width + u]; }

std::string tempFile(const std::string& name, const std::string& text)
{
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}
}  // namespace

TEST(Scene, KnownSceneGivesExactDepthAtKnownPixels)
{
  Room room = emptyRoom();
  Box box;
  box.center = Eigen::Vector3f(2.25f, 0.0f, 1.1f);  // front face at x = 2 m, in front of the camera
  box.half = Eigen::Vector3f(0.25f, 0.3f, 0.3f);
  room.boxes.push_back(box);
  const SceneRenderer scene(exactCamera(0.0), room);
  FrameImages im;
  scene.render({}, 1, 0, im);
  // Level camera: optical depth of the box face is its distance.
  EXPECT_NEAR(at(im, 320, 240), 2.0f, 1e-4f);
  EXPECT_NEAR(at(im, 300, 220), 2.0f, 1e-4f);
  // Floor below: the ray through row v meets the floor at z = h * fy / (v - cy).
  EXPECT_NEAR(at(im, 320, 400), 1.1f * 525.0f / (400 - 239.5f), 1e-3f);
  EXPECT_NEAR(at(im, 100, 470), 1.1f * 525.0f / (470 - 239.5f), 1e-3f);
  // Above the horizon, nothing (no walls): no depth.
  EXPECT_TRUE(std::isnan(at(im, 320, 20)));
  // The floor at 4.77 m (row 360) is beyond the 4.5 m range: no depth either.
  EXPECT_TRUE(std::isnan(at(im, 320, 360)));
  // The mask is empty without bodies.
  for (auto m : im.mask)
    ASSERT_EQ(m, 0);
}

TEST(Scene, TiltedCameraSeesTheFloorWhereTrigonometrySays)
{
  const double tilt = 0.3;
  const SceneRenderer scene(exactCamera(tilt), emptyRoom());
  FrameImages im;
  scene.render({}, 1, 0, im);
  // The optical axis (between pixels 319/320, 239/240) meets the floor h / sin(tilt) away.
  const float expected = float(1.1 / std::sin(tilt));
  const float centre = 0.25f * (at(im, 319, 239) + at(im, 320, 239) + at(im, 319, 240) + at(im, 320, 240));
  EXPECT_NEAR(centre, expected, 0.01f);
  // The cloud puts that point on the floor: 1.1 m below the camera along world z.
  action_flow::Cloud cloud;
  scene.toCloud(im, cloud);
  ASSERT_EQ(cloud.width, 640u);
  ASSERT_EQ(cloud.height, 480u);
  EXPECT_EQ(cloud.header.frame_id, "camera_rgb_optical_frame");
  const auto& p = cloud.at(320, 240);
  const Eigen::Vector3f world = scene.camera().worldFromOptical() * Eigen::Vector3f(p.x, p.y, p.z);
  EXPECT_NEAR(world.z(), 0.0f, 0.01f);
}

class DepthNoise : public ::testing::TestWithParam<float>
{
};

TEST_P(DepthNoise, MatchesTheKhoshelhamModelWithinTwentyPercent)
{
  const float distance = GetParam();
  Room room = emptyRoom();
  room.floor = false;
  room.boxes.push_back(wall(distance));
  CameraModel noisy = exactCamera(0.15);  // tilted: the true depth sweeps many quantisation steps
  noisy.noise = true;
  noisy.edge_dropout = 0;
  const SceneRenderer exact(exactCamera(0.15), room), sensor(noisy, room);
  FrameImages truth, im;
  exact.render({}, 7, 0, truth);
  double sum2 = 0;
  long n = 0;
  for (int frame = 0; frame < 4; ++frame)
  {
    sensor.render({}, 7, frame, im);
    for (int v = 140; v < 340; v += 2)
      for (int u = 120; u < 520; u += 2)
      {
        const float z0 = at(truth, u, v), z = at(im, u, v);
        if (!std::isfinite(z0) || !std::isfinite(z))
          continue;
        const double sigma = 1.425e-3 * z0 * z0;
        sum2 += (z - z0) * (z - z0) / (sigma * sigma);
        ++n;
      }
  }
  ASSERT_GT(n, 20000);
  const double ratio = std::sqrt(sum2 / n);
  EXPECT_GT(ratio, 0.8) << "noise at " << distance << " m is " << ratio << " of the model";
  EXPECT_LT(ratio, 1.2) << "noise at " << distance << " m is " << ratio << " of the model";
}

INSTANTIATE_TEST_SUITE_P(At2And4Metres, DepthNoise, ::testing::Values(2.0f, 4.0f));

TEST(Scene, NoiseIsQuantisedInDisparity)
{
  Room room = emptyRoom();
  room.floor = false;
  room.boxes.push_back(wall(3.0f));
  CameraModel cam = exactCamera(0.0);
  cam.noise = true;
  const SceneRenderer scene(cam, room);
  FrameImages im;
  scene.render({}, 3, 0, im);
  // Every depth is f*b / (k/8) for an integer k, rounded to millimetres.
  const double fb = 525.0 * 0.075;
  for (int u = 200; u < 440; u += 7)
  {
    const float z = at(im, u, 240);
    ASSERT_TRUE(std::isfinite(z));
    const double k = fb / z / 0.125;
    EXPECT_NEAR(std::round(fb / (std::round(k) * 0.125) * 1000) / 1000, z, 1e-4) << "u=" << u;
  }
}

TEST(Scene, ProjectorShadowLeftOfANearObject)
{
  Room room = emptyRoom();
  room.floor = false;
  room.boxes.push_back(wall(4.0f));
  Box post;  // a near post in front of the wall, centred
  post.center = Eigen::Vector3f(1.6f, 0.0f, 1.1f);
  post.half = Eigen::Vector3f(0.05f, 0.1f, 0.5f);
  room.boxes.push_back(post);
  CameraModel cam = exactCamera(0.0);
  cam.noise = true;
  cam.edge_dropout = 0;
  const SceneRenderer scene(cam, room);
  FrameImages im;
  scene.render({}, 3, 0, im);
  // Post edges at u = 319.5 -+ 525*0.1/1.55. The shadow on the wall, left of the post, is
  // f*b*(1/1.55 - 1/4) = 15 px wide; right of the post there is none.
  const int left_edge = int(std::ceil(319.5 - 525 * 0.1 / 1.55));
  int shadow_left = 0, shadow_right = 0;
  for (int u = left_edge - 12; u < left_edge - 2; ++u)
    shadow_left += std::isnan(at(im, u, 240)) ? 1 : 0;
  const int right_edge = int(std::floor(319.5 + 525 * 0.1 / 1.55));
  for (int u = right_edge + 3; u < right_edge + 13; ++u)
    shadow_right += std::isnan(at(im, u, 240)) ? 1 : 0;
  EXPECT_EQ(shadow_left, 10);
  EXPECT_EQ(shadow_right, 0);
  EXPECT_NEAR(at(im, left_edge - 25, 240), 4.0f, 0.1f);
}

TEST(Skeleton, JointNamesAreOpenNiTrackers)
{
  EXPECT_EQ(jointName(Joint::Head), "head");
  EXPECT_EQ(jointName(Joint::LeftHand), "left_hand");
  EXPECT_EQ(jointName(Joint::RightFoot), "right_foot");
  EXPECT_EQ(jointName(Joint::Torso), "torso");
}

TEST(MsrParser, ReadsFramesAndFlagsUntrackedOnes)
{
  std::string text;
  for (int f = 0; f < 2; ++f)
    for (int j = 1; j <= 20; ++j)
      text += f == 1 ? "0.000000 0.000000 0.000000 0.000000\n"
                     : std::to_string(0.01 * j) + " " + std::to_string(-0.02 * j) + " 2.5 1.000000\n";
  const std::string path = tempFile("a05_s03_e02_skeleton3D.txt", text);
  const MsrSkeletonFile file = parseMsrSkeletonFile(path);
  ASSERT_EQ(file.frames.size(), 2u);
  EXPECT_EQ(file.action, 5);
  EXPECT_EQ(file.subject, 3);
  EXPECT_EQ(file.take, 2);
  EXPECT_TRUE(file.tracked[0]);
  EXPECT_FALSE(file.tracked[1]);
  EXPECT_EQ(file.trackedFrames(), 1);
  EXPECT_NEAR(file.frames[0][12].x(), 0.13f, 1e-6f);  // joint 13 (right hand)
  // Un-mirrored: the right hand (joint 13) goes to -x.
  const Skeleton s = msrToOpenNi(file.frames[0]);
  EXPECT_NEAR(s[Joint::RightHand].x(), -0.13f, 1e-6f);
  EXPECT_NEAR(s[Joint::Head].y(), -0.4f, 1e-6f);
  std::remove(path.c_str());
}

TEST(MsrParser, RejectsAMalformedLineNamingFileAndLine)
{
  std::string text;
  for (int j = 1; j <= 20; ++j)
    text += j == 7 ? "0.1 0.2 oops 1.0\n" : "0.1 0.2 2.5 1.0\n";
  const std::string path = tempFile("a01_s01_e01_bad_skeleton3D.txt", text);
  try
  {
    parseMsrSkeletonFile(path);
    FAIL() << "no exception";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_NE(std::string(e.what()).find(path + ":7:"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

TEST(MsrParser, RejectsTruncatedFilesAndBadConfidence)
{
  std::string text;
  for (int j = 1; j <= 23; ++j)
    text += "0.1 0.2 2.5 1.0\n";
  const std::string path = tempFile("truncated_skeleton3D.txt", text);
  EXPECT_THROW(
      {
        try
        {
          parseMsrSkeletonFile(path);
        }
        catch (const std::runtime_error& e)
        {
          EXPECT_NE(std::string(e.what()).find(path + ":23:"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);
  const std::string bad = tempFile("conf_skeleton3D.txt", "0.1 0.2 2.5 1.5\n");
  EXPECT_THROW(parseMsrSkeletonFile(bad), std::runtime_error);
  EXPECT_THROW(parseMsrSkeletonFile("no_such_folder/a01_s01_e01_skeleton3D.txt"), std::runtime_error);
  std::remove(path.c_str());
  std::remove(bad.c_str());
}
