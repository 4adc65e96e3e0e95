#include "freenect_device.h"

#include <action_flow/kinect_depth.h>

#include <libfreenect.h>

#include <dlfcn.h>
#include <sys/time.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace action_flow
{
namespace
{
namespace fs = std::filesystem;

constexpr int kWidth = 640, kHeight = 480;
constexpr std::size_t kDepthBytes = 2u * kWidth * kHeight, kRgbBytes = 3u * kWidth * kHeight;

// Checks a fakenect dump as fakenect will read it: INDEX.txt, then per line a file whose name
// starts "<type>-<time>-<timestamp>", for depth and colour a one-line header and a whole frame.
// fakenect itself calls exit() on a missing or short file, which would end the nodelet manager.
void checkDump(const fs::path& dir)
{
  const fs::path index = dir / "INDEX.txt";
  std::ifstream in(index);
  if (!in)
    throw DeviceError("fakenect dump '" + dir.string() + "' has no readable INDEX.txt");
  std::string line;
  int frames = 0, number = 0;
  while (std::getline(in, line))
  {
    ++number;
    if (line.empty())
      continue;
    const fs::path file = dir / line;
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    const std::string where = index.string() + ":" + std::to_string(number);
    if (ec)
      throw DeviceError(where + ": '" + file.string() + "' cannot be read: " + ec.message());
    if (line[0] != 'd' && line[0] != 'r')
      continue;
    std::ifstream f(file, std::ios::binary);
    std::string header;
    std::getline(f, header);
    const std::size_t need = line[0] == 'd' ? kDepthBytes : kRgbBytes;
    if (!f || header.size() > 64 || size < header.size() + 1 + need)
      throw DeviceError(where + ": '" + file.string() + "' is not a one-line header and a 640x480 " +
                        (line[0] == 'd' ? "11-bit depth" : "RGB") + " frame");
    frames += line[0] == 'd';
  }
  if (frames == 0)
    throw DeviceError("fakenect dump '" + dir.string() + "' lists no depth frame in INDEX.txt");
}

// The part of libfreenect's API the driver uses, bound from the loaded library by name.
struct Api
{
  void* handle = nullptr;
  decltype(&freenect_init) init = nullptr;
  decltype(&freenect_shutdown) shutdown = nullptr;
  decltype(&freenect_set_log_level) set_log_level = nullptr;
  decltype(&freenect_select_subdevices) select_subdevices = nullptr;
  decltype(&freenect_num_devices) num_devices = nullptr;
  decltype(&freenect_open_device) open_device = nullptr;
  decltype(&freenect_close_device) close_device = nullptr;
  decltype(&freenect_find_video_mode) find_video_mode = nullptr;
  decltype(&freenect_find_depth_mode) find_depth_mode = nullptr;
  decltype(&freenect_set_video_mode) set_video_mode = nullptr;
  decltype(&freenect_set_depth_mode) set_depth_mode = nullptr;
  decltype(&freenect_set_video_callback) set_video_callback = nullptr;
  decltype(&freenect_set_depth_callback) set_depth_callback = nullptr;
  decltype(&freenect_start_depth) start_depth = nullptr;
  decltype(&freenect_start_video) start_video = nullptr;
  decltype(&freenect_stop_depth) stop_depth = nullptr;
  decltype(&freenect_stop_video) stop_video = nullptr;
  decltype(&freenect_process_events_timeout) process_events_timeout = nullptr;

  explicit Api(const std::string& library)
  {
    handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle)
      throw DeviceError("cannot load libfreenect '" + library + "': " + ::dlerror() +
                        " (Debian package libfreenect0.5)");
    bind(init, "freenect_init");
    bind(shutdown, "freenect_shutdown");
    bind(set_log_level, "freenect_set_log_level");
    bind(select_subdevices, "freenect_select_subdevices");
    bind(num_devices, "freenect_num_devices");
    bind(open_device, "freenect_open_device");
    bind(close_device, "freenect_close_device");
    bind(find_video_mode, "freenect_find_video_mode");
    bind(find_depth_mode, "freenect_find_depth_mode");
    bind(set_video_mode, "freenect_set_video_mode");
    bind(set_depth_mode, "freenect_set_depth_mode");
    bind(set_video_callback, "freenect_set_video_callback");
    bind(set_depth_callback, "freenect_set_depth_callback");
    bind(start_depth, "freenect_start_depth");
    bind(start_video, "freenect_start_video");
    bind(stop_depth, "freenect_stop_depth");
    bind(stop_video, "freenect_stop_video");
    bind(process_events_timeout, "freenect_process_events_timeout");
  }
  ~Api()
  {
    if (handle)
      ::dlclose(handle);
  }
  Api(const Api&) = delete;
  Api& operator=(const Api&) = delete;

  template <class F>
  void bind(F& f, const char* name)
  {
    f = reinterpret_cast<F>(::dlsym(handle, name));
    if (!f)
    {
      ::dlclose(handle);
      handle = nullptr;
      throw DeviceError(std::string("the loaded libfreenect has no ") + name);
    }
  }
};

// The latest frames, as libfreenect hands them over.
struct Latest
{
  std::vector<std::uint16_t> depth;
  std::vector<std::uint8_t> rgb;
  std::uint32_t depth_timestamp = 0;
  bool new_depth = false, have_rgb = false;
};

// libfreenect calls back from inside process_events, on the thread that calls it (the reading
// thread), which points this at its device's frames first. fakenect frees the data after the
// call, so it is copied.
thread_local Latest* t_latest = nullptr;

void onDepth(freenect_device*, void* data, std::uint32_t timestamp)
{
  const auto* d = static_cast<const std::uint16_t*>(data);
  t_latest->depth.assign(d, d + kWidth * kHeight);
  t_latest->depth_timestamp = timestamp;
  t_latest->new_depth = true;
}

void onVideo(freenect_device*, void* data, std::uint32_t)
{
  const auto* c = static_cast<const std::uint8_t*>(data);
  t_latest->rgb.assign(c, c + kRgbBytes);
  t_latest->have_rgb = true;
}
}  // namespace

