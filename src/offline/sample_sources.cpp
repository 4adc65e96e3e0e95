#include "sample_sources.h"

#include "guarded_bag.h"

#include <action_flow/depth_cloud.h>
#include <action_flow/ros/input_checks.h>

#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/image_encodings.h>

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <map>
#include <sys/stat.h>

namespace action_flow
{
namespace tools
{
namespace
{
// Frames of one bag: the organized PointCloud2 topic if the bag has it, else depth + colour images
// with equal stamps (raw sensor_msgs/Image, or CompressedImage on <topic>/compressed: PNG depth in
// millimetres, JPEG colour) and camera_info, made into an organized cloud.
class BagFrameSource : public FrameSource
{
public:
  BagFrameSource(const std::string& path, const BagTopics& topics) : path_(path), topics_(topics)
  {
    try
    {
      bag_ = std::make_unique<GuardedBag>(path, rosbag::bagmode::Read);
    }
    catch (const rosbag::BagException& e)
    {
      throw DatasetError(path + ": cannot open bag (" + e.what() + ")");
    }
    rosbag::View probe(**bag_, rosbag::TopicQuery(std::vector<std::string>{ topics_.points }));
    use_points_ = probe.size() > 0;
    const std::vector<std::string> wanted =
        use_points_ ? std::vector<std::string>{ topics_.points } :
                      std::vector<std::string>{ topics_.depth, topics_.rgb, topics_.depth + "/compressed",
                                                topics_.rgb + "/compressed", topics_.info };
    view_ = std::make_unique<rosbag::View>(**bag_, rosbag::TopicQuery(wanted));
    if (view_->size() == 0)
      throw DatasetError(path + ": bag has neither " + topics_.points + " nor " + topics_.depth + " + " + topics_.rgb);
    it_ = view_->begin();
  }

  bool next(Cloud& cloud, double& stamp) override
  {
    try
    {
      return nextFrame(cloud, stamp);
    }
    catch (const rosbag::BagException& e)  // e.g. a damaged chunk: name the bag
    {
      throw DatasetError(path_ + ": cannot read the bag (" + e.what() + ")");
    }
    catch (const ros::Exception& e)
    {
      throw DatasetError(path_ + ": cannot read a message (" + e.what() + ")");
    }
  }

private:
  // Every message is checked as the live pipeline checks it (input_checks.h) before it is read.
  bool nextFrame(Cloud& cloud, double& stamp)
  {
    for (; it_ != view_->end(); ++it_)
    {
      const rosbag::MessageInstance& m = *it_;
      if (use_points_)
      {
        auto msg = m.instantiate<sensor_msgs::PointCloud2>();
        if (!msg)
          continue;
        const std::string error = checkPointCloud2(*msg);
        if (!error.empty())
          fail(topics_.points, "a point cloud that " + error);
        pcl::fromROSMsg(*msg, cloud);
        stamp = msg->header.stamp.toSec();
        ++it_;
        return true;
      }
      const bool is_depth = m.getTopic().rfind(topics_.depth, 0) == 0;
      if (auto info = m.instantiate<sensor_msgs::CameraInfo>())
      {
        const std::string error = checkCameraInfo(*info);
        if (!error.empty())
          fail(topics_.info, "a camera_info that " + error);
        // The projection P, as depth_image_proc uses it live (checkCameraInfo requires it).
        k_.fx = info->P[0], k_.cx = info->P[2], k_.fy = info->P[5], k_.cy = info->P[6];
        have_info_ = true;
      }
      else if (auto img = m.instantiate<sensor_msgs::Image>())
      {
        const std::string error = checkImage(*img);
        if (!error.empty())
          fail(is_depth ? topics_.depth : topics_.rgb, "an image that " + error);
        is_depth ? readDepth(*img) : readColour(*img);
      }
      else if (auto jpg = m.instantiate<sensor_msgs::CompressedImage>())
        is_depth ? readDepth(*jpg) : readColour(*jpg);
      if (have_info_ && depth_stamp_ == colour_stamp_ && depth_stamp_ > 0.0)
      {
        depthToCloud(depth_m_.data(), rgb8_.data(), width_, height_, k_, cloud);
        stamp = depth_stamp_;
        depth_stamp_ = -1.0;
        colour_stamp_ = -2.0;
        ++it_;
        return true;
      }
    }
    return false;
  }

