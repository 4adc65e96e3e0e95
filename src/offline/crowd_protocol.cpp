#include "crowd_protocol.h"

#include "cli.h"
#include "extraction.h"
#include "feature_extractor.h"
#include "plot_script.h"
#include "../eval/crowd_recognition.h"

#include <action_flow/files.h>
#include <action_flow/synth/crowd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>

namespace action_flow
{
namespace tools
{
namespace
{
using json = nlohmann::json;

/** A segment is scored when the person counts (crowd.h: head seen, enough of them with depth) in at
 *  least this share of its frames with nobody else in view: what the camera could show of them. */
constexpr double kShownShare = 0.5;
/** An action counts as in plain view with everyone there when its person counts in at least this
 *  share of its frames with the others in view too (not hidden behind them). */
constexpr double kVisibleShare = 0.9;
/** The label of a segment whose person no track followed. */
const char* const kUntracked = "untracked";

/** One run of the tracker and pipelines over a scene: everyone (only 0), or person `only` alone. */
struct Pass
{
  std::size_t scene = 0;
  std::uint8_t only = 0;
  std::vector<SampleFrames> rows;   // per extraction used: every track's descriptors
  TrackedScene tracked;
  std::vector<char> counted;        // only != 0: per frame, whether that person counts
  std::map<std::uint8_t, std::vector<char>> counted_of;  // only == 0: per person, per frame
  int tracks = 0;
};

/** Renders a crowd scene frame by frame (everyone, or one person alone) and keeps each frame's truth. */
class CrowdSource : public FrameSource
{
public:
  CrowdSource(const synth::CrowdRenderer& crowd, std::uint8_t only) : crowd_(crowd), only_(only) {}

