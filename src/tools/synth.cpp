// synth: renders the synthetic IAS-Lab-style dataset, its continuous streams of actions, the MSR
// Action3D skeletons or streams of them as Kinect bags (one per sample, plus index.csv), or preview images. See
// docs/synth.md.
#include "../offline/cli.h"
#include "../offline/synth_bag.h"

#include <action_flow/files.h>
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

// Samples and frames done, shown as a bar (ProgressLine: redrawn on a terminal, a line every 10 s in a log).
class Progress
{
public:
  Progress(size_t samples, bool quiet) : samples_(samples), quiet_(quiet) {}
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
  double seconds() const { return line_.seconds(); }
  long frames() const { return frames_; }

private:
  void draw(bool last)
  {
    if (quiet_)
      return;
    line_.show(
        [&] {
          const double t = seconds();
          const size_t done = done_;
          const int width = 30;
          const int fill = samples_ ? int(width * done / samples_) : width;
          const double eta = done ? t / done * (samples_ - done) : 0.0;
          char buf[256];
          std::snprintf(buf, sizeof buf, "[%s%s] %zu/%zu samples, %ld frames, %.1f frames/s, elapsed %s, eta %s ",
                        std::string(size_t(fill), '#').c_str(), std::string(size_t(width - fill), '.').c_str(), done,
                        samples_, frames_.load(), t > 0 ? frames_ / t : 0.0, fmtTime(t).c_str(),
                        done ? fmtTime(eta).c_str() : "?");
          return std::string(buf);
        },
        last);
  }
  size_t samples_;
  bool quiet_;
  std::atomic<size_t> done_{ 0 };
  std::atomic<long> frames_{ 0 };
  action_flow::tools::ProgressLine line_;
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

// What the command line asks for.
struct Settings
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
};

// The options into Settings; @throws UsageError naming a bad one.
Settings readSettings(const action_flow::tools::Args& args)
{
  Settings st;
  st.dataset = args.get("dataset", st.dataset);
  st.skeletons = args.get("skeletons");
  st.segments = args.get("segments");
  st.all_msr = args.has("all-msr");
  st.people_given = args.has("people");
  st.people = int(args.integer("people", st.people, 1, 99));
  st.scenes = int(args.integer("scenes", st.scenes, 1, 999));
  st.seconds = double(args.integer("seconds", 60, 2, 3600));
  st.repetitions = int(args.integer("repetitions", st.repetitions, 1, 99));
  st.first_person = int(args.integer("first-person", st.first_person, 1, 99));
  st.streams = int(args.integer("streams", st.streams, 1, 99));
  st.stream_actions = int(args.integer("stream-actions", st.stream_actions, 1, 99));
  st.seed = std::uint64_t(args.integer("seed", 1, 0, 2147483647));
  st.only_person = args.get("person");
  st.only_action = args.get("action");
  st.only_rep = int(args.integer("repetition", 0, 1, 99));
  st.every = int(args.integer("every", st.every, 1, 1000000));
  st.limit = int(args.integer("limit", st.limit, 1, 1000000));
  st.max_frames = int(args.integer("frames", st.max_frames, 1, 1000000));
  st.out = args.get("out", st.out);
  st.jobs = int(args.integer("jobs", st.jobs, 1, 64));
  st.skip_existing = args.has("skip-existing");
  st.bag.points = args.has("points");
  st.bag.raw_images = args.has("raw-images");
  st.bag.compression = args.get("compression", st.bag.compression);
  st.bag.jpeg_quality = int(args.integer("jpeg-quality", st.bag.jpeg_quality, 1, 100));
  st.bag.points_topic = args.get("points-topic", st.bag.points_topic);
  st.bag.rgb_topic = args.get("rgb-topic", st.bag.rgb_topic);
  st.bag.depth_topic = args.get("depth-topic", st.bag.depth_topic);
  st.bag.info_topic = args.get("info-topic", st.bag.info_topic);
  st.bag.mask_topic = args.get("mask-topic", st.bag.mask_topic);
  st.bag.tf_topic = args.get("tf-topic", st.bag.tf_topic);
  st.bag.action_topic = args.get("action-topic", st.bag.action_topic);
  st.list = args.has("list");
  st.preview = args.has("preview");
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
    st.preview_at.push_back(f);
  }
  st.fakenect = args.has("fakenect");
  st.montage = args.get("montage");
  st.quiet = args.has("quiet");
  if (st.bag.compression != "none" && st.bag.compression != "lz4" && st.bag.compression != "bz2")
    throw action_flow::tools::UsageError("--compression must be none, lz4 or bz2, got '" + st.bag.compression + "'");
  if (st.fakenect && (st.preview || st.dataset == "crowd"))
    throw action_flow::tools::UsageError("--fakenect writes one sample's frames: not with --preview or --dataset crowd");
  if (st.preview_at.empty())
    st.preview_at.push_back(0.5);
  return st;
}

