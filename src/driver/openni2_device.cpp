#include "openni2_device.h"

#include <OpenNI.h>

#include <cmath>
#include <mutex>

namespace action_flow
{
namespace
{
// OpenNI2 keeps one process-wide context; initialise it once and never shut it down, since
// shutting down would close every other instance's device too.
void initialiseOpenNI()
{
  static std::once_flag once;
  static openni::Status status = openni::STATUS_OK;
  static std::string error;
  std::call_once(once, [] {
    status = openni::OpenNI::initialize();
    if (status != openni::STATUS_OK)
      error = openni::OpenNI::getExtendedError();
  });
  if (status != openni::STATUS_OK)
    throw DeviceError("OpenNI2 failed to initialise: " + error);
}

std::string lastError()
{
  const std::string e = openni::OpenNI::getExtendedError();
  return e.empty() ? "no details from OpenNI2" : e;
}
}  // namespace

struct OpenNI2Device::Impl
{
  openni::Device device;
  openni::VideoStream depth, color;
  bool has_color = false;
  openni::VideoFrameRef color_frame;
};

OpenNI2Device::OpenNI2Device(const std::string& uri) : impl_(std::make_unique<Impl>())
{
  initialiseOpenNI();
  const char* which = uri.empty() ? openni::ANY_DEVICE : uri.c_str();
  if (impl_->device.open(which) != openni::STATUS_OK)
    throw DeviceError("cannot open OpenNI2 device '" + (uri.empty() ? std::string("first device") : uri) +
                      "': " + lastError());
  const openni::DeviceInfo& info = impl_->device.getDeviceInfo();
  description_ = std::string(info.getUri()) + " (" + info.getVendor() + " " + info.getName() + ")";
  if (impl_->depth.create(impl_->device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
  {
    impl_->device.close();
    throw DeviceError("device '" + description_ + "' has no depth stream: " + lastError());
  }
  impl_->has_color = impl_->device.hasSensor(openni::SENSOR_COLOR) &&
                     impl_->color.create(impl_->device, openni::SENSOR_COLOR) == openni::STATUS_OK;
  if (impl_->device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR))
    impl_->device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR);
  if (isFile() && impl_->device.getPlaybackControl())
    impl_->device.getPlaybackControl()->setRepeatEnabled(true);
}

OpenNI2Device::~OpenNI2Device()
{
  stop();
  impl_->depth.destroy();
  if (impl_->has_color)
    impl_->color.destroy();
  impl_->color_frame.release();
  impl_->device.close();
}

bool OpenNI2Device::isFile() const
{
  return impl_->device.isFile();
}

void OpenNI2Device::start()
{
  if (streaming_)
    return;
  if (impl_->depth.start() != openni::STATUS_OK)
    throw DeviceError("cannot start the depth stream of '" + description_ + "': " + lastError());
  if (impl_->has_color && impl_->color.start() != openni::STATUS_OK)
  {
    impl_->depth.stop();
    throw DeviceError("cannot start the colour stream of '" + description_ + "': " + lastError());
  }
  streaming_ = true;
}

void OpenNI2Device::stop()
{
  if (!streaming_)
    return;
  impl_->depth.stop();
  if (impl_->has_color)
    impl_->color.stop();
  streaming_ = false;
}

bool OpenNI2Device::read(RgbdFrame& frame, int timeout_ms)
{
  if (!streaming_)
    return false;
  openni::VideoStream* streams[2] = { &impl_->depth, &impl_->color };
  const int count = impl_->has_color ? 2 : 1;
  // Colour frames are kept as they arrive; a depth frame completes a pair with the latest colour.
  for (;;)
  {
    int ready = -1;
    if (openni::OpenNI::waitForAnyStream(streams, count, &ready, timeout_ms) != openni::STATUS_OK)
      return false;
    if (ready == 1)
    {
      if (impl_->color.readFrame(&impl_->color_frame) != openni::STATUS_OK)
        throw DeviceError("reading a colour frame of '" + description_ + "' failed: " + lastError());
      continue;
    }
    openni::VideoFrameRef depth;
    if (impl_->depth.readFrame(&depth) != openni::STATUS_OK)
      throw DeviceError("reading a depth frame of '" + description_ + "' failed: " + lastError());
    if (depth.getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_DEPTH_1_MM &&
        depth.getVideoMode().getPixelFormat() != openni::PIXEL_FORMAT_DEPTH_100_UM)
      throw DeviceError("depth stream of '" + description_ + "' has an unsupported pixel format");
    const float scale = depth.getVideoMode().getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_100_UM ? 0.1f : 1.0f;
    const int w = depth.getWidth(), h = depth.getHeight();
    frame.width = w;
    frame.height = h;
    frame.timestamp_us = depth.getTimestamp();
    frame.depth_mm.resize(static_cast<std::size_t>(w) * h);
    const auto* d = static_cast<const std::uint16_t*>(depth.getData());
    const int stride = depth.getStrideInBytes() / 2;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        frame.depth_mm[y * w + x] = static_cast<std::uint16_t>(d[y * stride + x] * scale);

    frame.rgb.assign(3 * static_cast<std::size_t>(w) * h, 0);
    const openni::VideoFrameRef& c = impl_->color_frame;
    if (c.isValid() && c.getVideoMode().getPixelFormat() == openni::PIXEL_FORMAT_RGB888)
    {
      const int cw = c.getWidth(), ch = c.getHeight(), cstride = c.getStrideInBytes();
      const auto* rgb = static_cast<const std::uint8_t*>(c.getData());
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
        {
          const std::uint8_t* px = rgb + (y * ch / h) * cstride + 3 * (x * cw / w);
          std::copy(px, px + 3, frame.rgb.begin() + 3 * (y * w + x));
        }
    }

    const float hfov = impl_->depth.getHorizontalFieldOfView();
    const float vfov = impl_->depth.getVerticalFieldOfView();
    setKinectV1Intrinsics(frame);
    frame.default_intrinsics = !(std::isfinite(hfov) && hfov > 0.01f && std::isfinite(vfov) && vfov > 0.01f);
    if (!frame.default_intrinsics)
    {
      frame.fx = 0.5f * w / std::tan(0.5f * hfov);
      frame.fy = 0.5f * h / std::tan(0.5f * vfov);
    }
    return true;
  }
}

}  // namespace action_flow
