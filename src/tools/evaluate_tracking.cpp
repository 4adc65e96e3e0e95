// evaluate_tracking: the people tracker on crowd scenes of the virtual Kinect, scored as the MOT
// benchmarks score trackers (MOTA, IDF1, id switches; tracking_metrics.h). See docs/evaluation.md,
// "Several people: tracking".
#include "../offline/cli.h"
#include "../offline/crowd_protocol.h"
#include "../offline/plot_script.h"
#include "../offline/extraction.h"

#include <action_flow/files.h>
#include <action_flow/people_tracker.h>
#include <action_flow/synth/crowd.h>
#include "../eval/tracking_metrics.h"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <thread>

using namespace action_flow;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace
{
const char* kUsage = R"(usage: evaluate_tracking [options]
Renders crowd scenes of the virtual Kinect (synth --dataset crowd: 2-5 people entering, leaving,
crossing, facing any way), runs the people tracker with its default parameters on every frame's
cloud, and scores it as the MOT benchmarks do: per frame, tracks are matched to the people who
count (head seen, at least 0.12 m^2 of them with depth) by ground-plane distance within the gate.

)";

/** Counts how often two people who count swap their left-right order in the image (a crossing). */
class CrossingCounter
{
public:
  void add(const std::vector<synth::CrowdTruth>& truth)
  {
    for (const auto& a : truth)
      for (const auto& b : truth)
        if (a.mask_id < b.mask_id && a.counted && b.counted)
        {
          const float bearing = std::atan2(a.position.y(), a.position.x()) - std::atan2(b.position.y(), b.position.x());
          int& last = side_[{ a.mask_id, b.mask_id }];
          const int side = bearing > 0 ? 1 : -1;
          crossings_ += last != 0 && last != side ? 1 : 0;
          last = side;
        }
  }
  int crossings() const { return crossings_; }

private:
  std::map<std::pair<int, int>, int> side_;
  int crossings_ = 0;
};

struct SceneResult
{
  synth::SampleSpec spec;
  TrackingScores scores;
  int frames = 0, crossings = 0;
  float clearance = 0.0f;
  double seconds = 0.0;
  std::string csv;
};