// Every sample of the dataset the settings name.
std::vector<SampleSpec> datasetSamples(const Settings& st)
{
  std::vector<SampleSpec> specs;
  if (st.dataset == "ias")
    specs = iasLabSamples(st.people, st.repetitions, st.seed);
  else if (st.dataset == "stream")
    specs = streamSamples(st.first_person, st.people, st.streams, st.stream_actions, st.seed);
  else if (st.dataset == "clutter")
    specs = clutterSamples(st.repetitions, st.seed);
  else if (st.dataset == "msr")
  {
    if (st.skeletons.empty())
      fail("--dataset msr needs --skeletons DIR (the MSR Action3D skeleton folder)");
    specs = msrSamples(st.skeletons, st.seed, !st.all_msr);
  }
  else if (st.dataset == "msr_stream")
  {
    if (st.skeletons.empty())
      fail("--dataset msr_stream needs --skeletons DIR (or a skeleton file with --segments FILE)");
    if (!st.segments.empty())
    {
      SampleSpec s;
      s.dataset = "msr_stream";
      s.person = st.only_person.empty() ? "s01" : st.only_person;  // the body
      s.action = "stream";
      s.seed = st.seed;
      s.skeleton_file = st.skeletons;
      s.segments_file = st.segments;
      specs = { s };
    }
    else
    {
      std::vector<std::string> subjects;
      if (!st.only_person.empty())
        subjects = { st.only_person };
      else
        for (const SampleSpec& m : msrSamples(st.skeletons, st.seed))
          if (subjects.empty() || subjects.back() != m.person)
            subjects.push_back(m.person);
      std::sort(subjects.begin(), subjects.end());
      subjects.erase(std::unique(subjects.begin(), subjects.end()), subjects.end());
      specs = msrStreamSamples(st.skeletons, subjects, st.streams, st.stream_actions, st.seed);
    }
  }
  else if (st.dataset == "crowd")
    specs = crowdSamples(st.people_given ? st.people : 3, st.scenes, st.seconds, st.seed);
  else
    fail("--dataset must be ias, stream, msr, msr_stream, crowd or clutter, got '" + st.dataset + "'");
  if (!st.segments.empty() && st.dataset != "msr_stream")
    fail("--segments is for --dataset msr_stream (a continuous skeleton file)");
  return specs;
}

// The samples selected by --person, --action, --repetition, --every and --limit.
std::vector<SampleSpec> selectSamples(const Settings& st, const std::vector<SampleSpec>& specs)
{
  if (!st.only_action.empty() && st.dataset == "ias")
  {
    const auto& acts = iasLabActions();
    if (std::find(acts.begin(), acts.end(), st.only_action) == acts.end())
      fail("--action: unknown action '" + st.only_action + "'");
  }
  std::vector<SampleSpec> selected;
  size_t matching = 0;
  for (SampleSpec s : specs)
  {
    if ((!st.only_person.empty() && s.person != st.only_person) || (!st.only_action.empty() && s.action != st.only_action) ||
        (st.only_rep && s.repetition != st.only_rep))
      continue;
    if (matching++ % size_t(st.every) != 0)
      continue;
    s.max_frames = st.max_frames;
    selected.push_back(s);
    if (st.limit && int(selected.size()) >= st.limit)
      break;
  }
  return selected;
}

