// bench: per-stage timings of the flow pipeline and the classifier, ours beside the paper-faithful
// PCL-octree baseline on the same frames in the same run (see docs/bench.md).
#include "../offline/cli.h"
#include "../bench/octree_flow_baseline.h"
#include "../bench/stage_stats.h"
#include "../bench/training_set.h"


#include <action_flow/action_classifier.h>
#include <action_flow/action_model.h>
#include <action_flow/flow_estimator.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/posture_flow.h>
#include <action_flow/pca.h>
#include <action_flow/sequence_descriptor.h>
#include <action_flow/voxel_filter.h>
#include <pcl/filters/voxel_grid.h>
#include "../eval/evaluation.h"

#include <dirent.h>
#include <action_flow/synth/synth.h>
#include <action_flow/people_tracker.h>
#include <action_flow/depth_cloud.h>
#include <action_flow/ros/input_checks.h>
#include <depth_image_proc/depth_conversions.h>
#include <image_geometry/pinhole_camera_model.h>
#include <sensor_msgs/point_cloud2_iterator.h>
#include <boost/make_shared.hpp>
#include <cstring>
#include <initializer_list>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <memory>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

using namespace action_flow;
using namespace action_flow::bench;

namespace
{

struct Options
{
  int pairs = 200;
  std::vector<float> voxels{ 0.06f, 0.04f, 0.02f, 0.01f };
  int k = 50;
  double octree_resolution = 0.0;  // 0: the voxel size
  int training = 540;
  int queries = 300;
  bool baseline = true;
  bool classification = true;
  bool tracker = true;
  Clock clock = Clock::Wall;
  double octree_scale = 8.0;  // baseline octree resolution = this x voxel unless --octree-resolution
  std::string descriptors;  // an evaluate cache folder of real frame descriptors
  std::string query_person = "p12";
};

action_flow::tools::Options commandLine()
{
  action_flow::tools::Options o("usage: bench [options]\nTimes each stage against its baseline, side by side in one run "
                                "(benchmarks/results.md).");
  o.value("pairs", "N", "frame pairs timed per voxel size (>= 1, default 200)")
      .value("voxels", "V[,V...]", "voxel sizes in metres, each in [0.002, 0.2] (default 0.06,0.04,0.02,0.01)")
      .value("k", "K", "the flow's K (default 50)")
      .value("octree-resolution", "M", "the octree baseline's resolution (default: 8 x the voxel size)")
      .value("training", "N", "training sequences of the classification bench (>= 2, default 540)")
      .value("queries", "N", "its queries (default 300)")
      .flag("cpu-time", "time the thread's CPU time instead of wall time")
      .flag("no-baseline", "skip the baselines")
      .flag("no-classification", "skip the classification bench")
      .flag("no-tracker", "skip the tracker bench")
      .value("descriptors", "DIR", "classification on an evaluate cache folder's frame descriptors")
      .value("query-person", "P", "with --descriptors: P's samples are the queries, everyone else's the training "
                                  "set (default p12)");
  return o;
}

[[noreturn]] void usage(const std::string& error)
{
  std::fprintf(stderr, "bench: %s (--help lists the options)\n", error.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv)
{
  const action_flow::tools::Options cl = commandLine();
  Options o;
  try
  {
    const action_flow::tools::Args a(argc, argv, cl);
    if (a.has("help"))
      std::exit(cl.printHelp());
    o.pairs = static_cast<int>(a.integer("pairs", o.pairs, 1, 1000000));
    o.k = static_cast<int>(a.integer("k", o.k, 1, 1000));
    o.octree_resolution = a.number("octree-resolution", o.octree_resolution);
    o.training = static_cast<int>(a.integer("training", o.training, 2, 10000000));
    o.queries = static_cast<int>(a.integer("queries", o.queries, 1, 10000000));
    o.descriptors = a.get("descriptors");
    o.query_person = a.get("query-person", o.query_person);
    o.baseline = !a.has("no-baseline");
    o.classification = !a.has("no-classification");
    o.tracker = !a.has("no-tracker");
    if (a.has("cpu-time"))
      o.clock = Clock::ThreadCpu;
    if (a.has("voxels"))
    {
      o.voxels.clear();
      std::stringstream ss(a.get("voxels"));
      for (std::string item; std::getline(ss, item, ',');)
      {
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !(v >= 0.002 && v <= 0.2))
          usage("--voxels: each voxel size must be a number in [0.002, 0.2] m, got '" + item + "'");
        o.voxels.push_back(static_cast<float>(v));
      }
    }
  }
  catch (const std::invalid_argument& e)  // UsageError and the numbers
  {
    usage(e.what());
  }
  if (o.octree_resolution < 0 || o.voxels.empty())
    usage("--octree-resolution must be >= 0, --voxels not empty");
  return o;
}

std::string ms(double s)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", s * 1e3);
  return buf;
}

