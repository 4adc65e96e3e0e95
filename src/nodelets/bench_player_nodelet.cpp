// Whole-pipeline benchmark inside the nodelet manager: plays raw rgb + depth + camera_info frames
// of synthetic bags (held in memory) into depth_image_proc and the pipeline loaded in the same
// manager, each frame restamped with a fresh, increasing stamp, and measures what comes out of the
// classifier: frames per second, the manager's CPU use, latency from a frame's stamp to its
// per-frame `states` (and to `labels`), and the manager's resident memory over the run.
#include <action_flow/files.h>
#include <action_flow/ActionLabel.h>
#include <action_flow/ros/stage_types.h>
#include <diagnostic_msgs/DiagnosticArray.h>

#include "../bench/stage_stats.h"

#include <nlohmann/json.hpp>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/package.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <sys/resource.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <boost/algorithm/string.hpp>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

namespace action_flow
{
namespace
{
/** Resident memory of this process (VmRSS), MB; NaN when /proc is not readable. */
double residentMb()
{
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("VmRSS:", 0) == 0)
      return std::stod(line.substr(6)) / 1024.0;  // kB
  return std::numeric_limits<double>::quiet_NaN();
}

/** User + system CPU time of this whole process (every thread), seconds. */
double processCpuSeconds()
{
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double threadCpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

double steadySeconds()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string loadAverage()
{
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

nlohmann::json percentiles(const bench::StageSamples& s)
{
  if (s.empty())
    return nullptr;
  double max = 0.0, min = std::numeric_limits<double>::infinity();
  for (double v : s.samples())
  {
    max = std::max(max, v);
    min = std::min(min, v);
  }
  return { { "count", s.size() }, { "median", s.median() }, { "p95", s.p95() }, { "min", min }, { "max", max } };
}

/** @p path relative to this package's folder when it lies inside it (build/...), else as given. */
std::string packageRelative(const std::string& path)
{
  namespace fs = std::filesystem;
  const std::string root = ros::package::getPath("action_flow");
  if (root.empty())
    return path;
  std::error_code error;
  const fs::path rel = fs::weakly_canonical(path, error).lexically_relative(fs::weakly_canonical(root, error));
  return error || rel.empty() || *rel.begin() == ".." ? path : rel.string();
}

}  // namespace

/**
 * Parameters (private): `bags` (bag paths, separated by spaces or commas), `rgb_topic`,
 * `depth_topic`, `camera_info_topic` (read from the bags and published under the same names),
 * `max_bag_frames` (1200: frames held in memory, ~1.5 MB each at 640x480), `frames` (10000
 * measured frames), `warmup` (30 frames before measuring), `mode` (max: closed loop, the next
 * frame when the previous one's states arrived; rate: a fixed rate), `rate` (Hz, mode rate),
 * `in_flight` (mode max: frames published and not yet answered, 1), `timeout` (s: a frame
 * without states after this long counts as dropped), `sample_every` (100 frames between
 * memory/CPU samples), `progress_every` (1000), `output_dir`, `shutdown_when_done` (true: end the
 * manager when the results are written, so that a launch with a required manager returns),
 * `bad_every` (0: off; N: after every N-th measured frame one malformed message, of six kinds in
 * turn: depth data cut short, a 0x0 colour image, an unknown encoding, a camera_info with NaN
 * intrinsics, a depth step beyond its data, and a PointCloud2 on `cloud_topic` that claims a
 * million points it does not carry; each must be dropped by the checks and the next good frame
 * served) and `cloud_topic` (the tracker's input, camera/depth_registered/points_from_images).
 * Subscribes `states` (ActionStates), `labels` (ActionLabel) and /diagnostics (each stage's latency).
 * Writes into output_dir: summary.json, samples.csv, frames.csv, labels.csv, stages.csv (each
 * stage's latency once a second, from /diagnostics).
 */
class BenchPlayerNodelet : public nodelet::Nodelet
{
public:
  ~BenchPlayerNodelet() override
  {
    stop_ = true;
    cv_.notify_all();
    if (thread_.joinable())
      thread_.join();
  }

private:
  struct Frame
  {
    sensor_msgs::ImageConstPtr rgb, depth;
    sensor_msgs::CameraInfoConstPtr info;
  };
  /** One published frame. */
  struct Record
  {
    std::uint64_t stamp_us = 0;
    double published = 0.0;  // steady clock, s
    double arrived = -1.0;   // steady clock, s; < 0: no states
    double latency = -1.0;   // states arrival (ROS time) minus stamp, s
    int arrival_order = -1;
    int tracks = 0;
  };
  struct Sample
  {
    std::size_t frame = 0;
    double wall = 0.0, rss = 0.0, cpu = 0.0, cores = 0.0, fps = 0.0, median = 0.0, p95 = 0.0;
  };
  struct LabelRecord
  {
    std::uint64_t stamp_us = 0;
    double latency = 0.0, window_end_latency = 0.0;
    std::uint32_t track = 0;
    std::string label;
  };

  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    std::string bags;
    pnh.param("bags", bags, bags);
    boost::split(bag_paths_, bags, boost::is_any_of(" ,\t\n"), boost::token_compress_on);
    bag_paths_.erase(std::remove(bag_paths_.begin(), bag_paths_.end(), std::string()), bag_paths_.end());
    pnh.param("rgb_topic", rgb_topic_, rgb_topic_);
    pnh.param("depth_topic", depth_topic_, depth_topic_);
    pnh.param("camera_info_topic", info_topic_, info_topic_);
    pnh.param("max_bag_frames", max_bag_frames_, max_bag_frames_);
    pnh.param("frames", frames_, frames_);
    pnh.param("warmup", warmup_, warmup_);
    pnh.param("mode", mode_, mode_);
    pnh.param("rate", rate_, rate_);
    pnh.param("in_flight", in_flight_, in_flight_);
    pnh.param("timeout", timeout_, timeout_);
    pnh.param("sample_every", sample_every_, sample_every_);
    pnh.param("progress_every", progress_every_, progress_every_);
    pnh.param("output_dir", output_dir_, output_dir_);
    pnh.param("shutdown_when_done", shutdown_when_done_, shutdown_when_done_);
    pnh.param("bad_every", bad_every_, bad_every_);
    pnh.param("cloud_topic", cloud_topic_, cloud_topic_);

    std::string error;
    if (bag_paths_.empty())
      error = "no ~bags given";
    else if (mode_ != "max" && mode_ != "rate")
      error = "unknown ~mode '" + mode_ + "' (max|rate)";
    else if (frames_ < 1 || warmup_ < 0 || in_flight_ < 1 || sample_every_ < 1 || progress_every_ < 1 ||
             max_bag_frames_ < 1)
      error = "~frames, ~in_flight, ~sample_every, ~progress_every, ~max_bag_frames must be >= 1, ~warmup >= 0";
    else if (mode_ == "rate" && !(rate_ > 0.0))
      error = "~rate must be > 0 in mode rate";
    else if (!(timeout_ > 0.0))
      error = "~timeout must be > 0";
    else if (bad_every_ < 0)
      error = "~bad_every must be >= 0";
    if (!error.empty())
    {
      // Loaded without a job (e.g. by a test that loads every class): say so and stay idle.
      NODELET_ERROR("bench_player: %s; not benchmarking", error.c_str());
      return;
    }

    ros::NodeHandle& nh = getNodeHandle();
    rgb_pub_ = nh.advertise<sensor_msgs::Image>(rgb_topic_, 5);
    depth_pub_ = nh.advertise<sensor_msgs::Image>(depth_topic_, 5);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(info_topic_, 5);
    if (bad_every_ > 0)
      cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>(cloud_topic_, 5);
    states_sub_ = nh.subscribe("states", 100, &BenchPlayerNodelet::onStates, this);
    labels_sub_ = nh.subscribe("labels", 100, &BenchPlayerNodelet::onLabel, this);
    diagnostics_sub_ = nh.subscribe("/diagnostics", 50, &BenchPlayerNodelet::onDiagnostics, this);
    // Opened here and closed at unload, never on the player's thread: rosbag::Bag loads and unloads
    // its encryption plugin through class_loader, which crashed (SIGSEGV in unloadLibrary) when that
    // ran while the manager was loading the other nodelets.
    for (const auto& path : bag_paths_)
      try
      {
        bags_.push_back(std::make_unique<rosbag::Bag>(path, rosbag::bagmode::Read));
      }
      catch (const std::exception& e)
      {
        NODELET_ERROR("bench_player: cannot open bag '%s': %s", path.c_str(), e.what());
        bags_.push_back(nullptr);
      }
    thread_ = std::thread([this] { run(); });
  }

  // ---- input -----------------------------------------------------------------------------------

  /** Loads up to max_bag_frames frames that have all three topics with one stamp. */
  bool loadBags()
  {
    for (std::size_t b = 0; b < bag_paths_.size(); ++b)
    {
      const std::string& path = bag_paths_[b];
      if (!bags_[b])
        return false;
      std::map<ros::Time, Frame> partial;
      try
      {
        rosbag::View view(*bags_[b], rosbag::TopicQuery({ rgb_topic_, depth_topic_, info_topic_ }));
        if (view.size() == 0)
        {
          NODELET_ERROR("bench_player: bag '%s' has none of the topics %s, %s, %s (raw images: synth --raw-images)",
                        path.c_str(), rgb_topic_.c_str(), depth_topic_.c_str(), info_topic_.c_str());
          return false;
        }
        for (const auto& m : view)
        {
          if (stop_ || static_cast<int>(frames_in_memory_.size()) >= max_bag_frames_)
            break;
          if (m.getTopic() == info_topic_)
          {
            auto info = m.instantiate<sensor_msgs::CameraInfo>();
            if (info)
              partial[info->header.stamp].info = info;
          }
          else
          {
            auto image = m.instantiate<sensor_msgs::Image>();
            if (!image)
              continue;
            Frame& f = partial[image->header.stamp];
            (m.getTopic() == rgb_topic_ ? f.rgb : f.depth) = image;
            bag_bytes_ += image->data.size();
          }
          // Frames complete in stamp order; a bag interleaves the three topics of one stamp.
          for (auto it = partial.begin(); it != partial.end();)
          {
            if (!(it->second.rgb && it->second.depth && it->second.info))
              break;
            frames_in_memory_.push_back(it->second);
            it = partial.erase(it);
          }
        }
      }
      catch (const std::exception& e)
      {
        NODELET_ERROR("bench_player: cannot read bag '%s': %s", path.c_str(), e.what());
        return false;
      }
    }
    if (frames_in_memory_.empty())
    {
      NODELET_ERROR("bench_player: no frame with all of %s, %s, %s in the bags", rgb_topic_.c_str(),
                    depth_topic_.c_str(), info_topic_.c_str());
      return false;
    }
    const auto& f = frames_in_memory_.front();
    width_ = f.rgb->width;
    height_ = f.rgb->height;
    NODELET_INFO("bench_player: %zu frames (%ux%u) in memory from %zu bag(s), %.0f MB of images",
                 frames_in_memory_.size(), width_, height_, bag_paths_.size(), bag_bytes_ / 1e6);
    return true;
  }

  // ---- output callbacks ------------------------------------------------------------------------

  void onStates(const ActionStates::ConstPtr& states)
  {
    const ros::Time now = ros::Time::now();
    const double arrived = steadySeconds();
    const std::uint64_t key = states->header.stamp.toNSec() / 1000;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = pending_.find(key);
    if (it == pending_.end())
    {
      ++unknown_states_;  // a frame already counted as dropped, or not ours
      return;
    }
    if (key < last_arrived_us_)
      ++out_of_order_;
    last_arrived_us_ = std::max(last_arrived_us_, key);
    Record& r = records_[it->second];
    r.arrived = arrived;
    r.latency = (now - states->header.stamp).toSec();
    r.arrival_order = arrivals_++;
    r.tracks = static_cast<int>(states->tracks.size());
    pending_.erase(it);
    cv_.notify_all();
  }

  void onLabel(const ActionLabel::ConstPtr& label)
  {
    const ros::Time now = ros::Time::now();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!measuring_)
      return;
    LabelRecord r;
    r.stamp_us = label->header.stamp.toNSec() / 1000;
    r.latency = (now - label->header.stamp).toSec();
    r.window_end_latency = (now - label->window_end).toSec();
    r.track = label->track_id;
    r.label = label->label;
    labels_.push_back(r);
  }