// Renders the selected samples on st.jobs threads: frames_of[k] the frames written of sample k
// (-1: not complete), preview_files[k] its previews' prefixes. Returns the first error, if any.
std::string renderAll(const Settings& st, const std::vector<SampleSpec>& selected, const fs::path& dir, Progress& progress,
                      std::vector<int>& frames_of, std::vector<std::vector<std::string>>& preview_files)
{
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
          frames_of[k] = renderCrowd(spec, dir, st.preview, st.preview_at, st.bag, st.skip_existing, progress, preview_files[k]);
          if (frames_of[k] < 0)
            return;  // interrupted
          progress.sample();
          continue;
        }
        SampleRenderer sample(spec);
        if (st.preview)
        {
          for (double at : st.preview_at)
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
        else if (st.fakenect)
        {
          const fs::path path = dir / (spec.name() + ".fakenect");
          if (!(st.skip_existing && fs::exists(path / "INDEX.txt")) &&
              !writeFakenectDump(sample, path.string(), &g_cancel, [&]() { progress.frame(); }))
            return;  // interrupted; the temporary folder is gone
          frames_of[k] = sample.frames();
        }
        else
        {
          const fs::path path = dir / (spec.name() + ".bag");
          if (!(st.skip_existing && fs::exists(path)) &&
              !writeSampleBag(sample, path.string(), st.bag, &g_cancel, [&]() { progress.frame(); }))
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
  action_flow::runWorkers(std::min<int>(st.jobs, int(selected.size())), worker);
  return first_error;
}

// The index lists every complete sample: this run's, and those of earlier runs into the same
// folder whose bags are still there (a second `--action` run adds to it, it does not replace it).
// Written under a temporary name, then renamed. Returns the complete samples of this run.
size_t writeIndex(const fs::path& dir, const std::vector<SampleSpec>& selected, const std::vector<int>& frames_of)
{
  size_t complete = 0;
  std::error_code ec;
  const fs::path index = dir / "index.csv";
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
  std::ostringstream csv;
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
  try
  {
    action_flow::writeTextAtomically(index.string(), csv.str());
  }
  catch (const std::exception& e)
  {
    fail(e.what());
  }
  return complete;
}

// One grid of all previews: colour row above depth row for each, up to 5 per row, at 1/3 size.
void writeMontage(const std::string& montage, const std::vector<std::vector<std::string>>& preview_files)
{
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

}  // namespace

int main(int argc, char** argv)
{
  const action_flow::tools::Options o = options();
  Settings st;
  try
  {
    const action_flow::tools::Args args(argc, argv, o);
    if (args.has("help"))
      return o.printHelp();
    st = readSettings(args);
  }
  catch (const std::exception& e)
  {
    std::cerr << "synth: " << e.what() << " (--help lists the options)" << std::endl;
    return 2;
  }
  std::vector<SampleSpec> selected;
  try
  {
    selected = selectSamples(st, datasetSamples(st));
  }
  catch (const std::exception& e)
  {
    fail(e.what());
  }
  if (selected.empty())
    fail("no sample matches the selection");
  if (st.list)
  {
    for (const SampleSpec& s : selected)
      std::cout << s.name() << "," << s.person << "," << s.action << "," << s.repetition << "\n";
    return 0;
  }

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const fs::path dir = st.preview ? fs::path(st.out) : fs::path(st.out) / st.dataset;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    fail(dir.string() + ": cannot create folder: " + ec.message());
  Progress progress(selected.size(), st.quiet);
  std::vector<int> frames_of(selected.size(), -1);
  std::vector<std::vector<std::string>> preview_files(selected.size());
  const std::string first_error = renderAll(st, selected, dir, progress, frames_of, preview_files);
  progress.finish();

  size_t complete = 0;
  if (st.fakenect)
    complete = size_t(std::count_if(frames_of.begin(), frames_of.end(), [](int f) { return f >= 0; }));
  else if (!st.preview)
    complete = writeIndex(dir, selected, frames_of);
  else if (!st.montage.empty() && first_error.empty() && !g_cancel)
    writeMontage(st.montage, preview_files);

  if (!first_error.empty())
    fail(first_error);
  if (g_cancel)
  {
    std::cerr << "synth: interrupted; " << complete << " complete samples kept and indexed, no partial file left"
              << std::endl;
    return 130;
  }
  if (!st.quiet)
    std::cerr << "synth: " << selected.size() << " samples, " << progress.frames() << " frames in "
              << fmtTime(progress.seconds()) << " -> " << dir.string() << std::endl;
  return 0;
}