void row(const char* stage, const StageSamples& ours, const StageSamples* base)
{
  if (base && !base->empty())
    std::printf("| %-22s | %9s | %9s | %9s | %9s | %7.1fx |\n", stage, ms(ours.median()).c_str(), ms(ours.p95()).c_str(),
                ms(base->median()).c_str(), ms(base->p95()).c_str(), base->median() / ours.median());
  else
    std::printf("| %-22s | %9s | %9s | %9s | %9s | %8s |\n", stage, ms(ours.median()).c_str(), ms(ours.p95()).c_str(),
                "-", "-", "-");
}

void header(const char* title)
{
  std::printf("\n%s\n\n", title);
  std::printf("| %-22s | %9s | %9s | %9s | %9s | %8s |\n", "stage (ms)", "ours med", "ours p95", "base med", "base p95",
              "base/ours");
  std::printf("|%s|%s|%s|%s|%s|%s|\n", std::string(24, '-').c_str(), std::string(11, '-').c_str(),
              std::string(11, '-').c_str(), std::string(11, '-').c_str(), std::string(11, '-').c_str(),
              std::string(10, '-').c_str());
}

// One row of a result table: a stage's samples of ours and, when given, of the baseline.
struct TableRow
{
  const char* stage;
  const StageSamples& ours;
  const StageSamples* base;
};

// The table header under @p title, then one row per stage.
void table(const char* title, std::initializer_list<TableRow> rows)
{
  header(title);
  for (const TableRow& r : rows)
    row(r.stage, r.ours, r.base);
}

// One person's clouds in consecutive frames, at one voxel size.
struct PersonSequence
{
  std::vector<Cloud> clouds;
  std::vector<double> stamps;
  Eigen::Vector4f ground;  // in the clouds' frame, normal up
};

// The samples of one flow implementation's four steps, one per frame pair.
struct FlowStepSamples
{
  StageSamples build, match, vel, out, total;
  std::size_t kept = 0;  // flow vectors kept, over all frame pairs

  void add(double t_build, double t_match, double t_vel, double t_out, std::size_t kept_flow)
  {
    build.add(t_build);
    match.add(t_match);
    vel.add(t_vel);
    out.add(t_out);
    total.add(t_build + t_match + t_vel + t_out);
    kept += kept_flow;
  }
};

FlowParams flowParams(int k)
{
  FlowParams fp;
  fp.k = k;
  return fp;
}

Eigen::Vector3f centroid(const FlowFrame& frame)
{
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  for (std::size_t k = 0; k < frame.size(); ++k)
    c += frame.point(k);
  c /= std::max<std::size_t>(1, frame.size());
  return c;
}

// Our flow step and the octree baseline's, timed on the same frame pairs at one voxel size, and
// our descriptors on our flow.
class FlowBench
{
public:
  FlowBench(const Options& o, float voxel)
    : o_(o)
    , voxel_(voxel)
    , params_(flowParams(o.k))
    , ours_(params_)
    , base_(params_, o.octree_resolution > 0 ? o.octree_resolution : o.octree_scale * voxel)
  {
  }

  // Times the frame pairs of @p seq while fewer than o.pairs pairs are timed.
  void timeSequence(const PersonSequence& seq)
  {
    std::unique_ptr<FlowFrame> prev = std::make_unique<FlowFrame>(seq.clouds[0], seq.stamps[0]);
    std::unique_ptr<OctreeFlowBaseline::Frame> bprev = base_.prepare(seq.clouds[0], seq.stamps[0]);
    for (std::size_t i = 1; i < seq.clouds.size() && pairs_ < o_.pairs; ++i, ++pairs_)
    {
      const Cloud& cloud = seq.clouds[i];
      const double stamp = seq.stamps[i];
      points_ += cloud.size();
      // Alternate which goes first so neither always finds the caches warmed by the other.
      std::vector<Correspondence> mo, mb;
      if (!o_.baseline)
        mo = timeOurs(cloud, stamp, seq.ground, prev);
      else if (i % 2)
      {
        mo = timeOurs(cloud, stamp, seq.ground, prev);
        mb = timeBase(cloud, stamp, bprev);
      }
      else
      {
        mb = timeBase(cloud, stamp, bprev);
        mo = timeOurs(cloud, stamp, seq.ground, prev);
      }
      if (o_.baseline)
        compareMatches(mo, mb);
    }
  }

