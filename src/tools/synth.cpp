// synth: renders the synthetic IAS-Lab-style dataset, its continuous streams of actions, the MSR
// Action3D skeletons or streams of them as Kinect bags (one per sample, plus index.csv), or preview images. See
// docs/synth.md.
#include "cli.h"
#include "synth_bag.h"

#include <action_flow/synth/crowd.h>
#include <action_flow/synth/clutter.h>
#include <action_flow/synth/synth.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <sstream>
#include <set>
#include <string>
#include <thread>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using namespace action_flow::synth;

namespace
{
std::atomic<bool> g_cancel{ false };
void onSignal(int) { g_cancel = true; }

const char* kSynopsis = R"(usage: synth [options]
Renders one bag per sample (in the layout of a Kinect recorded with the ROS OpenNI driver) into
OUT/<dataset>/<sample>.bag plus OUT/<dataset>/index.csv, or preview images.)";

action_flow::tools::Options options()
{
  action_flow::tools::Options o(kSynopsis);
  o.value("dataset", "ias|stream|msr|msr_stream|crowd|clutter",
          "ias: synthetic actors, 15 IAS-Lab actions (default); stream: the same actors performing actions in a row "
          "(pNN_stream_R.bag with /ground_truth/action, and pNN_stream_R_segments.csv); msr: MSR Action3D skeletons; "
          "msr_stream: an MSR subject's sequences in a row (sNN_msr_stream_R.bag and sNN_msr_stream_R_segments.csv); "
          "crowd: several actors at once, entering, leaving, crossing, facing any way (crowdN_S.bag, "
          "crowdN_S_segments.csv with a person column, crowdN_S_people.csv: each person's position and visibility "
          "per frame); clutter: the actors in cluttered rooms (walls, chairs, tables, shelves, doors, cut by the image "
          "border) and rooms of furniture only, KIND_NN.bag, for people detection (docs/synth.md)")
      .value("skeletons", "DIR", "msr, msr_stream: folder of aAA_sSS_eEE_skeleton3D.txt files (required)")
      .value("segments", "FILE", "msr_stream: --skeletons is one continuous skeleton file in the MSR format and FILE "
                                 "its truth (CSV action,first_frame,last_frame in the file's 15 fps frames); the body "
                                 "is --person's (default s01); the bag is named after the file")
      .flag("all-msr", "msr: also sequences not in files_used_in_cvpr12_paper.txt")
      .value("people", "N", "ias, stream: number of actors (default 12); crowd: people per scene, 2-5 (default 3)")
      .value("scenes", "S", "crowd: number of scenes (default 2)")
      .value("seconds", "T", "crowd: length of a scene in seconds (default 60)")
      .value("repetitions", "N", "ias: repetitions of each action (default 3); clutter: scenes of each kind")
      .value("first-person", "K", "stream: the actors are pK.. (default 1)")
      .value("streams", "S", "stream, msr_stream: streams per actor or subject (default 2)")
      .value("stream-actions", "A", "stream, msr_stream: actions (MSR sequences) per stream (default 8; sit_down + "
                                    "get_up count as two)")
      .value("seed", "N", "dataset seed (default 1); same seed, byte-identical output")
      .value("person", "ID", "render only this person's samples")
      .value("action", "NAME", "render only this action's samples")
      .value("repetition", "N", "render only this repetition")
      .value("every", "N", "only every Nth selected sample (a spread-out subset, e.g. for timing)")
      .value("limit", "N", "only the first N selected samples")
      .value("frames", "N", "at most N frames per sample")
      .value("out", "DIR", "output folder (default synth_data)")
      .value("jobs", "N", "samples rendered in parallel (default 1)")
      .flag("skip-existing", "keep bags already complete from an earlier run")
      .flag("points", "also write the organized PointCloud2 (large: ~10 MB a frame)")
      .flag("raw-images", "sensor_msgs/Image topics instead of <topic>/compressed (JPEG colour, PNG depth)")
      .value("compression", "none|lz4|bz2", "bag chunk compression (default lz4)")
      .value("jpeg-quality", "Q", "colour JPEG quality 1-100 (default 80)")
      .value("points-topic", "T", "topic of the cloud")
      .value("rgb-topic", "T", "topic of the colour image")
      .value("depth-topic", "T", "topic of the depth image")
      .value("info-topic", "T", "topic of the camera_info")
      .value("mask-topic", "T", "topic of the person mask")
      .value("tf-topic", "T", "topic of the camera's TF")
      .value("action-topic", "T", "topic of a stream's ground-truth action (default /ground_truth/action)")
      .flag("list", "print the selected samples and exit")
      .flag("preview", "write PNGs instead of bags: OUT/<sample>_fNNN_color.png and _depth.png")
      .value("preview-at", "F[,F...]", "preview frames as fractions of the sample (default 0.5)")
      .value("montage", "FILE", "with --preview: also one JPEG grid of all previews (colour above depth)")
      .flag("fakenect", "write fakenect dumps instead of bags: OUT/<dataset>/<sample>.fakenect/ (INDEX.txt, RGB and "
                        "11-bit depth frames; replay with kinect.launch backend:=freenect device_uri:=DIR); not indexed, "
                        "about 1.5 MB a frame")
      .flag("quiet", "no progress bar");
  return o;
}