struct FreenectDevice::Impl
{
  std::unique_ptr<Api> api;
  freenect_context* context = nullptr;
  freenect_device* device = nullptr;
  bool dump = false;  // fakenect: 11-bit raw depth; a sensor: registered millimetres
  Latest latest;
};

std::string FreenectDevice::builtInFakenectLibrary()
{
#ifdef ACTION_FLOW_FAKENECT_LIBRARY
  return ACTION_FLOW_FAKENECT_LIBRARY;
#else
  return "";
#endif
}

FreenectDevice::FreenectDevice(const std::string& which, const std::string& fakenect_library)
  : impl_(std::make_unique<Impl>())
{
  std::error_code ec;
  impl_->dump = !which.empty() && fs::is_directory(which, ec);
  int index = 0;
  if (impl_->dump)
  {
    checkDump(which);
    const std::string lib = fakenect_library.empty() ? builtInFakenectLibrary() : fakenect_library;
    if (lib.empty())
      throw DeviceError("no fakenect library to replay '" + which +
                        "' with: give fakenect_library (Debian's libfreenect0.5 ships it)");
    // fakenect reads the dump's folder from the environment at its first event.
    ::setenv("FAKENECT_PATH", fs::absolute(which).c_str(), 1);
    impl_->api = std::make_unique<Api>(lib);
    description_ = "fakenect dump '" + which + "'";
  }
  else
  {
    if (!which.empty())
    {
      char* end = nullptr;
      const long i = std::strtol(which.c_str(), &end, 10);
      if (*end != '\0' || i < 0)
        throw DeviceError("device_uri '" + which + "' is neither a Kinect index nor a fakenect dump folder");
      index = static_cast<int>(i);
    }
    impl_->api = std::make_unique<Api>("libfreenect.so.0.5");
    description_ = "Kinect v1 #" + std::to_string(index);
  }
  Api& api = *impl_->api;
  if (api.init(&impl_->context, nullptr) < 0)
    throw DeviceError("libfreenect failed to initialise (no USB access?)");
  api.set_log_level(impl_->context, FREENECT_LOG_WARNING);
  api.select_subdevices(impl_->context, FREENECT_DEVICE_CAMERA);
  const int count = api.num_devices(impl_->context);
  if (count <= index || api.open_device(impl_->context, &impl_->device, index) < 0)
  {
    api.shutdown(impl_->context);
    throw DeviceError("cannot open " + description_ + ": libfreenect found " + std::to_string(std::max(count, 0)) +
                      " Kinect v1 device(s)");
  }
  api.set_depth_callback(impl_->device, onDepth);
  api.set_video_callback(impl_->device, onVideo);
  const freenect_frame_mode video = api.find_video_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_VIDEO_RGB);
  // fakenect knows only the 11-bit mode (it asserts on any other).
  const freenect_frame_mode depth = api.find_depth_mode(
      FREENECT_RESOLUTION_MEDIUM, impl_->dump ? FREENECT_DEPTH_11BIT : FREENECT_DEPTH_REGISTERED);
  if (!video.is_valid || !depth.is_valid || api.set_video_mode(impl_->device, video) < 0 ||
      api.set_depth_mode(impl_->device, depth) < 0)
  {
    api.close_device(impl_->device);
    api.shutdown(impl_->context);
    throw DeviceError(description_ + " does not offer 640x480 RGB with registered depth");
  }
}