  // The table of the timed pairs and the flow's counts per frame.
  void print() const
  {
    if (pairs_ < 1)
      throw std::runtime_error("no frame pairs to time");
    char title[256];
    std::snprintf(title, sizeof title,
                  "### Flow, voxel %.2f m: person clouds of %.0f points on average, %d frame pairs, "
                  "K = %d",
                  voxel_, points_ / static_cast<double>(pairs_), pairs_, o_.k);
    const auto base = [&](const StageSamples& s) { return o_.baseline ? &s : nullptr; };
    table(title, { { "tree build", ours_steps_.build, base(base_steps_.build) },
                   { "matching (reciprocal)", ours_steps_.match, base(base_steps_.match) },
                   { "flow vectors", ours_steps_.vel, base(base_steps_.vel) },
                   { "outlier removal", ours_steps_.out, base(base_steps_.out) },
                   { "flow step total", ours_steps_.total, base(base_steps_.total) },
                   { "descriptor: paper's SUMFLOW", sumflow_, nullptr },
                   { "descriptor: posture_flow; base = SUMFLOW", posture_flow_time_, &sumflow_ } });
    const double np = pairs_;
    std::printf("\nflow vectors kept per frame: ours %.1f", ours_steps_.kept / np);
    if (o_.baseline)
      std::printf(", baseline %.1f; reciprocal correspondences: ours %.1f, baseline %.1f per "
                  "frame, %.2f %% of ours identical in the baseline",
                  base_steps_.kept / np, ours_matches_ / np, base_matches_ / np,
                  100.0 * agree_ / std::max<std::size_t>(1, ours_matches_));
    std::printf("\n");
    std::fflush(stdout);
  }

private:
  // Our four steps from *prev to @p cloud, then the descriptors on the flow kept; prev becomes
  // the new frame. Returns the correspondences.
  std::vector<Correspondence> timeOurs(const Cloud& cloud, double stamp,
                                       const Eigen::Vector4f& ground, std::unique_ptr<FlowFrame>& prev)
  {
    Stopwatch w(o_.clock);
    auto frame = std::make_unique<FlowFrame>(cloud, stamp);
    const double t_build = w.lap();
    FlowStats stats;
    const auto matches = ours_.correspond(*prev, *frame, stats);
    const double t_match = w.lap();
    const FlowVectors flow =
        FlowEstimator::velocities(*prev, *frame, matches, stamp - prev->stamp());
    const double t_vel = w.lap();
    const FlowVectors kept_flow = ours_.rejectOutliers(*frame, matches, flow, stats);
    const double t_out = w.lap();
    const Eigen::Vector3f c = centroid(*frame);
    const PersonFrame where = PersonFrame::fromGround(c, ground, 1.75f, c);
    w.lap();
    const Eigen::VectorXf d = grid_.compute(kept_flow, where);
    const double t_desc = w.lap();
    const Eigen::VectorXf pf = posture_flow_.compute(cloud, kept_flow, where);
    posture_flow_time_.add(w.lap());
    ours_steps_.add(t_build, t_match, t_vel, t_out, kept_flow.size());
    sumflow_.add(t_desc);
    prev = std::move(frame);
    return matches;
  }

  // The baseline's four steps from *prev to @p cloud; prev becomes the new frame.
  std::vector<Correspondence> timeBase(const Cloud& cloud, double stamp,
                                       std::unique_ptr<OctreeFlowBaseline::Frame>& prev)
  {
    Stopwatch w(o_.clock);
    auto frame = base_.prepare(cloud, stamp);
    const double t_build = w.lap();
    FlowStats stats;
    const auto matches = base_.correspond(*prev, *frame, stats);
    const double t_match = w.lap();
    const FlowVectors flow = base_.velocities(*prev, *frame, matches);
    const double t_vel = w.lap();
    const FlowVectors kept_flow = base_.rejectOutliers(*frame, matches, flow, stats);
    const double t_out = w.lap();
    base_steps_.add(t_build, t_match, t_vel, t_out, kept_flow.size());
    prev = std::move(frame);
    return matches;
  }

  // Counts our correspondences @p mo that the baseline's @p mb has too.
  void compareMatches(const std::vector<Correspondence>& mo, const std::vector<Correspondence>& mb)
  {
    std::set<std::pair<std::size_t, std::size_t>> b;
    for (const auto& m : mb)
      b.insert({ m.target, m.source });
    for (const auto& m : mo)
      agree_ += b.count({ m.target, m.source });
    ours_matches_ += mo.size();
    base_matches_ += mb.size();
  }

  const Options& o_;
  const float voxel_;
  const FlowParams params_;
  const FlowEstimator ours_;
  const OctreeFlowBaseline base_;
  const GridDescriptor grid_;
  const PostureFlowDescriptor posture_flow_;
  FlowStepSamples ours_steps_, base_steps_;
  StageSamples sumflow_, posture_flow_time_;  // our descriptors' times
  std::size_t points_ = 0, agree_ = 0, ours_matches_ = 0, base_matches_ = 0;
  int pairs_ = 0;
};