[[noreturn]] void fail(const std::string& msg)
{
  std::cerr << "synth: " << msg << std::endl;
  std::exit(1);
}


std::string fmtTime(double s)
{
  char buf[32];
  const int t = int(s + 0.5);
  std::snprintf(buf, sizeof buf, "%d:%02d:%02d", t / 3600, (t / 60) % 60, t % 60);
  return buf;
}

class Progress
{
public:
  Progress(size_t samples, bool quiet)
    : samples_(samples), quiet_(quiet), tty_(isatty(2) != 0), start_(std::chrono::steady_clock::now())
  {
  }
  void frame()
  {
    ++frames_;
    draw(false);
  }
  void sample()
  {
    ++done_;
    draw(false);
  }
  void finish() { draw(true); }
  double seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  long frames() const { return frames_; }

private:
  void draw(bool last)
  {
    if (quiet_)
      return;
    std::lock_guard<std::mutex> lock(mutex_);
    const double t = seconds();
    // A terminal gets a bar redrawn in place; a log gets a line every 10 s.
    if (!last && t - last_draw_ < (tty_ ? 0.25 : 10.0))
      return;
    last_draw_ = t;
    const size_t done = done_;
    const int width = 30;
    const int fill = samples_ ? int(width * done / samples_) : width;
    const double eta = done ? t / done * (samples_ - done) : 0.0;
    std::fprintf(stderr, "%s[%s%s] %zu/%zu samples, %ld frames, %.1f frames/s, elapsed %s, eta %s ",
                 tty_ ? "\r" : "", std::string(size_t(fill), '#').c_str(), std::string(size_t(width - fill), '.').c_str(), done,
                 samples_, frames_.load(), t > 0 ? frames_ / t : 0.0, fmtTime(t).c_str(),
                 done ? fmtTime(eta).c_str() : "?");
    if (last || !tty_)
      std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  size_t samples_;
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point start_;
  std::atomic<size_t> done_{ 0 };
  std::atomic<long> frames_{ 0 };
  std::mutex mutex_;
  double last_draw_ = -1;
};

/** Renders a crowd scene: its bag and truth files (or previews); returns its frames, -1 if interrupted. */
int renderCrowd(const SampleSpec& spec, const fs::path& dir, bool preview, const std::vector<double>& preview_at,
                const BagOptions& bag, bool skip_existing, Progress& progress, std::vector<std::string>& previews)
{
  CrowdRenderer crowd(spec);
  if (preview)
    for (double at : preview_at)
    {
      const int f = std::min(crowd.frames() - 1, int(at * (crowd.frames() - 1) + 0.5));
      char buf[16];
      std::snprintf(buf, sizeof buf, "_f%03d", f);
      previews.push_back((dir / (spec.name() + buf)).string());
      writeCrowdPreview(crowd, f, previews.back());
      progress.frame();
    }
  else
  {
    const fs::path path = dir / (spec.name() + ".bag");
    if (skip_existing && fs::exists(path) && fs::exists(dir / (spec.name() + "_people.csv")))
      return crowd.frames();
    std::vector<std::vector<CrowdTruth>> truth;
    if (!writeCrowdBag(crowd, path.string(), bag, &truth, &g_cancel, [&]() { progress.frame(); }))
      return -1;
    writeCrowdTruth(crowd, truth, (dir / spec.name()).string());
  }
  return crowd.frames();
}

}  // namespace