SceneResult runScene(const synth::SampleSpec& spec, float gate, const TrackerParams& params)
{
  const auto start = std::chrono::steady_clock::now();
  const synth::CrowdRenderer crowd(spec);
  PeopleTracker tracker(params);  // the default parameters unless --config, as train, evaluate and the nodelet
  const Eigen::Isometry3f world_from_optical = crowd.camera().worldFromOptical();
  std::vector<TrackingFrame> frames(size_t(crowd.frames()));
  SceneResult out;
  out.spec = spec;
  out.csv = "frame,stamp,kind,id,x,y,counted\n";
  CrossingCounter crossings;
  synth::FrameImages im;
  Cloud cloud;
  char row[128];
  for (int i = 0; i < crowd.frames(); ++i)
  {
    crowd.renderImages(i, im);
    crowd.scene().toCloud(im, cloud);
    cloud.header.stamp = std::uint64_t(std::llround(crowd.stamp(i) * 1e6));
    const std::vector<synth::CrowdTruth> truth = crowd.truth(i, im);
    crossings.add(truth);
    for (const auto& t : truth)
    {
      TrackPoint p;
      p.id = t.mask_id;
      p.position = t.position.head<2>();
      p.ignored = !t.counted;
      frames[size_t(i)].truth.push_back(p);
      std::snprintf(row, sizeof row, "%d,%.4f,truth,%d,%.4f,%.4f,%d\n", i, crowd.stamp(i) - crowd.stamp(0), int(t.mask_id),
                    t.position.x(), t.position.y(), int(t.counted));
      out.csv += row;
    }
    for (const TrackedPerson& person : tracker.update(cloud, crowd.stamp(i)).people)
    {
      TrackPoint p;
      p.id = person.id;
      p.position = (world_from_optical * person.position).head<2>();
      frames[size_t(i)].predicted.push_back(p);
      std::snprintf(row, sizeof row, "%d,%.4f,track,%u,%.4f,%.4f,1\n", i, crowd.stamp(i) - crowd.stamp(0), person.id,
                    p.position.x(), p.position.y());
      out.csv += row;
    }
  }
  out.scores = scoreTracking(frames, gate, 1.0 / crowd.camera().fps);
  out.frames = crowd.frames();
  out.crossings = crossings.crossings();
  out.clearance = crowd.leastClearance();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

json toJson(const TrackingScores& s)
{
  return { { "frames", s.frames },
           { "truth", s.truth },
           { "matches", s.matches },
           { "misses", s.misses },
           { "false_positives", s.false_positives },
           { "id_switches", s.id_switches },
           { "fragmentations", s.fragmentations },
           { "mota", s.mota() },
           { "motp_m", s.motp() },
           { "precision", s.precision() },
           { "recall", s.recall() },
           { "idf1", s.idf1() },
           { "idp", s.idp() },
           { "idr", s.idr() },
           { "idtp", s.idtp },
           { "idfp", s.idfp },
           { "idfn", s.idfn },
           { "truth_ids", s.truth_ids },
           { "predicted_ids", s.predicted_ids },
           { "mostly_tracked", s.mostly_tracked },
           { "mostly_lost", s.mostly_lost },
           { "person_minutes", s.person_seconds / 60.0 },
           { "id_switches_per_person_minute", s.switchesPerPersonMinute() } };
}

/** Runs the scenes on @p jobs threads, printing a line per scene done. */
std::vector<SceneResult> runAll(const std::vector<synth::SampleSpec>& specs, float gate, const TrackerParams& params,
                                int jobs)
{
  std::vector<SceneResult> results(specs.size());
  std::atomic<size_t> next{ 0 };
  std::mutex lock;
  std::string error;
  size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  const auto worker = [&]() {
    for (size_t k = next++; k < specs.size(); k = next++)
    {
      try
      {
        results[k] = runScene(specs[k], gate, params);
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> g(lock);
        error = specs[k].name() + ": " + e.what();
        next = specs.size();
        return;
      }
      std::lock_guard<std::mutex> g(lock);
      const TrackingScores& s = results[k].scores;
      std::fprintf(stderr, "  %s (%s): %d frames, MOTA %.3f, IDF1 %.3f, %zu id switches, %d crossings  [%zu/%zu, %.0f s]\n",
                   specs[k].name().c_str(), specs[k].person.c_str(), results[k].frames, s.mota(), s.idf1(),
                   s.id_switches, results[k].crossings, ++done, specs.size(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
  };
  tools::runWorkers(jobs, worker);
  if (!error.empty())
    throw std::runtime_error(error);
  return results;
}

/** Writes report.json and the tracks' CSVs into @p out; prints the figures per people count. */
void writeReport(const std::vector<SceneResult>& results, const std::string& out, float gate, double seconds,
                 std::uint64_t seed, const std::string& config)
{
  fs::create_directories(fs::path(out) / "tracks");
  json report = { { "protocol", "tracking" },
                  { "match", "per frame, track to person by ground-plane distance (world x-y of the tracker's centroid "
                             "and of the mean of the person's 15 joints), gate inclusive; previous matches kept "
                             "within the gate, the rest by the Hungarian method (CLEAR MOT); IDF1 by the best "
                             "one-to-one pairing of whole trajectories" },
                  { "counted", "a person counts where their head is seen and at least 0.12 m^2 of them return depth; "
                               "tracks on people who do not count are neither matches nor false positives" },
                  { "tracker", config.empty() ? "PeopleTracker with its default parameters (TrackerParams())"
                                              : "PeopleTracker with the parameters of " + config },
                  { "gate_m", gate }, { "seconds", seconds }, { "seed", seed } };
  std::map<int, TrackingScores> by_people;
  TrackingScores total;
  for (const SceneResult& r : results)
  {
    report["scenes"].push_back({ { "scene", r.spec.name() }, { "actors", r.spec.person }, { "people", r.spec.crowd_people },
                                 { "crossings", r.crossings }, { "least_clearance_m", r.clearance },
                                 { "wall_seconds", r.seconds }, { "scores", toJson(r.scores) } });
    by_people[r.spec.crowd_people] = addTrackingScores(by_people[r.spec.crowd_people], r.scores);
    total = addTrackingScores(total, r.scores);
    writeTextAtomically((fs::path(out) / "tracks" / (r.spec.name() + ".csv")).string(), r.csv);
  }
  for (const auto& [n, s] : by_people)
    report["by_people"][std::to_string(n)] = toJson(s);
  report["total"] = toJson(total);
  writeTextAtomically((fs::path(out) / "report.json").string(), report.dump(2) + "\n");
  for (const auto& [n, s] : by_people)
    std::printf("%d people: MOTA %.3f  IDF1 %.3f  id switches %zu (%.2f per person-minute)  precision %.3f  recall %.3f  MOTP %.3f m\n",
                n, s.mota(), s.idf1(), s.id_switches, s.switchesPerPersonMinute(), s.precision(), s.recall(), s.motp());
  std::printf("report: %s/report.json\n", out.c_str());
}

int run(int argc, char** argv)
{
  tools::Options o(kUsage);
  o.value("people", "LIST", "people per scene, e.g. 3 or 2,3,4,5 (default 3)")
      .value("scenes", "S", "scenes per people count (default 3), numbered 1..S")
      .value("seconds", "T", "length of a scene (default 60)")
      .value("seed", "N", "dataset seed (default 1)")
      .value("frames", "N", "at most N frames per scene")
      .value("gate", "M", "largest ground-plane distance of a match in metres (default 0.5)")
      .value("jobs", "N", "scenes in parallel (default 2)")
      .value("out", "DIR", "report.json, tracks/<scene>.csv and, unless --no-plot, tracks/<scene>.png "
                           "(default tracking_results)")
      .flag("no-plot", "no pictures (scripts/plot_tracks.py)")
      .value("config", "FILE[,FILE...]", "the tracker's parameters from yaml files as the nodelets load them "
                                         "(e.g. config/tracker.yaml; default: the declared defaults)");
  const tools::Args args(argc, argv, o);
  if (args.has("help"))
    return o.printHelp();
  const std::vector<int> people = tools::crowdPeopleList(args.get("people", "3"), "--people");
  const int scenes = int(args.integer("scenes", 3, 1, 999));
  const double seconds = double(args.integer("seconds", 60, 2, 3600));
  const std::uint64_t seed = std::uint64_t(args.integer("seed", 1, 0, 2147483647));
  const int max_frames = int(args.integer("frames", 0, 0, 10000000));
  const float gate = float(args.number("gate", 0.5));
  if (!(gate > 0.0f && gate <= 5.0f))
    throw tools::UsageError("--gate must be in (0, 5] metres");
  const std::string out = args.get("out", "tracking_results");
  const TrackerParams params = tools::configParams(args).tracker;
  PeopleTracker check(params);  // bad parameters: one line before any rendering
  std::vector<synth::SampleSpec> specs;
  for (int n : people)
    for (synth::SampleSpec s : synth::crowdSamples(n, scenes, seconds, seed))
    {
      s.max_frames = max_frames;
      specs.push_back(s);
    }
  std::fprintf(stderr, "evaluate_tracking: %zu scenes, gate %.2f m on the ground plane\n", specs.size(), gate);
  const std::vector<SceneResult> results = runAll(specs, gate, params, tools::jobsOption(args));

  writeReport(results, out, gate, seconds, seed, args.get("config"));
  if (!args.has("no-plot"))
  {
    try
    {
      tools::runPlotScript("plot_tracks.py", { out });
    }
    catch (const std::runtime_error& e)
    {
      std::fprintf(stderr, "evaluate_tracking: the pictures could not be drawn (%s)\n", e.what());
    }
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv)
{
  return tools::runTool("evaluate_tracking", [&]() { return run(argc, argv); });
}
