// Known answers for the Kinect v1 raw depth conversion (kinect_depth.h).
#include <action_flow/kinect_depth.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace action_flow;

TEST(KinectDepth, KnownRawValuesGiveTheFitsMetres)
{
  // z = 0.1236 tan(raw / 2842.5 + 1.1863), worked by hand: raw 0 -> 0.30546 m, 743 -> 0.99893 m,
  // 976 -> 3.00293 m.
  EXPECT_NEAR(kinectRawToMetres(0), 0.30546, 1e-4);
  EXPECT_NEAR(kinectRawToMetres(743), 0.99893, 1e-4);
  EXPECT_NEAR(kinectRawToMetres(976), 3.00293, 1e-4);
  EXPECT_EQ(metresToKinectRaw(1.0f), 743);
  EXPECT_EQ(metresToKinectRaw(3.0f), 976);
}

TEST(KinectDepth, NoReadingAndOutOfRangeValues)
{
  EXPECT_TRUE(std::isnan(kinectRawToMetres(kKinectRawNoReading)));
  EXPECT_TRUE(std::isnan(kinectRawToMetres(1500)));  // past the fit's pole (raw 1093)
  EXPECT_EQ(metresToKinectRaw(std::nanf("")), kKinectRawNoReading);
  EXPECT_EQ(metresToKinectRaw(0.2f), kKinectRawNoReading);   // nearer than the sensor sees
  EXPECT_EQ(metresToKinectRaw(-1.0f), kKinectRawNoReading);
  EXPECT_EQ(metresToKinectRaw(11.0f), kKinectRawNoReading);
}

TEST(KinectDepth, MetresSurviveARoundTripWithinHalfARawStep)
{
  float previous = 0.0f;
  for (std::uint16_t raw = 0; raw <= 1057; ++raw)  // up to 10 m (kKinectRawMaxMetres)
  {
    const float z = kinectRawToMetres(raw);
    ASSERT_GT(z, previous) << "raw " << raw;  // one raw step is one depth step, nearest first
    previous = z;
  }
  for (float z = 0.5f; z <= 4.5f; z += 0.01f)
  {
    const std::uint16_t raw = metresToKinectRaw(z);
    const float step = kinectRawToMetres(raw + 1) - kinectRawToMetres(raw);
    EXPECT_LE(std::fabs(kinectRawToMetres(raw) - z), 0.5f * step + 1e-5f) << z << " m";
  }
}