  bool next(Cloud& cloud, double& stamp) override
  {
    if (i_ >= crowd_.frames())
      return false;
    crowd_.renderImages(i_, images_, only_);
    std::vector<synth::CrowdTruth> truth = crowd_.truth(i_, images_);
    if (only_ != 0)
      truth.erase(std::remove_if(truth.begin(), truth.end(), [&](const synth::CrowdTruth& t) { return t.mask_id != only_; }),
                  truth.end());
    truth_.push_back(std::move(truth));
    crowd_.scene().toCloud(images_, cloud);
    stamp = crowd_.stamp(i_);
    cloud.header.stamp = std::uint64_t(std::llround(stamp * 1e6));
    ++i_;
    return true;
  }
  const std::vector<std::vector<synth::CrowdTruth>>& truth() const { return truth_; }

private:
  const synth::CrowdRenderer& crowd_;
  std::uint8_t only_;
  int i_ = 0;
  synth::FrameImages images_;
  std::vector<std::vector<synth::CrowdTruth>> truth_;
};

void runPass(const synth::SampleSpec& spec, const std::vector<RecognitionParams>& extractions,
             const TrackerParams& tracker, float gate, Pass& pass)
{
  const synth::CrowdRenderer crowd(spec);
  const Eigen::Isometry3f world_from_optical = crowd.camera().worldFromOptical();
  CrowdSource source(crowd, pass.only);
  std::vector<TrackingFrame> frames;
  std::vector<double> stamps;
  std::set<std::uint32_t> ids;
  pass.rows = extractSample(source, tracker, extractions, true, [&](double stamp, const TrackerResult& result) {
    TrackingFrame f;
    for (const synth::CrowdTruth& t : source.truth().back())
    {
      TrackPoint p;
      p.id = t.mask_id;
      p.position = t.position.head<2>();
      p.ignored = !t.counted;
      f.truth.push_back(p);
    }
    for (const TrackedPerson& person : result.people)
    {
      TrackPoint p;
      p.id = person.id;
      p.position = (world_from_optical * person.position).head<2>();
      f.predicted.push_back(p);
      ids.insert(person.id);
    }
    frames.push_back(std::move(f));
    stamps.push_back(stamp);
  });
  pass.tracked = trackScene(frames, stamps, gate);
  pass.tracks = int(ids.size());
  for (const auto& truth : source.truth())
  {
    for (const synth::CrowdPerson& person : crowd.people())
    {
      bool counted = false;
      for (const auto& t : truth)
        counted = counted || (t.mask_id == person.mask_id && t.counted);
      if (pass.only == 0)
        pass.counted_of[person.mask_id].push_back(counted);
      else if (person.mask_id == pass.only)
        pass.counted.push_back(counted);
    }
  }
}

/** The scenes tested: per people count, the first --scenes whose actors are none of the training people. */
std::vector<synth::SampleSpec> testScenes(const Args& args, const std::set<std::string>& training_people)
{
  const std::vector<int> counts = crowdPeopleList(args.get("crowd-people", "3"), "--crowd-people");
  const int per_count = static_cast<int>(args.integer("scenes", 4, 1, 200));
  const double seconds = static_cast<double>(args.integer("crowd-seconds", 40, 2, 3600));
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1000000000));
  std::vector<synth::SampleSpec> out;
  for (int n : counts)
  {
    std::vector<int> chosen;
    for (int s = 1; s <= 999 && int(chosen.size()) < per_count; ++s)
    {
      bool unseen = true;
      for (const std::string& a : synth::crowdActors(n, s))
        unseen = unseen && !training_people.count(a);
      if (unseen)
        chosen.push_back(s);
    }
    if (int(chosen.size()) < per_count)
      throw UsageError("--scenes: too few crowd scenes of " + std::to_string(n) + " people without a training person");
    const std::vector<synth::SampleSpec> all = synth::crowdSamples(n, chosen.back(), seconds, seed);
    for (int s : chosen)
      out.push_back(all[std::size_t(s - 1)]);
  }
  return out;
}

/** Every pass of every scene (each scene: everyone, then each person alone), on --jobs threads. */
std::vector<Pass> runPasses(const std::vector<synth::SampleSpec>& scenes,
                            const std::vector<std::vector<synth::CrowdPerson>>& people,
                            const std::vector<RecognitionParams>& extractions, const TrackerParams& tracker,
                            float gate, int jobs)
{
  std::vector<Pass> passes;
  for (std::size_t s = 0; s < scenes.size(); ++s)
  {
    passes.push_back({});
    passes.back().scene = s;
    for (const synth::CrowdPerson& p : people[s])
    {
      passes.push_back({});
      passes.back().scene = s;
      passes.back().only = p.mask_id;
    }
  }
  std::atomic<std::size_t> next{ 0 };
  std::mutex lock;
  std::string error;
  std::size_t done = 0;
  ProgressLine progress(0.0);
  const auto worker = [&]() {
    for (std::size_t k = next++; k < passes.size(); k = next++)
    {
      Pass& pass = passes[k];
      const synth::SampleSpec& spec = scenes[pass.scene];
      try
      {
        runPass(spec, extractions, tracker, gate, pass);
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> g(lock);
        error = spec.name() + (pass.only ? " (person " + std::to_string(pass.only) + " alone)" : "") + ": " + e.what();
        next = passes.size();
        return;
      }
      std::lock_guard<std::mutex> g(lock);
      ++done;
      progress.show([&] {
        char line[256];
        std::snprintf(line, sizeof line, "  crowd pass %zu/%zu: %s, %s: %d tracks  [%.0f s]", done, passes.size(),
                      spec.name().c_str(),
                      pass.only ? ("person " + std::to_string(pass.only) + " alone").c_str() : "everyone",
                      pass.tracks, progress.seconds());
        return std::string(line);
      });
    }
  };
  runWorkers(jobs, worker);
  progress.end();
  if (!error.empty())
    throw std::runtime_error(error);
  return passes;
}

/** One scored action: who, what, and the label each way of seeing them gave. */
struct ScoredSegment
{
  std::size_t scene = 0;
  std::string actor;
  CrowdSegment segment;
  double shown_alone = 0.0, shown_together = 0.0;  // share of its frames in which the person counts
  std::string alone, together;                     // predicted label, or kUntracked
  std::uint32_t alone_track = 0, together_track = 0;
};

double share(const std::vector<char>& counted, int first, int last)
{
  int n = 0;
  for (int f = first; f <= last; ++f)
    n += counted[std::size_t(f)] ? 1 : 0;
  return double(n) / double(last - first + 1);
}

/** The label @p classifier gives the rows of @p pass showing @p segment (kUntracked without any). */
std::string recognise(const Pass& pass, std::size_t extraction, const CrowdSegment& segment, const ActionModel& model,
                      const SequenceClassifier& classifier, std::uint32_t& track)
{
  SampleFrames frames;
  track = segmentFrames(pass.rows[extraction], pass.tracked, segment, frames);
  if (track == 0 || frames.descriptors.rows() == 0)
    return kUntracked;
  return classifier.classify(sequenceOf({ "", segment.action, &frames }, model)).label;
}

struct Tally
{
  int segments = 0, alone = 0, together = 0;
  void add(const ScoredSegment& s)
  {
    ++segments;
    alone += s.alone == s.segment.action;
    together += s.together == s.segment.action;
  }
  json toJson() const
  {
    const auto acc = [&](int n) { return segments ? double(n) / segments : 0.0; };
    return { { "segments", segments }, { "alone", acc(alone) }, { "together", acc(together) },
             { "difference", acc(together) - acc(alone) } };
  }
};
/** What scoring one variant gathers: its tallies, confusion matrices and the actions it skipped. */
struct VariantScores
{
  Confusion alone, together;
  Tally all, visible;
  std::map<std::string, Tally> by_person, by_action;
  int not_shown = 0, not_trained = 0;