FreenectDevice::~FreenectDevice()
{
  stop();
  impl_->api->close_device(impl_->device);
  impl_->api->shutdown(impl_->context);
}

void FreenectDevice::start()
{
  if (streaming_)
    return;
  Api& api = *impl_->api;
  if (api.start_depth(impl_->device) < 0 || api.start_video(impl_->device) < 0)
  {
    api.stop_depth(impl_->device);
    throw DeviceError("cannot start the streams of " + description_);
  }
  impl_->latest.new_depth = impl_->latest.have_rgb = false;
  streaming_ = true;
}

void FreenectDevice::stop()
{
  if (!streaming_)
    return;
  impl_->api->stop_depth(impl_->device);
  impl_->api->stop_video(impl_->device);
  streaming_ = false;
}

bool FreenectDevice::read(RgbdFrame& frame, int timeout_ms)
{
  if (!streaming_)
    return false;
  Impl& impl = *impl_;
  Latest& latest = impl.latest;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  // A depth frame completes a pair with the latest colour frame.
  while (!(latest.new_depth && latest.have_rgb))
  {
    if (std::chrono::steady_clock::now() > deadline)
      return false;
    timeval tv{ 0, 50000 };
    t_latest = &latest;
    const int status = impl.api->process_events_timeout(impl.context, &tv);
    if (status < 0)
    {
      if (impl.dump)
        throw EndOfRecording(description_ + " has no more frames");
      throw DeviceError("reading from " + description_ + " failed (libfreenect error " + std::to_string(status) + ")");
    }
  }
  latest.new_depth = false;
  frame.width = kWidth;
  frame.height = kHeight;
  // libfreenect's frame timestamp counts ticks of a clock whose rate it does not document: no
  // device time (the driver stamps on receipt).
  frame.timestamp_us = 0;
  frame.depth_mm.resize(latest.depth.size());
  for (std::size_t i = 0; i < latest.depth.size(); ++i)
  {
    if (!impl.dump)
      frame.depth_mm[i] = latest.depth[i];  // FREENECT_DEPTH_REGISTERED: mm, 0 = none
    else
    {
      const float z = kinectRawToMetres(latest.depth[i]);
      frame.depth_mm[i] = std::isfinite(z) ? static_cast<std::uint16_t>(std::lround(z * 1000.0f)) : 0;
    }
  }
  frame.rgb = latest.rgb;
  setKinectV1Intrinsics(frame);
  frame.default_intrinsics = false;  // libfreenect gives none: the Kinect v1's are the values
  return true;
}

}  // namespace action_flow