void benchFlow(const Options& o, float voxel, const std::vector<PersonSequence>& sequences)
{
  FlowBench bench(o, voxel);
  for (const PersonSequence& seq : sequences)
    bench.timeSequence(seq);
  bench.print();
}

// The samples of one evaluate cache folder (<person>_<action>_<repetition>_<key>.frames), split
// into training and query sequences by person.
void loadCachedSequences(const Options& o, std::vector<DescriptorSequence>& train, std::vector<DescriptorSequence>& queries)
{
  DIR* dir = ::opendir(o.descriptors.c_str());
  if (!dir)
    throw std::runtime_error("cannot open the descriptor folder '" + o.descriptors + "'");
  std::vector<std::string> names;
  while (const dirent* e = ::readdir(dir))
  {
    const std::string name = e->d_name;
    if (name.size() > 7 && name.compare(name.size() - 7, 7, ".frames") == 0)
      names.push_back(name);
  }
  ::closedir(dir);
  std::sort(names.begin(), names.end());
  for (const auto& name : names)
  {
    const auto first = name.find('_'), key = name.rfind('_'), repetition = name.rfind('_', key - 1);
    if (first == std::string::npos || repetition == std::string::npos || repetition <= first)
      throw std::runtime_error(o.descriptors + "/" + name + ": not named <person>_<action>_<repetition>_<key>.frames");
    SampleFrames frames;
    loadSampleFrames(o.descriptors + "/" + name, frames);
    if (frames.descriptors.rows() == 0)
      continue;  // no flow (the tracker missed the person): cannot be classified
    DescriptorSequence seq;
    seq.label = name.substr(first + 1, repetition - first - 1);
    seq.stamps = frames.stamps;
    for (Eigen::Index r = 0; r < frames.descriptors.rows(); ++r)
      seq.frames.push_back(frames.descriptors.row(r).transpose());
    (name.compare(0, first, o.query_person) == 0 ? queries : train).push_back(std::move(seq));
  }
  if (train.size() < 2 || queries.empty())
    throw std::runtime_error(o.descriptors + ": need training sequences and queries of person " + o.query_person);
}

// Model selection as trainModel runs it (chooseLinear: 3 groups of people held out in turn, each
// value of C) on @p model's training rows, beside the same held-out classifiers each trained on its
// own rows: @p t_subsets and @p t_gram receive the seconds of each.
void timeModelSelection(const ActionModel& model, const Options& o, double& t_subsets, double& t_gram)
{
  Stopwatch w(o.clock);
  std::vector<std::string> persons;
  for (std::size_t i = 0; i < model.labels.size(); ++i)
    persons.push_back("p" + std::to_string(i % 6));
  for (int f = 0; f < 3; ++f)
  {
    std::vector<Eigen::Index> rows, held_out;
    std::vector<std::string> labels;
    for (std::size_t i = 0; i < model.labels.size(); ++i)
      if (i % 6 % 3 == static_cast<std::size_t>(f))
        held_out.push_back(static_cast<Eigen::Index>(i));
      else
      {
        rows.push_back(static_cast<Eigen::Index>(i));
        labels.push_back(model.labels[i]);
      }
    for (const LinearClassifier& c :
         LinearClassifier::train(Eigen::MatrixXf(model.descriptors(rows, Eigen::all)), labels, linearCandidates()))
      for (Eigen::Index q : held_out)
        c.scores(model.descriptors.row(q).transpose());
  }
  t_subsets = w.lap();
  chooseLinear(model.descriptors, nullptr, model.labels, persons, { false }, linearCandidates());
  t_gram = w.lap();
}