  explicit VariantScores(const std::vector<std::string>& labels) : alone(labels), together(labels) {}

  void add(const ScoredSegment& r, const std::string& who)
  {
    alone.add(r.segment.action, r.alone);
    together.add(r.segment.action, r.together);
    all.add(r);
    if (r.shown_together >= kVisibleShare)
      visible.add(r);
    by_person[who].add(r);
    by_action[r.segment.action].add(r);
  }

  /** @p v's report entry; writes its confusion matrices to @p dir and prints its two lines. */
  json report(const RecognizerVariant& v, const std::string& dir) const
  {
    json per_person = json::array(), per_action = json::object();
    for (const auto& [who, t] : by_person)
    {
      json j = t.toJson();
      j["person"] = who;
      per_person.push_back(j);
    }
    for (const auto& [a, t] : by_action)
      per_action[a] = t.toJson();
    int alone_untracked = 0, together_untracked = 0;
    for (std::size_t t = 0; t + 1 < alone.labels.size(); ++t)
    {
      alone_untracked += alone.counts[t].back();
      together_untracked += together.counts[t].back();
    }
    json r = all.toJson();
    r.update({ { "variant", v.name },
               { "title", v.title },
               { "alone_untracked", alone_untracked },
               { "together_untracked", together_untracked },
               { "segments_not_shown", not_shown },
               { "segments_not_trained", not_trained },
               { "visible", visible.toJson() },
               { "per_person", per_person },
               { "per_action", per_action },
               { "alone_confusion", confusionJson(alone) },
               { "together_confusion", confusionJson(together) } });
    writeTextAtomically(dir + "/crowd_confusion_" + v.name + "_alone.csv", confusionCsv(alone));
    writeTextAtomically(dir + "/crowd_confusion_" + v.name + "_together.csv", confusionCsv(together));
    std::printf("%-40s %d actions: alone %5.1f%%, together %5.1f%% (%+.1f points); untracked %d alone, %d together\n",
                v.title.c_str(), all.segments, 100.0 * r["alone"].get<double>(), 100.0 * r["together"].get<double>(),
                100.0 * r["difference"].get<double>(), alone_untracked, together_untracked);
    std::printf("%-40s %d of them in plain view together: alone %5.1f%%, together %5.1f%% (%+.1f points)\n", "",
                visible.segments, 100.0 * r["visible"]["alone"].get<double>(),
                100.0 * r["visible"]["together"].get<double>(), 100.0 * r["visible"]["difference"].get<double>());
    return r;
  }
};

/** One line of segments.csv: @p r as @p variant read it, in @p scene. */
std::string segmentLine(const std::string& variant, const std::string& scene, const ScoredSegment& r)
{
  char line[512];
  std::snprintf(line, sizeof line, "%s,%s,%s,%d,%s,%d,%d,%.3f,%.3f,%s,%s,%u,%u\n", variant.c_str(), scene.c_str(),
                r.actor.c_str(), int(r.segment.person), r.segment.action.c_str(), r.segment.first, r.segment.last,
                r.shown_alone, r.shown_together, r.alone.c_str(), r.together.c_str(), r.alone_track, r.together_track);
  return line;
}

/** Trains @p v on every training sample, scores every action of the crowd scenes' people alone and
 *  together (@p e: the extraction index of the passes' rows it reads), writes its confusion matrices
 *  to @p dir, adds its lines to @p csv and returns its report entry. */
json scoreVariant(const RecognizerVariant& v, std::size_t e, const std::vector<SampleRef>& samples,
                  const std::vector<std::vector<SampleFrames>>& train_frames,
                  const std::vector<synth::SampleSpec>& scenes, const std::vector<std::vector<synth::CrowdPerson>>& people,
                  const std::vector<const Pass*>& together,
                  const std::map<std::pair<std::size_t, std::uint8_t>, const Pass*>& alone, const std::string& dir,
                  std::string& csv)
{
  std::vector<LabelledSample> labelled;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    labelled.push_back({ samples[i].person, samples[i].action, &train_frames[v.extraction][i] });
    rows.push_back(i);
  }
  const ActionModel model = trainModel(labelled, rows, v.params);
  const SequenceClassifier classifier = model.classifier();
  std::vector<std::string> labels = classifier.classes();
  labels.push_back(kUntracked);
  VariantScores scores(labels);
  for (std::size_t s = 0; s < scenes.size(); ++s)
    for (const synth::CrowdPerson& person : people[s])
      for (const synth::StreamSegment& seg : person.segments)
      {
        const Pass& solo = *alone.at({ s, person.mask_id });
        if (seg.last >= int(solo.counted.size()) || seg.first > seg.last)
          continue;  // past the scene's end
        if (std::find(labels.begin(), labels.end() - 1, seg.action) == labels.end() - 1)
        {
          ++scores.not_trained;
          continue;
        }
        ScoredSegment r;
        r.scene = s;
        r.actor = person.actor;
        r.segment = { person.mask_id, seg.action, seg.first, seg.last };
        r.shown_alone = share(solo.counted, seg.first, seg.last);
        r.shown_together = share(together[s]->counted_of.at(person.mask_id), seg.first, seg.last);
        if (r.shown_alone < kShownShare)
        {
          ++scores.not_shown;
          continue;
        }
        r.alone = recognise(solo, e, r.segment, model, classifier, r.alone_track);
        r.together = recognise(*together[s], e, r.segment, model, classifier, r.together_track);
        scores.add(r, scenes[s].name() + "/" + person.actor);
        csv += segmentLine(v.name, scenes[s].name(), r);
      }
  return scores.report(v, dir);
}

}  // namespace