  // Each stage's latency (its outputs' mean, now minus the frame's stamp, over the last second) as
  // it reports it on /diagnostics (StageDiagnostics): what one stage adds is the difference to the
  // stage before it, and how that grows with the people in view is what stages.csv is for.
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& array)
  {
    const double at = steadySeconds();
    std::lock_guard<std::mutex> lock(mutex_);
    if (!measuring_)
      return;
    for (const auto& status : array->status)
      for (const auto& kv : status.values)
        if (kv.key == "latency mean (ms)")
        {
          char* end = nullptr;
          const double ms = std::strtod(kv.value.c_str(), &end);
          if (end != kv.value.c_str() && std::isfinite(ms) && ms > 0.0)
            stage_latencies_.push_back({ at, boost::replace_all_copy(status.name, ",", ";"), ms });
        }
  }

  // ---- the run ---------------------------------------------------------------------------------

  /** A fresh stamp: the ROS clock in whole microseconds (PCL headers keep microseconds), never going back. */
  ros::Time nextStamp()
  {
    std::uint64_t us = ros::Time::now().toNSec() / 1000;
    if (us <= last_stamp_us_)
      us = last_stamp_us_ + 1;
    last_stamp_us_ = us;
    ros::Time t;
    t.fromNSec(us * 1000);
    return t;
  }

  /** Publishes frame @p i of the loop with a fresh stamp; returns its record's index. */
  std::size_t publishFrame(std::size_t i)
  {
    const Frame& src = frames_in_memory_[i % frames_in_memory_.size()];
    const double copy_start = steadySeconds();
    // A fresh message per frame: a published message is shared and must never change.
    auto rgb = boost::make_shared<sensor_msgs::Image>(*src.rgb);
    auto depth = boost::make_shared<sensor_msgs::Image>(*src.depth);
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(*src.info);
    copy_ms_.add(1e3 * (steadySeconds() - copy_start));
    const ros::Time stamp = nextStamp();
    rgb->header.stamp = depth->header.stamp = info->header.stamp = stamp;
    rgb->header.seq = depth->header.seq = info->header.seq = static_cast<std::uint32_t>(i);
    std::size_t index;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      Record r;
      r.stamp_us = stamp.toNSec() / 1000;
      r.published = steadySeconds();
      records_.push_back(r);
      index = records_.size() - 1;
      pending_[r.stamp_us] = index;
    }
    info_pub_.publish(info);
    depth_pub_.publish(depth);
    rgb_pub_.publish(rgb);
    return index;
  }

  /** Publishes malformed message number @p n (one of six kinds in turn), stamped between frames. */
  void publishBad(std::size_t n)
  {
    const Frame& src = frames_in_memory_[n % frames_in_memory_.size()];
    const ros::Time stamp = nextStamp();
    auto depth = boost::make_shared<sensor_msgs::Image>(*src.depth);
    auto rgb = boost::make_shared<sensor_msgs::Image>(*src.rgb);
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(*src.info);
    depth->header.stamp = rgb->header.stamp = info->header.stamp = stamp;
    switch (n % 6)
    {
      case 0: depth->data.resize(depth->data.size() / 3); depth_pub_.publish(depth); break;
      case 1: rgb->width = rgb->height = 0; rgb->data.clear(); rgb_pub_.publish(rgb); break;
      case 2: rgb->encoding = "yuv9"; rgb_pub_.publish(rgb); break;
      case 3: info->K[0] = std::numeric_limits<double>::quiet_NaN(); info_pub_.publish(info); break;
      case 4: depth->step = 1u << 30; depth_pub_.publish(depth); break;
      default:
      {
        auto cloud = boost::make_shared<sensor_msgs::PointCloud2>();
        cloud->header = depth->header;
        cloud->width = 1000000;
        cloud->height = 1;
        cloud->point_step = 16;
        cloud->row_step = 16000000;
        sensor_msgs::PointField f;
        f.datatype = sensor_msgs::PointField::FLOAT32;
        f.count = 1;
        for (const char* name : { "x", "y", "z" })
        {
          f.name = name;
          cloud->fields.push_back(f);
          f.offset += 4;
        }
        cloud->data.resize(4096);
        cloud_pub_.publish(cloud);
      }
    }
    ++bad_sent_;
  }

  /** Counts pending frames older than the timeout as dropped. Call with mutex_ held. */
  void dropExpired(double now)
  {
    for (auto it = pending_.begin(); it != pending_.end();)
    {
      if (now - records_[it->second].published < timeout_)
      {
        ++it;
        continue;
      }
      ++dropped_;
      NODELET_WARN_THROTTLE(5, "bench_player: no states for a frame within %.1f s: counted as dropped", timeout_);
      it = pending_.erase(it);
    }
  }

  /** Closed loop: waits until fewer than @p limit frames are pending (dropping expired ones). */
  void waitPending(std::size_t limit)
  {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_ && ros::ok() && pending_.size() >= limit)
    {
      double oldest = std::numeric_limits<double>::infinity();
      for (const auto& p : pending_)
        oldest = std::min(oldest, records_[p.second].published);
      const double wait = std::max(0.0, oldest + timeout_ - steadySeconds());
      if (cv_.wait_for(lock, std::chrono::duration<double>(std::min(wait, 0.5))) == std::cv_status::timeout)
        dropExpired(steadySeconds());
    }
  }

  void run()
  {
    if (!loadBags())
      return finish(false, "could not load the bags");
    // The pipeline is lazy: it subscribes once our states subscription has woken it up.
    const double connect_start = steadySeconds();
    while (!stop_ && ros::ok() &&
           !(rgb_pub_.getNumSubscribers() && depth_pub_.getNumSubscribers() && info_pub_.getNumSubscribers()))
    {
      if (steadySeconds() - connect_start > 60.0)
        return finish(false, "nobody subscribed to " + rgb_topic_ + ", " + depth_topic_ + " and " + info_topic_ +
                                 " within 60 s (is depth_image_proc loaded and the pipeline listening?)");
      NODELET_INFO_THROTTLE(5, "bench_player: waiting for depth_image_proc to subscribe to the images");
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }

    // Warm-up, closed loop: the tracker finds the ground and the person; not measured.
    std::size_t next = 0;
    for (int i = 0; i < warmup_ && !stop_ && ros::ok(); ++i)
    {
      publishFrame(next++);
      waitPending(1);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      warmup_dropped_ = dropped_;
      dropped_ = 0;
      pending_.clear();
      records_.clear();
      records_.reserve(static_cast<std::size_t>(frames_));
      unknown_states_ = 0;
      out_of_order_ = 0;
      arrivals_ = 0;
      measuring_ = true;
    }
    copy_ms_ = bench::StageSamples();
    load_start_ = loadAverage();
    char pacing[64] = "max";
    if (mode_ == "rate")
      std::snprintf(pacing, sizeof(pacing), "rate %g Hz", rate_);
    NODELET_INFO("bench_player: measuring %d frames, mode %s (load average %s)", frames_, pacing,
                 load_start_.c_str());

    start_wall_ = steadySeconds();
    start_cpu_ = processCpuSeconds();
    const double start_thread_cpu = threadCpuSeconds();
    sample(0);
    for (int i = 0; i < frames_ && !stop_ && ros::ok(); ++i)
    {
      if (mode_ == "max")
        waitPending(static_cast<std::size_t>(in_flight_));
      else
      {
        const double due = start_wall_ + i / rate_;
        const double wait = due - steadySeconds();
        if (wait > 0)
          std::this_thread::sleep_for(std::chrono::duration<double>(wait));
        std::lock_guard<std::mutex> lock(mutex_);
        dropExpired(steadySeconds());
      }
      publishFrame(next++);
      const int done = i + 1;
      if (bad_every_ > 0 && done % bad_every_ == 0)
        publishBad(static_cast<std::size_t>(done / bad_every_));
      if (done % sample_every_ == 0 && done < frames_)
      {
        if (mode_ == "max")
          waitPending(1);  // sample when the pipeline is idle, with this frame answered
        sample(static_cast<std::size_t>(done));
      }
      if (done % progress_every_ == 0)
        progress(done);
    }
    waitPending(1);  // the last frames' states, or their timeout
    end_wall_ = steadySeconds();
    player_cpu_ = threadCpuSeconds() - start_thread_cpu;
    sample(records_.size());
    finish(!stop_ && ros::ok(), stop_ || !ros::ok() ? "interrupted" : "");
  }

  /** Memory and CPU at @p frame measured frames, with fps and latency over the frames since the last sample. */
  void sample(std::size_t frame)
  {
    Sample s;
    s.frame = frame;
    s.wall = steadySeconds() - start_wall_;
    s.rss = residentMb();
    s.cpu = processCpuSeconds() - start_cpu_;
    bench::StageSamples latency;
    std::size_t answered = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const std::size_t from = samples_.empty() ? 0 : samples_.back().frame;
      for (std::size_t k = from; k < std::min(frame, records_.size()); ++k)
        if (records_[k].latency >= 0)
        {
          latency.add(1e3 * records_[k].latency);
          ++answered;
        }
    }
    if (!samples_.empty() && s.wall > samples_.back().wall)
    {
      const Sample& p = samples_.back();
      s.cores = (s.cpu - p.cpu) / (s.wall - p.wall);
      s.fps = answered / (s.wall - p.wall);
    }
    if (!latency.empty())
    {
      s.median = latency.median();
      s.p95 = latency.p95();
    }
    samples_.push_back(s);
  }

  void progress(int done)
  {
    const double wall = steadySeconds() - start_wall_;
    bench::StageSamples latency;
    std::size_t answered = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (const auto& r : records_)
        if (r.latency >= 0)
        {
          latency.add(1e3 * r.latency);
          ++answered;
        }
    }
    NODELET_INFO("bench_player: %d/%d frames, %.1f fps, %.2f cores, latency median %.1f ms p95 %.1f ms, RSS %.0f MB%s",
                 done, frames_, answered / wall, (processCpuSeconds() - start_cpu_) / wall,
                 latency.empty() ? 0.0 : latency.median(), latency.empty() ? 0.0 : latency.p95(), residentMb(),
                 bad_every_ > 0 ? (", " + std::to_string(bad_sent_) + " bad messages").c_str() : "");
  }

  /**
 * RSS growth, MB per 1000 frames, between the mean of the 2nd quarter's samples and the last
 * quarter's; null with fewer than 3 samples in either (runs shorter than ~12 x sample_every).
 */
  nlohmann::json rssGrowth(std::size_t frames) const
  {
    double sum2 = 0, sum4 = 0, f2 = 0, f4 = 0;
    int n2 = 0, n4 = 0;
    for (const auto& s : samples_)
    {
      if (s.frame >= frames / 4 && s.frame < frames / 2)
      {
        sum2 += s.rss;
        f2 += s.frame;
        ++n2;
      }
      else if (s.frame >= 3 * frames / 4)
      {
        sum4 += s.rss;
        f4 += s.frame;
        ++n4;
      }
    }
    // A few samples per quarter would mostly show the start-up rise and the loop's sawtooth.
    if (n2 < 3 || n4 < 3 || f4 / n4 <= f2 / n2)
      return nullptr;
    return 1000.0 * (sum4 / n4 - sum2 / n2) / (f4 / n4 - f2 / n2);
  }

  void finish(bool complete, const std::string& why)
  {
    if (!why.empty())
      NODELET_ERROR("bench_player: %s", why.c_str());
    if (!measuring_ || output_dir_.empty())
    {
      if (output_dir_.empty())
        NODELET_ERROR("bench_player: no ~output_dir: results not written");
      return shutdown();
    }
    try
    {
      writeResults(complete, why);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("bench_player: %s", e.what());
    }
    shutdown();
  }

  void shutdown()
  {
    if (shutdown_when_done_ && !stop_)
    {
      NODELET_INFO("bench_player: done, shutting the manager down");
      ros::requestShutdown();
    }
  }

  /** What writeResults reports of the measured frames and labels. */
  struct Totals
  {
    bench::StageSamples latency, label_latency, window_end_latency;  // ms
    std::size_t processed = 0, with_person = 0;
    double tracks = 0;         // over the processed frames
    double rss_max = 0;        // MB, of the samples
    double wall = 0, cpu = 0;  // s, of the measured run
  };

  void writeResults(bool complete, const std::string& why)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Totals t;
    const std::string frames_csv = framesCsv(t);
    const std::string labels_csv = labelsCsv(t);
    const std::string samples_csv = samplesCsv(t);
    std::ostringstream stages_csv;
    stages_csv << "at_s,stage,latency_ms\n";
    for (const StageLatency& s : stage_latencies_)
      stages_csv << s.at - start_wall_ << ',' << s.stage << ',' << s.ms << '\n';
    t.wall = end_wall_ > start_wall_ ? end_wall_ - start_wall_ : steadySeconds() - start_wall_;
    t.cpu = samples_.empty() ? 0.0 : samples_.back().cpu;
    const nlohmann::json j = summary(complete, why, t);

    std::filesystem::create_directories(output_dir_);
    const std::string dir = output_dir_ + "/";
    writeTextAtomically(dir + "frames.csv", frames_csv);
    writeTextAtomically(dir + "labels.csv", labels_csv);
    writeTextAtomically(dir + "samples.csv", samples_csv);
    writeTextAtomically(dir + "stages.csv", stages_csv.str());
    // summary.json last: its presence means the rest is there.
    writeTextAtomically(dir + "summary.json", j.dump(2) + "\n");
    NODELET_INFO("bench_player: %zu of %zu frames processed in %.1f s (%.1f fps, %.2f cores), "
                 "latency median %.1f ms p95 %.1f ms; results in %s",
                 t.processed, records_.size(), t.wall, t.wall > 0 ? t.processed / t.wall : 0.0,
                 t.wall > 0 ? t.cpu / t.wall : 0.0, t.latency.empty() ? 0.0 : t.latency.median(),
                 t.latency.empty() ? 0.0 : t.latency.p95(), dir.c_str());
  }

  /** frames.csv of the records, with their latencies and counts into @p t (mutex_ held). */
  std::string framesCsv(Totals& t) const
  {
    std::ostringstream csv;
    csv << "frame,stamp_us,published_s,arrived_s,latency_ms,arrival_order,tracks\n";
    for (std::size_t k = 0; k < records_.size(); ++k)
    {
      const Record& r = records_[k];
      csv << k << ',' << r.stamp_us << ',' << r.published - start_wall_ << ',';
      if (r.latency >= 0)
      {
        ++t.processed;
        t.latency.add(1e3 * r.latency);
        t.tracks += r.tracks;
        t.with_person += r.tracks > 0;
        csv << r.arrived - start_wall_ << ',' << 1e3 * r.latency << ',' << r.arrival_order << ','
            << r.tracks << '\n';
      }
      else
        csv << ",,,\n";
    }
    return csv.str();
  }

  /** labels.csv, with the labels' latencies into @p t (mutex_ held). */
  std::string labelsCsv(Totals& t) const
  {
    std::ostringstream csv;
    csv << "stamp_us,latency_ms,window_end_latency_ms,track,label\n";
    for (const auto& l : labels_)
    {
      t.label_latency.add(1e3 * l.latency);
      t.window_end_latency.add(1e3 * l.window_end_latency);
      csv << l.stamp_us << ',' << 1e3 * l.latency << ',' << 1e3 * l.window_end_latency << ','
          << l.track << ',' << l.label << '\n';
    }
    return csv.str();
  }

  /** samples.csv, with the largest RSS sampled into @p t. */
  std::string samplesCsv(Totals& t) const
  {
    std::ostringstream csv;
    csv << "frame,wall_s,rss_mb,cpu_s,cores,fps,latency_median_ms,latency_p95_ms\n";
    for (const auto& s : samples_)
    {
      t.rss_max = std::max(t.rss_max, s.rss);
      csv << s.frame << ',' << s.wall << ',' << s.rss << ',' << s.cpu << ',' << s.cores << ','
          << s.fps << ',' << s.median << ',' << s.p95 << '\n';
    }
    return csv.str();
  }

  /** summary.json: the run's settings and @p t (mutex_ held). */
  nlohmann::json summary(bool complete, const std::string& why, const Totals& t) const
  {
    const double wall = t.wall, cpu = t.cpu;
    const std::size_t processed = t.processed;
    nlohmann::json j;
    j["complete"] = complete;
    j["error"] = why;
    j["mode"] = mode_;
    j["rate_hz"] = mode_ == "rate" ? nlohmann::json(rate_) : nlohmann::json(nullptr);
    j["in_flight"] = in_flight_;
    std::vector<std::string> bags;  // results files are kept in the project: no one machine's layout
    for (const auto& path : bag_paths_)
      bags.push_back(packageRelative(path));
    j["bags"] = bags;
    j["bag_frames"] = frames_in_memory_.size();
    j["bag_images_mb"] = bag_bytes_ / 1e6;
    j["width"] = width_;
    j["height"] = height_;
    j["warmup_frames"] = warmup_;
    j["warmup_dropped"] = warmup_dropped_;
    j["frames_requested"] = frames_;
    j["frames_published"] = records_.size();
    j["frames_processed"] = processed;
    j["frames_dropped"] = records_.size() - processed;
    j["frames_out_of_order"] = out_of_order_;
    j["states_unmatched"] = unknown_states_;
    j["frames_with_person"] = t.with_person;
    j["tracks_per_frame"] = processed ? t.tracks / processed : 0.0;
    j["wall_s"] = wall;
    j["fps"] = wall > 0 ? processed / wall : 0.0;
    j["cpu_s"] = cpu;
    j["cpu_cores"] = wall > 0 ? cpu / wall : 0.0;
    j["player_cpu_cores"] = wall > 0 ? player_cpu_ / wall : 0.0;
    j["copy_ms"] = percentiles(copy_ms_);
    j["latency_ms"] = percentiles(t.latency);
    j["label_latency_ms"] = percentiles(t.label_latency);
    j["label_window_end_latency_ms"] = percentiles(t.window_end_latency);
    j["labels"] = labels_.size();
    j["bad_every"] = bad_every_;
    j["bad_messages"] = bad_sent_;
    j["rss_mb"] = { { "first", samples_.empty() ? 0.0 : samples_.front().rss },
                    { "last", samples_.empty() ? 0.0 : samples_.back().rss },
                    { "max", t.rss_max } };
    j["rss_growth_mb_per_1000_frames"] = rssGrowth(records_.size());
    j["sample_every"] = sample_every_;
    j["load_average_start"] = load_start_;
    j["load_average_end"] = loadAverage();
    return j;
  }

  // parameters
  std::vector<std::string> bag_paths_;
  std::vector<std::unique_ptr<rosbag::Bag>> bags_;  // opened in onInit, closed at unload (see there)
  std::string rgb_topic_ = "/camera/rgb/image_color";
  std::string depth_topic_ = "/camera/depth_registered/image_raw";
  std::string info_topic_ = "/camera/rgb/camera_info";
  int max_bag_frames_ = 1200;
  int frames_ = 10000;
  int warmup_ = 30;
  std::string mode_ = "max";
  double rate_ = 30.0;
  int in_flight_ = 1;
  double timeout_ = 5.0;
  int sample_every_ = 100;
  int progress_every_ = 1000;
  std::string output_dir_;
  bool shutdown_when_done_ = true;
  int bad_every_ = 0;
  std::string cloud_topic_ = "camera/depth_registered/points_from_images";

  // input
  std::vector<Frame> frames_in_memory_;
  double bag_bytes_ = 0;
  std::uint32_t width_ = 0, height_ = 0;
  ros::Publisher rgb_pub_, depth_pub_, info_pub_, cloud_pub_;
  std::size_t bad_sent_ = 0;  // the player thread's
  ros::Subscriber states_sub_, labels_sub_, diagnostics_sub_;
  std::uint64_t last_stamp_us_ = 0;

  // shared with the callbacks (mutex_)
  std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<Record> records_;
  std::map<std::uint64_t, std::size_t> pending_;  // stamp (us) -> record
  std::vector<LabelRecord> labels_;
  struct StageLatency
  {
    double at;  // steady clock, s
    std::string stage;
    double ms;
  };
  std::vector<StageLatency> stage_latencies_;
  std::uint64_t last_arrived_us_ = 0;
  int arrivals_ = 0;
  std::size_t dropped_ = 0, warmup_dropped_ = 0, unknown_states_ = 0, out_of_order_ = 0;
  bool measuring_ = false;

  // the player thread's own
  std::vector<Sample> samples_;
  bench::StageSamples copy_ms_;
  double start_wall_ = 0, end_wall_ = 0, start_cpu_ = 0, player_cpu_ = 0;
  std::string load_start_;

  std::atomic<bool> stop_{ false };
  std::thread thread_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::BenchPlayerNodelet, nodelet::Nodelet)