// The default recognizer's classification: temporal pyramid of posture-and-flow frames, then the
// linear classifier (a product with the weights), on generated sequences of the same shape.
// @p fourier false is the previous default's pyramid of
// means and maxima, without the Fourier magnitudes, timed in the same run beside it.
void benchPostureFlowClassification(const Options& o, bool fourier)
{
  const int actions = 15;
  ActionModel model;
  model.params = defaultRecognitionParams();
  if (!fourier)
    model.params.pyramid.fourier = 0;
  model.params.pyramid.c = 0.01;
  model.params.pyramid.flow = FlowEncoding::Bins;
  model.params.pyramid.mirror = MirrorMode::Off;
  const int size = frameDescriptorLength(model.params);
  // makeSequences makes lengths that are multiples of 3: make one more and cut.
  const auto make = [&](int count, std::uint32_t seed) {
    std::vector<DescriptorSequence> s = makeSequences(count, actions, size + 3 - size % 3, seed);
    for (auto& q : s)
      for (auto& f : q.frames)
        f.conservativeResize(size);
    return s;
  };
  const std::vector<DescriptorSequence> train = make(o.training, 1), queries = make(o.queries, 2);
  Stopwatch w(o.clock);
  model.descriptors.resize(static_cast<Eigen::Index>(train.size()), model.sequenceLength());
  for (std::size_t i = 0; i < train.size(); ++i)
  {
    model.descriptors.row(static_cast<Eigen::Index>(i)) = model.sequence(train[i].frames, train[i].stamps).transpose();
    model.labels.push_back(train[i].label);
  }
  const double t_describe = w.lap();
  model.linear = LinearClassifier::train(model.descriptors, model.labels, model.params.pyramid.c, true);
  const double t_span = w.lap();
  LinearClassifier::train(model.descriptors, model.labels, model.params.pyramid.c, false);
  const double t_full = w.lap();
  double t_subsets = 0.0, t_gram = 0.0;
  timeModelSelection(model, o, t_subsets, t_gram);
  const SequenceClassifier classifier = model.classifier();
  std::printf("\n### Classification, posture_flow (%s): %zu training sequences of %d actions, %zu queries, "
              "generated; %ld values per sequence\n",
              fourier ? "the default, means, maxima and Fourier magnitudes" : "means and maxima, the previous default",
              train.size(),
              actions, queries.size(), static_cast<long>(model.sequenceLength()));
  std::printf("sequence descriptors %.2f s; training the linear classifier: %.2f s in the sequences' span, %.2f s "
              "over all values (%.1fx)\n",
              t_describe, t_span, t_full, t_full / std::max(1e-9, t_span));
  std::printf("model selection (3 groups of 6 people held out in turn, %zu values of C): %.2f s with each group's "
              "classifiers trained on its own rows, %.2f s on one Gram matrix (GramRows, %.1fx)\n",
              linearCandidates().size(), t_subsets, t_gram, t_subsets / std::max(1e-9, t_gram));
  StageSamples pyramid, linear, total;
  for (const auto& q : queries)
  {
    Stopwatch s(o.clock);
    const Eigen::VectorXf d = model.sequence(q.frames, q.stamps);
    const double t_seq = s.lap();
    classifier.classify(d);
    const double t_cls = s.lap();
    pyramid.add(t_seq);
    linear.add(t_cls);
    total.add(t_seq + t_cls);
  }
  header("| classification (ms)");
  row("temporal pyramid", pyramid, nullptr);
  row("linear classifier", linear, nullptr);
  row("classify, posture_flow", total, nullptr);
}

// The classification bench's training sequences and queries, and where they come from.
struct ClassificationSets
{
  std::vector<DescriptorSequence> train, queries;
  std::string source = "generated sequences";
  int actions = 15;
};

// Generated sequences of frame descriptors of @p size values, or those of --descriptors.
ClassificationSets classificationSets(const Options& o, int size)
{
  ClassificationSets s;
  if (o.descriptors.empty())
  {
    s.train = makeSequences(o.training, s.actions, size, 1);
    s.queries = makeSequences(o.queries, s.actions, size, 2);
    return s;
  }
  loadCachedSequences(o, s.train, s.queries);
  std::set<std::string> labels;
  for (const auto& t : s.train)
    labels.insert(t.label);
  s.actions = static_cast<int>(labels.size());
  s.source = "real frame descriptors from " + o.descriptors + ", queries: " + o.query_person;
  return s;
}

// The PCA of every frame descriptor of @p train (@p size values each), at 99 % of the variance.
Pca fitFramePca(const std::vector<DescriptorSequence>& train, int size)
{
  std::vector<Eigen::VectorXf> all_frames;
  for (const auto& s : train)
    all_frames.insert(all_frames.end(), s.frames.begin(), s.frames.end());
  Eigen::MatrixXf frame_matrix(all_frames.size(), size);
  for (std::size_t i = 0; i < all_frames.size(); ++i)
    frame_matrix.row(i) = all_frames[i].transpose();
  return Pca::fit(frame_matrix, 0.99);
}

// The classifier of @p train's sequence descriptors, frames projected on @p p unless it is empty.
ActionClassifier sequenceClassifier(const std::vector<DescriptorSequence>& train,
                                    const SequenceDescriptor& seq, const Pca& p, int size)
{
  Eigen::MatrixXf m(train.size(), 30 * (p.empty() ? size : p.outputSize()));
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < train.size(); ++i)
  {
    m.row(i) = seq.compute(train[i].frames, train[i].stamps, p).transpose();
    labels.push_back(train[i].label);
  }
  return ActionClassifier(std::move(m), labels);
}