void addCrowdOptions(Options& o)
{
  o.group("crowd protocol (--protocol crowd: several people at once; --scenes scenes per count, --gate as detection)")
      .value("crowd-people", "LIST", "people per crowd scene, e.g. 3 or 2,3,5 (default 3)")
      .value("crowd-seconds", "T", "length of a crowd scene in seconds (default 40)");
}

std::vector<int> crowdPeopleList(const std::string& text, const std::string& option)
{
  std::vector<int> out;
  for (const std::string& item : splitList(text))
  {
    if (item.size() != 1 || item[0] < '2' || item[0] > '5')
      throw UsageError(option + " takes counts 2..5 separated by commas, got '" + text + "'");
    out.push_back(item[0] - '0');
  }
  if (out.empty())
    throw UsageError(option + " takes counts 2..5 separated by commas, got '" + text + "'");
  return out;
}

int runCrowdProtocol(const Args& args, const std::vector<SampleRef>& samples,
                     const std::vector<RecognitionParams>& extractions, const std::vector<RecognizerVariant>& variants,
                     const std::string& dir)
{
  if (args.get("synth") != "ias")
    throw UsageError("--protocol crowd trains on the synthetic actors' samples: give --synth ias");
  for (const auto& v : variants)
    if (v.name == "joints")
      throw UsageError("--protocol crowd: the joint baseline has no skeletons of crowd scenes");
  const float gate = static_cast<float>(args.number("gate", 0.5));
  if (!(gate > 0.0f && gate < 5.0f))
    throw UsageError("--gate must be in (0, 5) m");
  std::set<std::string> training_people;
  for (const auto& s : samples)
    training_people.insert(s.person);
  const std::vector<synth::SampleSpec> scenes = testScenes(args, training_people);
  // Only the descriptor sets the variants read are extracted from the scenes.
  std::vector<std::size_t> used;
  for (const auto& v : variants)
    if (std::find(used.begin(), used.end(), v.extraction) == used.end())
      used.push_back(v.extraction);
  std::vector<RecognitionParams> scene_extractions;
  for (std::size_t e : used)
    scene_extractions.push_back(extractions[e]);
  const TrackerParams tracker = trackerParams(args);
  const int jobs = jobsOption(args);

  std::vector<std::vector<synth::CrowdPerson>> people;
  json scene_list = json::array();
  for (const auto& spec : scenes)
  {
    const synth::CrowdRenderer crowd(spec);
    people.push_back(crowd.people());
    scene_list.push_back({ { "scene", spec.name() }, { "actors", spec.person }, { "people", spec.crowd_people },
                           { "frames", crowd.frames() } });
  }
  std::fprintf(stderr,
               "evaluate: crowd protocol: %zu training samples of %zu people; %zu scenes of new people, each "
               "recognised with everyone in view and with each person alone\n",
               samples.size(), training_people.size(), scenes.size());
  installInterruptHandler();
  const auto train_frames = extractAll(samples, extractions, tracker, cacheDir(args), jobs);
  refuseEmptySamples(samples, train_frames[used.front()], args.has("allow-empty"));
  const std::vector<Pass> passes = runPasses(scenes, people, scene_extractions, tracker, gate, jobs);
  std::vector<const Pass*> together(scenes.size());
  std::map<std::pair<std::size_t, std::uint8_t>, const Pass*> alone;
  for (const Pass& p : passes)
    (p.only == 0 ? together[p.scene] : alone[{ p.scene, p.only }]) = &p;

  json results = json::array();
  std::string csv = "variant,scene,actor,person,action,first,last,shown_alone,shown_together,alone,together,"
                    "alone_track,together_track\n";
  for (const auto& v : variants)
    results.push_back(scoreVariant(v, std::size_t(std::find(used.begin(), used.end(), v.extraction) - used.begin()),
                                   samples, train_frames, scenes, people, together, alone, dir, csv));
  const json report = { { "protocol", "crowd" },
                        { "training", { { "samples", samples.size() },
                                        { "people", std::vector<std::string>(training_people.begin(), training_people.end()) } } },
                        { "scenes", scene_list },
                        { "gate_m", gate },
                        { "shown_share", kShownShare },
                        { "visible_share", kVisibleShare },
                        { "match", "per frame, track to person by ground-plane distance within the gate (as evaluate_tracking); "
                                   "an action's rows are those of the track matched to the person in most of its frames" },
                        { "variants", results } };
  writeTextAtomically(dir + "/crowd.json", report.dump(2) + "\n");
  writeTextAtomically(dir + "/segments.csv", csv);
  std::printf("evaluate: report in %s/crowd.json\n", dir.c_str());
  std::fflush(stdout);
  if (!args.has("no-plots"))
    runPlotScript("plot_crowd.py", { dir + "/crowd.json" });
  return 0;
}

}  // namespace tools
}  // namespace action_flow