int main(int argc, char** argv)
{
  std::string dataset = "ias", skeletons, segments, out = "synth_data", montage;
  std::string only_person, only_action;
  int only_rep = 0, every = 1, people = 12, repetitions = 3, limit = 0, max_frames = 0, jobs = 1;
  int first_person = 1, streams = 2, stream_actions = 8, scenes = 2;
  double seconds = 60.0;
  bool people_given = false;
  std::uint64_t seed = 1;
  bool all_msr = false, skip_existing = false, list = false, preview = false, quiet = false, fakenect = false;
  std::vector<double> preview_at;
  BagOptions bag;
  const action_flow::tools::Options o = options();
  std::unique_ptr<action_flow::tools::Args> parsed;
  try
  {
    parsed = std::make_unique<action_flow::tools::Args>(argc, argv, o);
  }
  catch (const std::exception& e)
  {
    std::cerr << "synth: " << e.what() << " (--help lists the options)" << std::endl;
    return 2;
  }
  const action_flow::tools::Args& args = *parsed;
  if (args.has("help"))
    return o.printHelp();
  try
  {
    dataset = args.get("dataset", dataset);
    skeletons = args.get("skeletons");
    segments = args.get("segments");
    all_msr = args.has("all-msr");
    people_given = args.has("people");
    people = int(args.integer("people", people, 1, 99));
    scenes = int(args.integer("scenes", scenes, 1, 999));
    seconds = double(args.integer("seconds", 60, 2, 3600));
    repetitions = int(args.integer("repetitions", repetitions, 1, 99));
    first_person = int(args.integer("first-person", first_person, 1, 99));
    streams = int(args.integer("streams", streams, 1, 99));
    stream_actions = int(args.integer("stream-actions", stream_actions, 1, 99));
    seed = std::uint64_t(args.integer("seed", 1, 0, 2147483647));
    only_person = args.get("person");
    only_action = args.get("action");
    only_rep = int(args.integer("repetition", 0, 1, 99));
    every = int(args.integer("every", every, 1, 1000000));
    limit = int(args.integer("limit", limit, 1, 1000000));
    max_frames = int(args.integer("frames", max_frames, 1, 1000000));
    out = args.get("out", out);
    jobs = int(args.integer("jobs", jobs, 1, 64));
    skip_existing = args.has("skip-existing");
    bag.points = args.has("points");
    bag.raw_images = args.has("raw-images");
    bag.compression = args.get("compression", bag.compression);
    bag.jpeg_quality = int(args.integer("jpeg-quality", bag.jpeg_quality, 1, 100));
    bag.points_topic = args.get("points-topic", bag.points_topic);
    bag.rgb_topic = args.get("rgb-topic", bag.rgb_topic);
    bag.depth_topic = args.get("depth-topic", bag.depth_topic);
    bag.info_topic = args.get("info-topic", bag.info_topic);
    bag.mask_topic = args.get("mask-topic", bag.mask_topic);
    bag.tf_topic = args.get("tf-topic", bag.tf_topic);
    bag.action_topic = args.get("action-topic", bag.action_topic);
    list = args.has("list");
    preview = args.has("preview");
    std::stringstream at(args.get("preview-at"));
    for (std::string v; std::getline(at, v, ',');)
    {
      std::size_t used = 0;
      double f = -1;
      try
      {
        f = std::stod(v, &used);
      }
      catch (const std::exception&)
      {
      }
      if (used != v.size() || !(f >= 0 && f <= 1))
        throw action_flow::tools::UsageError("--preview-at expects numbers in [0,1], got '" + v + "'");
      preview_at.push_back(f);
    }
    fakenect = args.has("fakenect");
    montage = args.get("montage");
    quiet = args.has("quiet");
  }
  catch (const std::exception& e)
  {
    std::cerr << "synth: " << e.what() << std::endl;
    return 2;
  }
  if (bag.compression != "none" && bag.compression != "lz4" && bag.compression != "bz2")
    fail("--compression must be none, lz4 or bz2, got '" + bag.compression + "'");
  if (fakenect && (preview || dataset == "crowd"))
    fail("--fakenect writes one sample's frames: not with --preview or --dataset crowd");
  if (preview_at.empty())
    preview_at.push_back(0.5);

  std::vector<SampleSpec> specs;
  try
  {
    if (dataset == "ias")
      specs = iasLabSamples(people, repetitions, seed);
    else if (dataset == "stream")
      specs = streamSamples(first_person, people, streams, stream_actions, seed);
    else if (dataset == "clutter")
      specs = clutterSamples(repetitions, seed);
    else if (dataset == "msr")
    {
      if (skeletons.empty())
        fail("--dataset msr needs --skeletons DIR (the MSR Action3D skeleton folder)");
      specs = msrSamples(skeletons, seed, !all_msr);
    }
    else if (dataset == "msr_stream")
    {
      if (skeletons.empty())
        fail("--dataset msr_stream needs --skeletons DIR (or a skeleton file with --segments FILE)");
      if (!segments.empty())
      {
        SampleSpec s;
        s.dataset = "msr_stream";
        s.person = only_person.empty() ? "s01" : only_person;  // the body
        s.action = "stream";
        s.seed = seed;
        s.skeleton_file = skeletons;
        s.segments_file = segments;
        specs = { s };
      }
      else
      {
        std::vector<std::string> subjects;
        if (!only_person.empty())
          subjects = { only_person };
        else
          for (const SampleSpec& m : msrSamples(skeletons, seed))
            if (subjects.empty() || subjects.back() != m.person)
              subjects.push_back(m.person);
        std::sort(subjects.begin(), subjects.end());
        subjects.erase(std::unique(subjects.begin(), subjects.end()), subjects.end());
        specs = msrStreamSamples(skeletons, subjects, streams, stream_actions, seed);
      }
    }
    else if (dataset == "crowd")
      specs = crowdSamples(people_given ? people : 3, scenes, seconds, seed);
    else
      fail("--dataset must be ias, stream, msr, msr_stream, crowd or clutter, got '" + dataset + "'");
    if (!segments.empty() && dataset != "msr_stream")
      fail("--segments is for --dataset msr_stream (a continuous skeleton file)");
  }
  catch (const std::exception& e)
  {
    fail(e.what());
  }
  if (!only_action.empty() && dataset == "ias")
  {
    const auto& acts = iasLabActions();
    if (std::find(acts.begin(), acts.end(), only_action) == acts.end())
      fail("--action: unknown action '" + only_action + "'");
  }
  std::vector<SampleSpec> selected;
  size_t matching = 0;
  for (SampleSpec s : specs)
  {
    if ((!only_person.empty() && s.person != only_person) || (!only_action.empty() && s.action != only_action) ||
        (only_rep && s.repetition != only_rep))
      continue;
    if (matching++ % size_t(every) != 0)
      continue;
    s.max_frames = max_frames;
    selected.push_back(s);
    if (limit && int(selected.size()) >= limit)
      break;
  }
  if (selected.empty())
    fail("no sample matches the selection");
  if (list)
  {
    for (const SampleSpec& s : selected)
      std::cout << s.name() << "," << s.person << "," << s.action << "," << s.repetition << "\n";
    return 0;
  }

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const fs::path dir = preview ? fs::path(out) : fs::path(out) / dataset;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    fail(dir.string() + ": cannot create folder: " + ec.message());
  Progress progress(selected.size(), quiet);

  std::vector<int> frames_of(selected.size(), -1);
  std::vector<std::vector<std::string>> preview_files(selected.size());
  std::atomic<size_t> next{ 0 };
  std::mutex error_mutex;
  std::string first_error;
  const auto worker = [&]() {
    for (;;)
    {
      const size_t k = next++;
      if (k >= selected.size() || g_cancel)
        return;
      const SampleSpec& spec = selected[k];
      try
      {
        if (spec.dataset == "crowd")
        {
          frames_of[k] = renderCrowd(spec, dir, preview, preview_at, bag, skip_existing, progress, preview_files[k]);
          if (frames_of[k] < 0)
            return;  // interrupted
          progress.sample();
          continue;
        }
        SampleRenderer sample(spec);
        if (preview)
        {
          for (double at : preview_at)
          {
            const int f = std::min(sample.frames() - 1, int(at * (sample.frames() - 1) + 0.5));
            char buf[16];
            std::snprintf(buf, sizeof buf, "_f%03d", f);
            const std::string prefix = (dir / (spec.name() + buf)).string();
            writePreview(sample, f, prefix);
            preview_files[k].push_back(prefix);
            progress.frame();
          }
          frames_of[k] = sample.frames();
        }
        else if (fakenect)
        {
          const fs::path path = dir / (spec.name() + ".fakenect");
          if (!(skip_existing && fs::exists(path / "INDEX.txt")) &&
              !writeFakenectDump(sample, path.string(), &g_cancel, [&]() { progress.frame(); }))
            return;  // interrupted; the temporary folder is gone
          frames_of[k] = sample.frames();
        }
        else
        {
          const fs::path path = dir / (spec.name() + ".bag");
          if (!(skip_existing && fs::exists(path)) &&
              !writeSampleBag(sample, path.string(), bag, &g_cancel, [&]() { progress.frame(); }))
            return;  // interrupted; the temporary file is gone
          // A stream's ground truth beside its bag (after it: a bag without one is completed by
          // --skip-existing).
          if (spec.dataset == "stream" || spec.dataset == "msr_stream")
            writeSegmentsCsv(sample, (dir / (spec.name() + "_segments.csv")).string());
          frames_of[k] = sample.frames();
        }
        progress.sample();
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (first_error.empty())
          first_error = spec.name() + ": " + e.what();
        g_cancel = true;
        return;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 0; j < std::min<int>(jobs, int(selected.size())); ++j)
    threads.emplace_back(worker);
  for (auto& t : threads)
    t.join();
  progress.finish();

  // The index lists every complete sample: this run's, and those of earlier runs into the same
  // folder whose bags are still there (a second `--action` run adds to it, it does not replace it).
  // Written under a temporary name, then renamed.
  size_t complete = 0;
  if (fakenect)
    complete = size_t(std::count_if(frames_of.begin(), frames_of.end(), [](int f) { return f >= 0; }));
  else if (!preview)
  {
    const fs::path index = dir / "index.csv", tmp = dir / "index.csv.tmp";
    static const std::string kHeader = "path,person,action,repetition,frames";
    std::set<std::string> written;
    for (size_t k = 0; k < selected.size(); ++k)
      if (frames_of[k] >= 0)
        written.insert(selected[k].name() + ".bag");
    std::vector<std::string> kept;
    {
      std::ifstream old(index);
      std::string line;
      if (std::getline(old, line) && line == kHeader)
        while (std::getline(old, line))
        {
          const std::string bag = line.substr(0, line.find(','));
          if (!bag.empty() && !written.count(bag) && fs::is_regular_file(dir / bag, ec))
            kept.push_back(line);
        }
    }
    {
      std::ofstream csv(tmp);
      csv << kHeader << "\n";
      for (const std::string& line : kept)
        csv << line << "\n";
      for (size_t k = 0; k < selected.size(); ++k)
        if (frames_of[k] >= 0)
        {
          csv << selected[k].name() << ".bag," << selected[k].person << "," << selected[k].action << ","
              << selected[k].repetition << "," << frames_of[k] << "\n";
          ++complete;
        }
      if (!csv)
        fail(tmp.string() + ": cannot write the index");
    }
    fs::rename(tmp, index, ec);
    if (ec)
      fail(index.string() + ": cannot rename the index into place: " + ec.message());
  }
  else if (!montage.empty() && first_error.empty() && !g_cancel)
  {
    // One grid: colour row above depth row for each preview, up to 5 per row, at 1/3 size.
    std::vector<cv::Mat> tiles;
    for (const auto& files : preview_files)
      for (const std::string& prefix : files)
      {
        cv::Mat c = cv::imread(prefix + "_color.png"), d = cv::imread(prefix + "_depth.png");
        cv::Mat both;
        cv::vconcat(c, d, both);
        cv::resize(both, both, cv::Size(), 1.0 / 3, 1.0 / 3, cv::INTER_AREA);
        tiles.push_back(both);
      }
    const int cols = std::min<int>(5, int(tiles.size()));
    std::vector<cv::Mat> rows;
    for (size_t i = 0; i < tiles.size(); i += size_t(cols))
    {
      std::vector<cv::Mat> row(tiles.begin() + long(i), tiles.begin() + long(std::min(tiles.size(), i + size_t(cols))));
      while (int(row.size()) < cols)
        row.push_back(cv::Mat::zeros(tiles[0].size(), tiles[0].type()));
      cv::Mat r;
      cv::hconcat(row, r);
      rows.push_back(r);
    }
    cv::Mat grid;
    cv::vconcat(rows, grid);
    if (!cv::imwrite(montage, grid, { cv::IMWRITE_JPEG_QUALITY, 85 }))
      fail(montage + ": cannot write the montage");
  }

  if (!first_error.empty())
    fail(first_error);
  if (g_cancel)
  {
    std::cerr << "synth: interrupted; " << complete << " complete samples kept and indexed, no partial file left"
              << std::endl;
    return 130;
  }
  if (!quiet)
    std::cerr << "synth: " << selected.size() << " samples, " << progress.frames() << " frames in "
              << fmtTime(progress.seconds()) << " -> " << dir.string() << std::endl;
  return 0;
}
