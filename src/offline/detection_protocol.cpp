// evaluate --protocol detection (see detection_protocol.h and docs/evaluation.md).
#include "detection_protocol.h"

#include "cli.h"
#include "extraction.h"
#include "plot_script.h"

#include <action_flow/files.h>
#include <action_flow/synth/clutter.h>
#include "../tracker/tracker_detector.h"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <thread>

namespace action_flow
{
namespace tools
{
namespace
{
using json = nlohmann::json;
using synth::Joint;

constexpr int kWarmUpFrames = 1;  // the tracker reports a track from its second detection
constexpr float kRequiredShare = 0.35f;
constexpr int kRequiredJoints = 8, kRequiredPixels = 400;

struct FrameTruth
{
  std::vector<TruthPerson> people;
  float visible_share = 0;  // of the body rendered alone
  int joints_inside = 0;
  Eigen::Vector3f torso = Eigen::Vector3f::Zero();
  float top = 0;  // highest joint + 0.1 m (the head's top), world z
  Eigen::Vector4i box = Eigen::Vector4i(-1, -1, -1, -1);  // the person's mask in the image
};

int maskPixels(const synth::FrameImages& im, Eigen::Vector4i* box)
{
  int n = 0;
  Eigen::Vector4i b(im.width, im.height, -1, -1);
  for (int v = 0; v < im.height; ++v)
    for (int u = 0; u < im.width; ++u)
      if (im.mask[static_cast<std::size_t>(v) * im.width + u])
      {
        ++n;
        b = Eigen::Vector4i(std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v));
      }
  if (box)
    *box = b;
  return n;
}

FrameTruth truthOf(const synth::SampleRenderer& sample, const synth::SceneRenderer& alone, int i,
                   const synth::FrameImages& im)
{
  FrameTruth t;
  if (sample.bodies() == 0)
    return t;
  const synth::Skeleton& s = sample.worldSkeleton(i);
  t.torso = s[Joint::Torso];
  for (const auto& j : s.joints)
    t.top = std::max(t.top, j.z() + 0.1f);
  synth::FrameImages body;
  alone.render({ sample.posedBody(i, 1) }, 1, i, body);
  const int seen = maskPixels(im, &t.box), full = maskPixels(body, nullptr);
  t.visible_share = full > 0 ? static_cast<float>(seen) / full : 0.0f;
  const synth::JointsInView view = synth::jointsInView(sample.camera(), s);
  t.joints_inside = view.inside;
  TruthPerson p;
  p.position = t.torso.head<2>();
  p.required = view.head_inside && view.inside >= kRequiredJoints && t.visible_share >= kRequiredShare &&
               seen >= kRequiredPixels;
  t.people.push_back(p);
  return t;
}

// What most of a detection's points lie on.
std::string falseOn(const synth::ClutterLayout& layout, int frame, const Cloud& points, const Eigen::Isometry3f& world)
{
  std::map<std::string, int> votes;
  const std::size_t step = std::max<std::size_t>(1, points.size() / 200);
  for (std::size_t k = 0; k < points.size(); k += step)
    ++votes[synth::objectAt(layout, frame, world * points[k].getVector3fMap())];
  std::string best = "other";
  int most = 0;
  for (const auto& [what, n] : votes)
    if (n > most)
    {
      best = what;
      most = n;
    }
  return best;
}

// Why a required person was not found, the first that applies.
std::string missCause(const synth::ClutterLayout& layout, const FrameTruth& t, const std::vector<Eigen::Vector2f>& found,
                      const TrackerParams& params, float gate)
{
  for (const auto& d : found)
    if ((d - t.torso.head<2>()).norm() < 2 * gate)
      return "displaced";  // a detection near them, beyond the gate
  if (t.top < params.min_height)
    return "not_upright";
  if (t.joints_inside < synth::kJointCount)
    return "cut_by_border";
  if (t.visible_share < 0.7f)
    return "occluded";
  if (synth::distanceToWall(layout.room, t.torso) < 0.6f)
    return "near_wall";
  for (const auto& o : layout.objects)
    for (const auto& b : o.boxes)
      if ((b.center.head<2>() - t.torso.head<2>()).norm() - b.half.head<2>().norm() < 0.6f)
        return "near_" + o.kind;
  return "other";
}

Eigen::Vector4i cloudBox(const Cloud& c, const synth::CameraModel& cam)
{
  Eigen::Vector4i b(cam.width, cam.height, -1, -1);
  for (const auto& p : c.points)
  {
    const int u = static_cast<int>(std::lround(cam.fx * p.x / p.z + cam.cx));
    const int v = static_cast<int>(std::lround(cam.fy * p.y / p.z + cam.cy));
    b = Eigen::Vector4i(std::min(b[0], u), std::min(b[1], v), std::max(b[2], u), std::max(b[3], v));
  }
  return b;
}

json boxJson(const Eigen::Vector4i& b, const std::string& what, const std::string& on = "")
{
  json j = { { "box", { b[0], b[1], b[2], b[3] } }, { "what", what } };
  if (!on.empty())
    j["on"] = on;
  return j;
}

double pitchUpDegrees(const synth::CameraModel& c) { return -c.tilt * 180.0 / M_PI; }

double floorShare(const synth::FrameImages& im, const synth::CameraModel& cam)
{
  const Eigen::Isometry3f w = cam.worldFromOptical();
  long floor = 0;
  for (int v = 0; v < im.height; ++v)
    for (int u = 0; u < im.width; ++u)
    {
      const float z = im.depth[static_cast<std::size_t>(v) * im.width + u];
      if (!std::isfinite(z))
        continue;
      const Eigen::Vector3f p(static_cast<float>((u - cam.cx) / cam.fx) * z, static_cast<float>((v - cam.cy) / cam.fy) * z, z);
      floor += (w * p).z() < 0.04f;
    }
  return static_cast<double>(floor) / (static_cast<double>(im.width) * im.height);
}

// One frame's outcome added to the scene's; the frame's boxes (JSON) returned.
json scoreOne(const synth::ClutterLayout& layout, int i, const TrackerResult& r, const FrameTruth& truth,
              const synth::SampleRenderer& sample, const TrackerParams& params, float gate, SceneOutcome& out)
{
  const Eigen::Isometry3f world = sample.camera().worldFromOptical();
  std::vector<Eigen::Vector2f> found;
  for (const auto& p : r.people)
    found.push_back((world * p.position).head<2>());
  const FrameScore s = scoreFrame(found, truth.people, gate);
  out.counts += s.counts;
  out.not_required += !truth.people.empty() && !truth.people[0].required;
  json boxes = json::array();
  for (std::size_t d = 0; d < r.people.size(); ++d)
  {
    const int t = s.truth_of_detection[d];
    std::string on;
    if (t < 0)
      ++out.false_on[on = falseOn(layout, i, *r.people[d].cloud, world)];
    boxes.push_back(boxJson(cloudBox(*r.people[d].cloud, sample.camera()),
                            t < 0 ? "fp" : (truth.people[t].required ? "tp" : "ignored"), on));
  }
  if (!s.missed.empty())  // one person per scene
    ++out.miss_causes[missCause(layout, truth, found, params, gate)];
  if (!truth.people.empty())
    boxes.push_back(boxJson(truth.box, s.missed.empty() ? "truth" : "missed"));
  return boxes;
}
}  // namespace

SceneOutcome runDetectionScene(const synth::SampleSpec& spec, const TrackerParams& params, float gate)
{
  const synth::SampleRenderer sample(spec);
  const synth::ClutterLayout layout = synth::clutterLayout(spec);  // the same scene: where things stand
  synth::Room bare;  // the body alone, to know how much of it the room hides
  bare.floor = bare.walls = false;
  synth::CameraModel exact = sample.camera();
  exact.noise = false;
  const synth::SceneRenderer alone(exact, bare);
  PeopleTracker tracker(params);
  SceneOutcome out;
  out.name = spec.name();
  out.kind = spec.scene;
  out.action = spec.action;
  out.camera_height = sample.camera().height_above_floor;
  out.pitch_up_deg = pitchUpDegrees(sample.camera());
  synth::FrameImages im;
  Cloud cloud;
  for (int i = 0; i < sample.frames(); ++i)
  {
    sample.renderImages(i, im);
    sample.scene().toCloud(im, cloud);
    const TrackerResult r = tracker.update(cloud, sample.stamp(i));
    if (i == 0)
      out.floor_share = floorShare(im, sample.camera());
    if (i < kWarmUpFrames)
      continue;
    const long errors = out.counts.false_positives + out.counts.misses;
    const json boxes = scoreOne(layout, i, r, truthOf(sample, alone, i, im), sample, params, gate, out);
    const bool error = out.counts.false_positives + out.counts.misses > errors;
    if ((error && !out.example_has_error) || (!out.example_has_error && i == sample.frames() / 2))
    {
      out.example_frame = i;
      out.example_has_error = error;
      out.example_rgb = im.rgb;
      out.example_boxes = boxes.dump();
    }
  }
  return out;
}

namespace
{
json countsJson(const DetectionCounts& c)
{
  return { { "precision", c.precision() }, { "recall", c.recall() },  { "true_positives", c.true_positives },
           { "false_positives", c.false_positives }, { "misses", c.misses }, { "ignored", c.ignored },
           { "frames", c.frames }, { "false_per_frame", c.frames ? double(c.false_positives) / c.frames : 0.0 } };
}

json tallyJson(const DetectionTally& t)
{
  json j = json::object();
  for (const auto& [k, c] : t)
    j[k] = countsJson(c);
  return j;
}

std::vector<SceneOutcome> runAll(const std::vector<synth::SampleSpec>& specs, const TrackerParams& params, float gate,
                                 int jobs)
{
  std::vector<SceneOutcome> out(specs.size());
  std::atomic<std::size_t> next{ 0 }, done{ 0 };
  std::mutex lock;
  std::string error;
  const auto start = std::chrono::steady_clock::now();
  const auto worker = [&]() {
    for (std::size_t k; (k = next++) < specs.size();)
    {
      try
      {
        out[k] = runDetectionScene(specs[k], params, gate);
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> g(lock);
        error = specs[k].name() + ": " + e.what();
        next = specs.size();
      }
      std::lock_guard<std::mutex> g(lock);
      const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const std::size_t n = ++done;
      std::fprintf(stderr, "  detection: %zu/%zu scenes (%s: P %.3f R %.3f)  %.0f s elapsed, about %.0f s left\n", n,
                   specs.size(), specs[k].name().c_str(), out[k].counts.precision(), out[k].counts.recall(), secs,
                   secs / n * (specs.size() - n));
    }
  };
  runWorkers(jobs, worker);
  if (!error.empty())
    throw std::runtime_error(error);
  return out;
}

// The example frames: per kind the first scene whose example shows an error, else its first scene;
// with @p every, each scene's (the first frame with an error, else its middle one).
json writeExamples(const std::vector<SceneOutcome>& scenes, const std::string& dir, bool every)
{
  std::vector<const SceneOutcome*> picks;
  if (every)
    for (const auto& s : scenes)
      picks.push_back(s.example_frame >= 0 ? &s : nullptr);
  for (const std::string& kind : every ? std::vector<std::string>() : synth::clutterKinds())
  {
    const SceneOutcome* pick = nullptr;
    for (const auto& s : scenes)
      if (s.kind == kind && s.example_frame >= 0 && (!pick || (s.example_has_error && !pick->example_has_error)))
        pick = &s;
    picks.push_back(pick);
  }
  json out = json::array();
  for (const SceneOutcome* pick : picks)
  {
    if (!pick)
      continue;
    const std::string& kind = pick->kind;
    const synth::CameraModel cam;
    cv::Mat rgb(cam.height, cam.width, CV_8UC3, const_cast<std::uint8_t*>(pick->example_rgb.data())), bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    const std::string file = "example_" + pick->name + ".png";
    if (!cv::imwrite(dir + "/" + file, bgr))
      throw std::runtime_error(dir + "/" + file + ": cannot write");
    out.push_back({ { "scene", pick->name }, { "kind", kind }, { "frame", pick->example_frame }, { "image", file },
                    { "boxes", json::parse(pick->example_boxes) } });
  }
  return out;
}

// The clutter scenes to run: @p per_kind of each kind for @p seed, or only those --scene names.
std::vector<synth::SampleSpec> chosenScenes(const Args& args, int per_kind, std::uint64_t seed)
{
  std::vector<synth::SampleSpec> specs = synth::clutterSamples(per_kind, seed);
  if (!args.has("scene"))
    return specs;
  const std::string wanted = "," + args.get("scene") + ",";
  std::vector<synth::SampleSpec> picked;
  for (const auto& s : specs)
    if (wanted.find("," + s.name() + ",") != std::string::npos)
      picked.push_back(s);
  if (picked.empty())
    throw UsageError("--scene: no scene " + args.get("scene") + " among the " + std::to_string(specs.size()) +
                     " of --scenes " + std::to_string(per_kind));
  return picked;
}

// The scenes' counts: overall, binned (kind, camera height, pitch, action, visible floor), and per scene.
struct DetectionSummary
{
  DetectionCounts all;
  DetectionTally by_kind, by_height, by_pitch, by_action, by_floor;
  std::map<std::string, long> false_on, miss_causes;
  json per_scene = json::array();