// One query through one classifier: its sequence descriptor, the answers of the pruned search
// and of the full scan, and the time of each step.
struct QueryRun
{
  Eigen::VectorXf descriptor;
  Classification pruned, full;
  double t_seq = 0.0, t_nn = 0.0, t_scan = 0.0;
};

// A classifier (without or with PCA) and its samples over the queries.
struct TimedClassifier
{
  TimedClassifier(const ActionClassifier& c, const Pca& p) : classifier(c), pca(p) {}

  // Runs @p q into @p r on the running stopwatch @p s; add() takes the samples afterwards, so
  // that no bookkeeping falls into a timed step.
  void time(Stopwatch& s, const SequenceDescriptor& seq, const DescriptorSequence& q, QueryRun& r)
  {
    r.descriptor = seq.compute(q.frames, q.stamps, pca);
    r.t_seq = s.lap();
    r.pruned = classifier.classify(r.descriptor);
    r.t_nn = s.lap();
    completed += ActionClassifier::lastCompletedRows();
    r.full = classifier.classifyBruteForce(r.descriptor);
    r.t_scan = s.lap();
  }

  // Adds the samples of @p r, a query of action @p label; true when the full scan found another
  // neighbour than the pruned search.
  bool add(const QueryRun& r, const std::string& label)
  {
    sequence.add(r.t_seq);
    nn.add(r.t_nn);
    all.add(r.t_seq + r.t_nn);
    scan.add(r.t_scan);
    scan_all.add(r.t_seq + r.t_scan);
    right += r.pruned.label == label;
    return r.pruned.neighbour != r.full.neighbour;
  }

  const ActionClassifier& classifier;
  const Pca& pca;
  StageSamples sequence, nn, all, scan, scan_all;
  std::size_t completed = 0;  // rows the pruned search completed, over all queries
  int right = 0;              // queries labelled right
};

// Ours: the pruned search (ActionClassifier::classify); baseline: a scan of every full row
// (classifyBruteForce), timed alternately on the same queries. Both give the same answers.
// Returns the queries where either classifier's two answers differ.
std::size_t timeQueries(Clock clock, const std::vector<DescriptorSequence>& queries,
                        const SequenceDescriptor& seq, TimedClassifier& plain,
                        TimedClassifier& reduced)
{
  std::size_t disagree = 0;
  for (const auto& q : queries)
  {
    QueryRun a, b;
    Stopwatch s(clock);
    plain.time(s, seq, q, a);
    reduced.time(s, seq, q, b);
    const bool plain_differs = plain.add(a, q.label), reduced_differs = reduced.add(b, q.label);
    disagree += plain_differs || reduced_differs;
  }
  return disagree;
}

void printQueryTimes(const TimedClassifier& plain, const TimedClassifier& reduced, int n_train,
                     int n_queries, std::size_t disagree)
{
  char name[64];
  std::snprintf(name, sizeof name, "1-NN, %d values", 30 * reduced.pca.outputSize());
  table("| classification (ms); base = scan of every full row",
        { { "sequence descr. no PCA", plain.sequence, nullptr },
          { "1-NN, 5760 values", plain.nn, &plain.scan },
          { "classify, no PCA", plain.all, &plain.scan_all },
          { "sequence descr. + PCA", reduced.sequence, nullptr },
          { name, reduced.nn, &reduced.scan },
          { "classify, with PCA", reduced.all, &reduced.scan_all } });
  std::printf("\nrows completed per query by the pruned search: %.1f of %d without PCA, %.1f with; "
              "answers differing from the full scan: %zu\n",
              static_cast<double>(plain.completed) / n_queries, n_train,
              static_cast<double>(reduced.completed) / n_queries, disagree);
  std::printf("\n(sanity: %d / %d queries labelled right without PCA, %d with)\n", plain.right,
              n_queries, reduced.right);
}

void benchClassification(const Options& o)
{
  const int size = GridDescriptor().size();
  Stopwatch w(o.clock);
  const ClassificationSets sets = classificationSets(o, size);
  const Pca pca = fitFramePca(sets.train, size);
  const SequenceDescriptor seq(30);
  const Pca none;
  const ActionClassifier plain = sequenceClassifier(sets.train, seq, none, size),
                         reduced = sequenceClassifier(sets.train, seq, pca, size);
  const int n_train = static_cast<int>(sets.train.size());
  const int n_queries = static_cast<int>(sets.queries.size());
  std::printf("\n### Classification: %d training sequences of %d actions, %d queries, F = 30, %s "
              "(set up in %.1f s; PCA keeps %d of %d components at 99 %% variance)\n",
              n_train, sets.actions, n_queries, sets.source.c_str(), w.seconds(), pca.outputSize(),
              size);
  TimedClassifier timed_plain(plain, none), timed_reduced(reduced, pca);
  const std::size_t disagree = timeQueries(o.clock, sets.queries, seq, timed_plain, timed_reduced);
  printQueryTimes(timed_plain, timed_reduced, n_train, n_queries, disagree);
}
}  // namespace