  [[noreturn]] void fail(const std::string& topic, const std::string& what) const
  {
    throw DatasetError(path_ + ": topic " + topic + ": " + what);
  }

  void size(int w, int h, const std::string& topic)
  {
    if (w <= 0 || h <= 0 || (width_ > 0 && (w != width_ || h != height_)))
      fail(topic, "image size " + std::to_string(w) + "x" + std::to_string(h) + " differs from the other stream");
    width_ = w;
    height_ = h;
  }

  void readDepth(const sensor_msgs::Image& img)
  {
    namespace enc = sensor_msgs::image_encodings;
    size(img.width, img.height, topics_.depth);
    depth_m_.resize(static_cast<std::size_t>(width_) * height_);
    if (img.encoding == enc::TYPE_32FC1)
      for (int v = 0; v < height_; ++v)
        std::memcpy(&depth_m_[v * width_], &img.data[v * img.step], sizeof(float) * width_);
    else if (img.encoding == enc::TYPE_16UC1)
      for (int v = 0; v < height_; ++v)
        for (int u = 0; u < width_; ++u)
        {
          std::uint16_t mm;
          std::memcpy(&mm, &img.data[v * img.step + 2 * u], 2);
          depth_m_[v * width_ + u] = mm * 0.001f;
        }
    else
      fail(topics_.depth, "encoding '" + img.encoding + "' (expected 32FC1 or 16UC1)");
    depth_stamp_ = img.header.stamp.toSec();
  }

  void readDepth(const sensor_msgs::CompressedImage& msg)
  {
    const std::string damage = checkPng(msg.data);
    if (!damage.empty())
      fail(topics_.depth + "/compressed", "an image that " + damage);
    const cv::Mat png = cv::imdecode(msg.data, cv::IMREAD_UNCHANGED);
    if (png.empty() || png.type() != CV_16UC1)
      fail(topics_.depth + "/compressed", "not a 16-bit PNG depth image (format '" + msg.format + "')");
    size(png.cols, png.rows, topics_.depth);
    depth_m_.resize(static_cast<std::size_t>(width_) * height_);
    for (int v = 0; v < height_; ++v)
      for (int u = 0; u < width_; ++u)
        depth_m_[v * width_ + u] = png.at<std::uint16_t>(v, u) * 0.001f;
    depth_stamp_ = msg.header.stamp.toSec();
  }

  void readColour(const sensor_msgs::Image& img)
  {
    namespace enc = sensor_msgs::image_encodings;
    const bool bgr = img.encoding == enc::BGR8;
    if (!bgr && img.encoding != enc::RGB8)
      fail(topics_.rgb, "encoding '" + img.encoding + "' (expected rgb8 or bgr8)");
    size(img.width, img.height, topics_.rgb);
    rgb8_.resize(static_cast<std::size_t>(3) * width_ * height_);
    for (int v = 0; v < height_; ++v)
      for (int u = 0; u < width_; ++u)
      {
        const std::uint8_t* p = &img.data[v * img.step + 3 * u];
        std::uint8_t* q = &rgb8_[3 * (v * width_ + u)];
        q[0] = bgr ? p[2] : p[0];
        q[1] = p[1];
        q[2] = bgr ? p[0] : p[2];
      }
    colour_stamp_ = img.header.stamp.toSec();
  }

  void readColour(const sensor_msgs::CompressedImage& msg)
  {
    const std::string damage = checkPng(msg.data);
    if (!damage.empty())
      fail(topics_.rgb + "/compressed", "an image that " + damage);
    const cv::Mat bgr = cv::imdecode(msg.data, cv::IMREAD_COLOR);
    if (bgr.empty())
      fail(topics_.rgb + "/compressed", "cannot decode the image (format '" + msg.format + "')");
    size(bgr.cols, bgr.rows, topics_.rgb);
    rgb8_.resize(static_cast<std::size_t>(3) * width_ * height_);
    for (int v = 0; v < height_; ++v)
      for (int u = 0; u < width_; ++u)
      {
        const cv::Vec3b& p = bgr.at<cv::Vec3b>(v, u);
        std::uint8_t* q = &rgb8_[3 * (v * width_ + u)];
        q[0] = p[2];
        q[1] = p[1];
        q[2] = p[0];
      }
    colour_stamp_ = msg.header.stamp.toSec();
  }