  void add(const SceneOutcome& s)
  {
    all += s.counts;
    by_kind[s.kind] += s.counts;
    by_height[binLabel(s.camera_height, { 0.5, 0.9, 1.3, 1.8001 }, "%.1f")] += s.counts;
    by_pitch[binLabel(s.pitch_up_deg, { -20.0001, -10, 0, 10.0001 }, "%+.0f")] += s.counts;
    if (s.kind != "furniture")
      by_action[s.action] += s.counts;
    by_floor[binLabel(100 * s.floor_share, { 0, 10, 25, 100.001 }, "%.0f%%")] += s.counts;
    for (const auto& [k, n] : s.false_on)
      false_on[k] += n;
    for (const auto& [k, n] : s.miss_causes)
      miss_causes[k] += n;
    json j = countsJson(s.counts);
    j.update({ { "scene", s.name }, { "kind", s.kind }, { "action", s.action }, { "camera_height", s.camera_height },
               { "pitch_up_deg", s.pitch_up_deg }, { "floor_share", s.floor_share }, { "false_on", s.false_on },
               { "miss_causes", s.miss_causes }, { "not_required_frames", s.not_required } });
    per_scene.push_back(j);
  }
};
}  // namespace

void addDetectionOptions(Options& o)
{
  o.group("detection protocol (--protocol detection: the people tracker, default parameters, on cluttered rooms)")
      .value("scenes", "N", "scenes of each kind (default 10; synth --dataset clutter); crowd: scenes per people "
                            "count (default 4)")
      .value("gate", "M", "a detection within M metres of a person on the floor finds them (default 0.5; crowd: "
                          "a track is theirs)")
      .value("remove-walls", "0|1", "change this person-likeness cue from its default (to measure it)")
      .value("max-head-ratio", "R", "likewise")
      .value("min-free-fraction", "F", "likewise")
      .value("scene", "NAME[,NAME...]", "only these scenes (e.g. wall_03; to look at one closely)")
      .flag("every-example", "write every scene's example frame (the first with an error), not one per kind");
}

int runDetectionProtocol(const Args& args, const std::string& dir)
{
  const int per_kind = static_cast<int>(args.integer("scenes", 10, 1, 999));
  const float gate = static_cast<float>(args.number("gate", 0.5));
  if (!(gate > 0.0f && gate < 5.0f))
    throw UsageError("--gate must be in (0, 5) m");
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 2147483647));
  const int jobs = jobsOption(args);
  TrackerParams params;  // the defaults, as the pipeline runs them on rendered data, unless a cue is changed
  params.remove_walls = args.integer("remove-walls", params.remove_walls, 0, 1) != 0;
  params.max_head_ratio = static_cast<float>(args.number("max-head-ratio", params.max_head_ratio));
  params.min_free_fraction = static_cast<float>(args.number("min-free-fraction", params.min_free_fraction));
  validateTrackerParams(params);
  const bool defaults = params.remove_walls == TrackerParams().remove_walls &&
                        params.max_head_ratio == TrackerParams().max_head_ratio &&
                        params.min_free_fraction == TrackerParams().min_free_fraction;
  const std::vector<synth::SampleSpec> specs = chosenScenes(args, per_kind, seed);
  makeOutputDir(dir);
  std::fprintf(stderr, "evaluate: detection on %zu clutter scenes (%d of each kind), gate %.2f m\n", specs.size(),
               per_kind, gate);
  const std::vector<SceneOutcome> scenes = runAll(specs, params, gate, jobs);

  DetectionSummary sum;
  for (const auto& s : scenes)
    sum.add(s);
  const DetectionCounts& all = sum.all;
  json report = { { "protocol", "detection" },
                  { "gate", gate },
                  { "seed", seed },
                  { "scenes_per_kind", per_kind },
                  { "tracker", defaults ? "PeopleTracker, default TrackerParams (no HOG)" : "PeopleTracker, changed cues" },
                  { "remove_walls", params.remove_walls },
                  { "max_head_ratio", params.max_head_ratio },
                  { "min_free_fraction", params.min_free_fraction },
                  { "overall", countsJson(all) },
                  { "by_kind", tallyJson(sum.by_kind) },
                  { "by_camera_height", tallyJson(sum.by_height) },
                  { "by_pitch_up_deg", tallyJson(sum.by_pitch) },
                  { "by_action", tallyJson(sum.by_action) },
                  { "by_floor_visible", tallyJson(sum.by_floor) },
                  { "false_positives_on", sum.false_on },
                  { "misses_by_cause", sum.miss_causes },
                  { "examples", writeExamples(scenes, dir, args.has("every-example")) },
                  { "scenes", sum.per_scene } };
  writeTextAtomically(dir + "/detection.json", report.dump(2) + "\n");
  std::printf("detection, %s, %zu scenes, %ld frames: precision %.3f, recall %.3f (%ld true, %ld false, "
              "%ld missed)\n",
              defaults ? "default parameters" : "changed cues", scenes.size(), all.frames, all.precision(), all.recall(), all.true_positives, all.false_positives,
              all.misses);
  for (const auto& [k, c] : sum.by_kind)
    std::printf("  %-10s precision %.3f recall %.3f  (%ld false, %ld missed, %ld frames)\n", k.c_str(), c.precision(),
                c.recall(), c.false_positives, c.misses, c.frames);
  std::printf("evaluate: report in %s/detection.json\n", dir.c_str());
  if (!args.has("no-plots"))
    runPlotScript("plot_detection.py", { dir + "/detection.json" });
  return 0;
}

}  // namespace tools
}  // namespace action_flow