// The people tracker's cost on full frames, and its first step side by side with PCL's: the detection
// voxels (0.06 m, every second row and column) from the reused VoxelFilter and from pcl::VoxelGrid.
struct TrackerTimes
{
  StageSamples update, voxels_ours, voxels_pcl;
  std::size_t people = 0;
};

void timeDetectionVoxels(Clock clock, const Cloud& full, TrackerTimes& times)
{
  static VoxelFilter filter;
  const TrackerParams defaults;
  pcl::Indices sampled;
  for (std::uint32_t r = 0; r < full.height; r += static_cast<std::uint32_t>(defaults.sampling_factor))
    for (std::uint32_t c = 0; c < full.width; c += static_cast<std::uint32_t>(defaults.sampling_factor))
      if (std::isfinite(full.at(c, r).z))
        sampled.push_back(static_cast<pcl::index_t>(r * full.width + c));
  Cloud ours, theirs;
  {
    Stopwatch w(clock);
    filter.filter(full, defaults.detection_voxel_size, &sampled, ours);
    times.voxels_ours.add(w.seconds());
  }
  {
    Stopwatch w(clock);
    pcl::VoxelGrid<PointT> grid;
    grid.setInputCloud(Cloud::ConstPtr(&full, [](const Cloud*) {}));
    grid.setIndices(pcl::make_shared<pcl::Indices>(sampled));
    grid.setLeafSize(defaults.detection_voxel_size, defaults.detection_voxel_size, defaults.detection_voxel_size);
    grid.filter(theirs);
    times.voxels_pcl.add(w.seconds());
  }
  if (ours.size() != theirs.size())
    throw std::runtime_error("the voxel filter and pcl::VoxelGrid disagree on a frame");
}

// Renders the frames once, cuts out the person (the renderer's mask), voxelises it at every size,
// and times the people tracker on the full frames on the way.
void collectFrames(const Options& o, std::map<float, std::vector<PersonSequence>>& by_voxel, TrackerTimes& tracker_times,
                   Cloud& last_frame)
{
  std::unique_ptr<PeopleTracker> tracker;
  if (o.tracker)
    tracker = std::make_unique<PeopleTracker>();
  auto addFrame = [&](const Cloud& full, const std::vector<std::uint8_t>& mask, double stamp, bool first,
                      const Eigen::Vector4f& ground) {
    last_frame = full;
    Cloud person;
    for (std::size_t k = 0; k < full.size(); ++k)
      if (mask[k] && std::isfinite(full.points[k].z))
        person.push_back(full.points[k]);
    for (float v : o.voxels)
    {
      auto& seqs = by_voxel[v];
      if (first)
        seqs.push_back(PersonSequence{ {}, {}, ground });
      seqs.back().clouds.push_back(voxelFiltered(person, v));
      seqs.back().stamps.push_back(stamp);
    }
    if (tracker)
    {
      Stopwatch w(o.clock);
      const TrackerResult r = tracker->update(full, stamp);
      tracker_times.update.add(w.seconds());
      tracker_times.people += r.people.size();
      timeDetectionVoxels(o.clock, full, tracker_times);
    }
  };
  int pairs = 0;
  Cloud full;
  std::vector<std::uint8_t> mask;
  Stopwatch w(o.clock);
  for (int p = 1; pairs < o.pairs; ++p)
  {
    synth::SampleSpec spec;
    char id[16];
    std::snprintf(id, sizeof id, "p%02d", p);
    spec.person = id;
    spec.action = "wave";
    const synth::SampleRenderer sample(spec);
    const Eigen::Isometry3f pose = sample.camera().worldFromOptical();
    // The floor (world z = 0) in the optical frame: normal = world up seen from the camera.
    const Eigen::Vector3f up = pose.linear().row(2).transpose();
    const Eigen::Vector4f ground(up.x(), up.y(), up.z(), pose.translation().z());
    const int frames = std::min(sample.frames(), o.pairs - pairs + 1);
    for (int i = 0; i < frames; ++i)
    {
      sample.render(i, full, &mask);
      addFrame(full, mask, sample.stamp(i), i == 0, ground);
    }
    pairs += frames - 1;
    std::printf("  rendered %s_wave_1: %d frames (%d pairs so far, %.0f s)\n", id, frames, pairs, w.seconds());
    std::fflush(stdout);
  }
}