  std::string path_;
  BagTopics topics_;
  std::unique_ptr<GuardedBag> bag_;  // destroyed after the view (members go in reverse order)
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  bool use_points_ = false;
  bool have_info_ = false;
  Intrinsics k_;
  int width_ = 0, height_ = 0;
  double depth_stamp_ = -1.0, colour_stamp_ = -2.0;
  std::vector<float> depth_m_;
  std::vector<std::uint8_t> rgb8_;
};

std::string fileFingerprint(const std::string& path)
{
  struct stat st;
  if (::stat(path.c_str(), &st) != 0)
    return "missing";
  return std::to_string(st.st_size) + "-" + std::to_string(st.st_mtime);
}
}  // namespace

std::vector<SampleRef> samplesFromIndex(const std::string& index, const BagTopics& topics,
                                        const std::vector<std::string>& known_actions)
{
  std::vector<SampleRef> out;
  for (const IndexEntry& e : readIndex(index, known_actions))
  {
    SampleRef s;
    s.key = e.person + "_" + e.action + "_" + std::to_string(e.repetition);
    for (char& c : s.key)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-')
        c = '_';
    s.person = e.person;
    s.action = e.action;
    s.repetition = e.repetition;
    s.fingerprint = "bag:" + e.path + ":" + fileFingerprint(e.path);
    s.where = e.path;
    const std::string path = e.path;
    s.open = [path, topics]() -> std::unique_ptr<FrameSource> {
      return std::make_unique<BagFrameSource>(path, topics);
    };
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace tools
}  // namespace action_flow

#include "cli.h"
#include "extraction.h"

#include <algorithm>

#include <cmath>
#include <cstdlib>

namespace action_flow
{
namespace tools
{
void addSampleOptions(Options& o)
{
  o.group("sample options")
      .value("synth", "ias|msr", "render the samples in-process with the virtual Kinect (no bags)")
      .value("people", "N", "ias: actors p01..pN (default 12)")
      .value("repetitions", "R", "ias: each action R times (default 3)")
      .value("msr-dir", "FOLDER", "msr: the MSR Action3D skeleton files (aAA_sSS_eEE_skeleton.txt)")
      .value("facing", "DEG", "ias: actors face DEG from the camera (0 towards it, 90 side on, 180 away; default 0)")
      .value("facing-spread", "DEG", "ias: +- this around --facing (default 30)")
      .value("seed", "N", "dataset seed (default 1)")
      .value("max-frames", "N", "render at most N frames of each sample (default 0: all)")
      .value("training-copies", "N",
             "msr: also render each training sample N more times, with another body, pace, turn and distance "
             "(training-time augmentation; copies train, are never tested; default 0)")
      .value("copy-changes", "a,b,...", "msr: what a training copy changes, of body, pace, turn, distance (default all)")
      .value("index", "INDEX.csv", "bags listed in a dataset index instead (docs/synth.md)")
      .value("points-topic", "T", "the index's bags' cloud topic (IAS-Lab layout by default)")
      .value("depth-topic", "T", "their depth image topic")
      .value("rgb-topic", "T", "their colour image topic")
      .value("info-topic", "T", "their camera_info topic")
      .value("actions", "a,b,...", "only these actions (e.g. an MSR subset)")
      .value("persons", "a,b,...", "only these people (e.g. the training subjects alone, to develop a setting "
                                   "without a test subject: --protocol lopo --persons s01,s03,...)");
}

std::vector<SampleRef> selectSamples(const Args& args)
{
  BagTopics topics;
  topics.points = args.get("points-topic", topics.points);
  topics.depth = args.get("depth-topic", topics.depth);
  topics.rgb = args.get("rgb-topic", topics.rgb);
  topics.info = args.get("info-topic", topics.info);
  if (args.has("index") == args.has("synth"))
    throw UsageError("give exactly one of --index INDEX.csv and --synth ias|msr");
  std::vector<SampleRef> all = args.has("index") ? samplesFromIndex(args.get("index"), topics) : samplesFromSynth(args);
  const auto listed = [&](const char* option, const std::string& value) {
    if (!args.has(option))
      return true;
    const auto keep = splitList(args.get(option));
    return std::find(keep.begin(), keep.end(), value) != keep.end();
  };
  std::vector<SampleRef> kept;
  for (auto& s : all)
    if (listed("actions", s.action) && listed("persons", s.person))
      kept.push_back(std::move(s));
  return kept;
}

std::vector<std::string> trainPersons(const Args& args)
{
  return splitList(args.get("train-persons", kDefaultTrainPersons));
}

std::string cacheDir(const Args& args)
{
  if (args.has("cache"))
    return args.get("cache");
  const char* home = std::getenv("HOME");
  return std::string(home ? home : ".") + "/.ros/action_flow/cache";
}

}  // namespace tools
}  // namespace action_flow

#include <action_flow/synth/synth.h>

namespace action_flow
{
namespace tools
{
namespace
{
// Frames rendered in-process by the virtual Kinect, one at a time.
class SynthFrameSource : public FrameSource
{
public:
  explicit SynthFrameSource(const synth::SampleSpec& spec) : renderer_(spec) {}
  bool next(Cloud& cloud, double& stamp) override
  {
    if (next_ >= renderer_.frames())
      return false;
    renderer_.render(next_, cloud);
    stamp = renderer_.stamp(next_++);
    return true;
  }

private:
  synth::SampleRenderer renderer_;
  int next_ = 0;
};
}  // namespace

// Part of every rendered sample's cache key: bump it when the renderer's output changes, so that
// cached descriptors of the old rendering are not reused.
constexpr const char* kRendererRevision = "synth-r1";

std::vector<SampleRef> samplesFromSynth(const Args& args)
{
  const std::string which = args.get("synth");
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1000000000));
  std::vector<synth::SampleSpec> specs;
  if (which == "ias")
    specs = synth::iasLabSamples(static_cast<int>(args.integer("people", 12, 1, 1000)),
                                 static_cast<int>(args.integer("repetitions", 3, 1, 100)), seed);
  else if (which == "msr")
  {
    if (!args.has("msr-dir"))
      throw UsageError("--synth msr needs --msr-dir FOLDER (the MSR Action3D skeleton files)");
    specs = synth::msrSamples(args.get("msr-dir"), seed);
  }
  else
    throw UsageError("--synth must be ias or msr, not '" + which + "'");
  if ((args.has("facing") || args.has("facing-spread")) && which != "ias")
    throw UsageError("--facing and --facing-spread are for --synth ias");
  const double facing = args.number("facing", 0.0), spread = args.number("facing-spread", 30.0);
  if (!(std::abs(facing) <= 180.0) || !(spread >= 0.0 && spread <= 180.0))
    throw UsageError("--facing must be in -180..180 and --facing-spread in 0..180 (degrees)");
  const int max_frames = static_cast<int>(args.integer("max-frames", 0, 0, 100000));
  const int copies = static_cast<int>(args.integer("training-copies", 0, 0, 99));
  if (copies > 0 && which != "msr")
    throw UsageError("--training-copies renders copies of --synth msr samples only");
  const std::string protocol = args.get("protocol", "lopo");
  if (copies > 0 && protocol != "lopo" && protocol != "cross-subject")
    throw UsageError("--training-copies is for train and for evaluate's protocols lopo and cross-subject");
  unsigned changes = 0;
  for (const std::string& c : splitList(args.get("copy-changes", "body,pace,turn,distance")))
  {
    const std::vector<std::string> names = { "body", "pace", "turn", "distance" };
    const auto at = std::find(names.begin(), names.end(), c);
    if (at == names.end())
      throw UsageError("--copy-changes: '" + c + "' is none of body, pace, turn, distance");
    changes |= 1u << (at - names.begin());
  }
  if (changes == 0)
    throw UsageError("--copy-changes names no change");
  // Cross-subject: only the training subjects' samples train, so only theirs are copied.
  const std::vector<std::string> copied =
      protocol == "cross-subject" ? trainPersons(args) : std::vector<std::string>{};
  std::vector<SampleRef> out;
  for (auto spec : specs)
  {
    spec.max_frames = max_frames;
    spec.facing = facing;
    spec.facing_spread = spread;
    out.push_back(renderedSample(spec));
    if (copied.empty() || std::find(copied.begin(), copied.end(), spec.person) != copied.end())
      for (spec.copy = 1; spec.copy <= copies; ++spec.copy)
      {
        spec.copy_changes = changes;
        out.push_back(renderedSample(spec));
      }
  }
  return out;
}

CrossViewSet crossViewSamples(const Args& args)
{
  if (args.get("synth") != "ias" || args.has("index") || args.has("facing") || args.has("facing-spread"))
    throw UsageError("--protocol cross-view renders its own samples: give --synth ias, without --index or --facing");
  const int people = static_cast<int>(args.integer("people", 12, 2, 99));
  const int train_reps = static_cast<int>(args.integer("repetitions", 3, 1, 99));
  const int test_reps = static_cast<int>(args.integer("test-repetitions", 1, 1, 99));
  const double train_spread = args.number("train-spread", 15.0);
  if (!(train_spread >= 0.0 && train_spread <= 180.0))
    throw UsageError("--train-spread must be in 0..180 degrees");
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1000000000));
  const int max_frames = static_cast<int>(args.integer("max-frames", 0, 0, 100000));
  std::vector<std::string> train = splitList(args.get("train-persons", ""));
  if (train.empty())
    for (int p = 1; p <= people / 2; ++p)
      train.push_back(std::string(p < 10 ? "p0" : "p") + std::to_string(p));
  CrossViewSet set;
  set.train_spread = train_spread;
  set.views = { 0.0 };
  for (const std::string& v : splitList(args.get("views", "45,90,135,180")))
  {
    std::size_t used = 0;
    double d = 0.0;
    try
    {
      d = std::stod(v, &used);
    }
    catch (const std::exception&)
    {
    }
    if (used != v.size() || !(d > 0.0 && d <= 180.0))
      throw UsageError("--views takes angles in (0, 180] degrees, got '" + v + "'");
    set.views.push_back(d);
  }
  const auto isTrain = [&](const std::string& p) { return std::find(train.begin(), train.end(), p) != train.end(); };
  const std::vector<std::string> actions = splitList(args.get("actions", ""));
  // The training people face the camera (0 +- 15); the others are rendered at every view, the
  // frontal view with the same spread.
  const auto add = [&](const synth::SampleSpec& spec, int view) {
    set.samples.push_back(renderedSample(spec));
    set.view_of.push_back(view);
  };
  for (const synth::SampleSpec& base : synth::iasLabSamples(people, std::max(train_reps, test_reps), seed))
  {
    synth::SampleSpec spec = base;
    spec.max_frames = max_frames;
    if (!actions.empty() && std::find(actions.begin(), actions.end(), spec.action) == actions.end())
      continue;
    if (isTrain(spec.person))
    {
      if (spec.repetition > train_reps)
        continue;
      spec.facing = 0.0;
      spec.facing_spread = train_spread;
      add(spec, -1);
      continue;
    }
    if (spec.repetition > test_reps)
      continue;
    for (std::size_t v = 0; v < set.views.size(); ++v)
    {
      spec.facing = set.views[v];
      spec.facing_spread = v == 0 ? 15.0 : 0.0;
      add(spec, static_cast<int>(v));
    }
  }
  const auto trained = std::count(set.view_of.begin(), set.view_of.end(), -1);
  if (trained == 0 || trained == static_cast<long>(set.view_of.size()))
    throw UsageError("--protocol cross-view needs training people (--train-persons) and others to test on");
  return set;
}

SampleRef renderedSample(const synth::SampleSpec& spec)
{
  SampleRef s;
  s.key = spec.name();
  s.person = spec.person;
  s.action = spec.action;
  s.repetition = spec.repetition;
  s.skeleton_file = spec.skeleton_file;
  s.copy = spec.copy;
  s.where = "rendered sample " + s.key;
  s.fingerprint = std::string(kRendererRevision) + ":" + spec.name() + ":" + std::to_string(spec.seed) + ":" +
                  std::to_string(spec.max_frames);
  // The streams' composition has its own revision; every track is kept.
  if (spec.dataset == "stream")
    s.fingerprint += ":stream-r1:" + std::to_string(spec.stream_actions) + ":all-tracks";
  else if (spec.dataset == "msr_stream")
  {
    s.fingerprint += ":msr-stream-r1:" + spec.skeleton_file + ":" + std::to_string(spec.stream_actions) + ":";
    for (const std::string& a : spec.stream_pool)
      s.fingerprint += a + ",";
    if (!spec.segments_file.empty())  // a continuous file: its content and its truth
      s.fingerprint += fileFingerprint(spec.skeleton_file) + ":" + spec.segments_file + ":" +
                       fileFingerprint(spec.segments_file);
    s.fingerprint += ":all-tracks";
  }
  s.all_tracks = spec.dataset == "stream" || spec.dataset == "msr_stream";
  s.open = [spec]() -> std::unique_ptr<FrameSource> { return std::make_unique<SynthFrameSource>(spec); };
  return s;
}

}  // namespace tools
}  // namespace action_flow