// Depth image to organized XYZRGB cloud, 640x480: the live pipeline's path (depth_image_proc's
// conversion into a PointCloud2 with rgb, as its point_cloud_xyzrgb nodelet does, then the
// tracker's header check and copy into a pcl cloud) against the tools' depthToCloud (16-bit
// millimetres to metres, then straight into the pcl cloud) on the same frame.
void benchDepthConversion(const Options& o, const Cloud& frame)
{
  const int w = static_cast<int>(frame.width), h = static_cast<int>(frame.height);
  if (w * h == 0 || frame.height < 2)
    return;
  auto depth = boost::make_shared<sensor_msgs::Image>();
  depth->width = frame.width, depth->height = frame.height;
  depth->encoding = "16UC1";
  depth->step = 2 * frame.width;
  depth->data.resize(depth->step * frame.height);
  std::vector<std::uint8_t> rgb(3 * frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i)
  {
    const float z = frame.points[i].z;
    const std::uint16_t mm = std::isfinite(z) ? static_cast<std::uint16_t>(z * 1000.0f + 0.5f) : 0;
    std::memcpy(&depth->data[2 * i], &mm, 2);
    rgb[3 * i] = frame.points[i].r, rgb[3 * i + 1] = frame.points[i].g, rgb[3 * i + 2] = frame.points[i].b;
  }
  sensor_msgs::CameraInfo info;
  info.width = frame.width, info.height = frame.height;
  info.K = { 525.0, 0, 319.5, 0, 525.0, 239.5, 0, 0, 1 };
  info.P = { 525.0, 0, 319.5, 0, 0, 525.0, 239.5, 0, 0, 0, 1, 0 };
  info.R = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  image_geometry::PinholeCameraModel model;
  model.fromCameraInfo(info);

  StageSamples dip, ours;
  std::vector<float> metres(frame.size());
  for (int rep = 0; rep < 200; ++rep)
  {
    {
      Stopwatch t(o.clock);
      auto cloud = boost::make_shared<sensor_msgs::PointCloud2>();
      cloud->header = depth->header;
      cloud->width = frame.width, cloud->height = frame.height;
      cloud->is_dense = false;
      sensor_msgs::PointCloud2Modifier mod(*cloud);
      mod.setPointCloud2Fields(4, "x", 1, sensor_msgs::PointField::FLOAT32, "y", 1, sensor_msgs::PointField::FLOAT32,
                               "z", 1, sensor_msgs::PointField::FLOAT32, "rgb", 1, sensor_msgs::PointField::FLOAT32);
      depth_image_proc::convert<std::uint16_t>(depth, cloud, model);
      sensor_msgs::PointCloud2Iterator<std::uint8_t> r(*cloud, "r"), g(*cloud, "g"), b(*cloud, "b");
      for (std::size_t i = 0; i < frame.size(); ++i, ++r, ++g, ++b)
        *r = rgb[3 * i], *g = rgb[3 * i + 1], *b = rgb[3 * i + 2];
      InputCloud in;
      InputCloud::fromWire(*cloud, in);
      dip.add(t.seconds());
      if (!in.cloud || in.cloud->size() != frame.size())
        throw std::runtime_error("depth_image_proc's cloud did not pass the tracker's check: " + in.error);
    }
    {
      Stopwatch t(o.clock);
      for (std::size_t i = 0; i < frame.size(); ++i)
      {
        std::uint16_t mm;
        std::memcpy(&mm, &depth->data[2 * i], 2);
        metres[i] = mm * 0.001f;
      }
      Cloud out;
      Intrinsics k;
      depthToCloud(metres.data(), rgb.data(), w, h, k, out);
      ours.add(t.seconds());
    }
  }
  header("### Depth image to cloud, 640x480 (ours = depthToCloud; base = depth_image_proc + the tracker's check and copy)");
  row("depth image to cloud", ours, &dip);
}

int main(int argc, char** argv)
{
  const Options o = parse(argc, argv);
  try
  {
    std::map<float, std::vector<PersonSequence>> by_voxel;
    TrackerTimes tracker_times;
    Cloud last_frame;
    collectFrames(o, by_voxel, tracker_times, last_frame);
    for (float voxel : o.voxels)
      benchFlow(o, voxel, by_voxel[voxel]);
    benchDepthConversion(o, last_frame);
    if (!tracker_times.update.empty())
    {
      header("### People tracker on full 640x480 clouds (PeopleTracker::update; base = pcl::VoxelGrid)");
      row("tracker update", tracker_times.update, nullptr);
      row("detection voxels", tracker_times.voxels_ours, &tracker_times.voxels_pcl);
      std::printf("\n%zu frames, %.2f tracked people per frame on average\n", tracker_times.update.size(),
                  tracker_times.people / static_cast<double>(tracker_times.update.size()));
    }
    if (o.classification)
    {
      benchClassification(o);
      for (bool fourier : { true, false })
        benchPostureFlowClassification(o, fourier);
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
