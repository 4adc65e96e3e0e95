#include "online_protocol.h"

#include "cli.h"
#include "plot_script.h"
#include "extraction.h"
#include "sample_sources.h"
#include "../eval/no_action.h"

#include <action_flow/files.h>
#include <action_flow/synth/synth.h>


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <limits>
#include <map>
#include <set>

namespace action_flow
{
namespace tools
{
namespace
{
using json = nlohmann::json;

json scoreJson(const StreamScore& s)
{
  const auto finite = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
  return { { "truths", s.truths },
           { "predictions", s.predictions },
           { "matched", s.matched },
           { "precision", s.precision },
           { "recall", s.recall },
           { "f1", s.f1 },
           { "frame_accuracy", s.frame_accuracy },
           { "false_labels", s.false_labels },
           { "false_per_minute", s.false_per_minute() },
           { "idle_false", s.idle_false },
           { "idle_false_per_minute", s.idle_false_per_minute() },
           { "idle_seconds", s.idle_seconds },
           { "stream_seconds", s.stream_seconds },
           { "median_start_latency_s", finite(median(s.start_latency)) },
           { "median_end_latency_s", finite(median(s.end_latency)) } };
}

StreamScore scoreCase(const StreamCase& c, const std::vector<PredictedSegment>& predicted)
{
  return scoreStream(c.truth, predicted, c.frame_stamps, c.start, c.end);
}

// The streams' cases: truth from the renderer (cheap: no frame is rendered), frames from extraction.
std::vector<StreamCase> streamCases(const std::vector<synth::SampleSpec>& specs, const std::vector<SampleFrames>& frames)
{
  std::vector<StreamCase> out;
  for (std::size_t i = 0; i < specs.size(); ++i)
  {
    const synth::SampleRenderer r(specs[i]);
    StreamCase c;
    c.name = specs[i].name();
    for (const auto& s : r.segments())
      c.truth.push_back({ s.action, r.stamp(s.first), r.stamp(s.last) });
    for (int f = 0; f < r.frames(); ++f)
      c.frame_stamps.push_back(r.stamp(f));
    c.start = c.frame_stamps.front();
    c.end = c.frame_stamps.back();
    c.frames = &frames[i];
    out.push_back(std::move(c));
  }
  return out;
}

int personNumber(const std::string& person)
{
  if (person.size() < 2 || person[0] != 'p')
    throw UsageError("--synth ias: the online protocol expected synthetic actors, not '" + person + "'");
  return std::atoi(person.c_str() + 1);
}

/** What a route of the protocol gives: the training samples and the streams to tune on and to test. */
struct OnlineSet
{
  std::vector<SampleRef> training;   // the segmented samples the models learn from
  std::vector<std::string> people;   // their people, sorted
  std::set<std::string> tuners;      // training people whose streams choose the thresholds
  std::vector<synth::SampleSpec> tuning, test;
  /** The streams of each training person who does not tune: with the tuning streams, the no-action windows' sources. */
  std::vector<synth::SampleSpec> no_action;
  std::vector<std::string> test_people;
  std::string dataset;               // --synth: ias or msr
};

/** The training people whose streams choose the thresholds (--tuning-people, default a third): the last ones. */
std::set<std::string> tuningPeople(const Args& args, const std::vector<std::string>& people)
{
  if (people.size() < 2)
    throw UsageError("--protocol online needs at least 2 training people (some choose the thresholds)");
  const int n = static_cast<int>(args.integer("tuning-people", std::max<long>(1, static_cast<long>(people.size() + 2) / 3),
                                              1, static_cast<long>(people.size()) - 1));
  return std::set<std::string>(people.end() - n, people.end());
}

/** The actions an MSR stream draws from: @p trained, or empty when that is all 20. */
std::vector<std::string> msrPool(const std::vector<std::string>& trained)
{
  std::vector<std::string> pool = uniqueSorted(trained);
  if (pool.size() == synth::msrActions().size())
    pool.clear();  // all of them
  return pool;
}

/**
 * The continuous streams of each of @p persons (training people: the tuning streams, and the sources
 * of the no-action and action windows), --training-streams of them (default 1), of @p count actions;
 * --synth msr: drawn from @p pool.
 */
std::vector<synth::SampleSpec> trainingStreams(const Args& args, const std::vector<std::string>& persons, int count,
                                               std::uint64_t seed, const std::vector<std::string>& pool)
{
  const int streams = static_cast<int>(args.integer("training-streams", 1, 1, 20));
  if (args.get("synth") == "msr")
    return synth::msrStreamSamples(args.get("msr-dir"), persons, streams, count, seed, pool);
  std::vector<synth::SampleSpec> out;
  for (const auto& p : persons)
    for (const auto& s : synth::streamSamples(personNumber(p), 1, streams, count, seed))
      out.push_back(s);
  return out;
}

/**
 * --synth ias: trains on every sample given; tunes on the streams of each tuning person; tests on
 * the streams of --stream-people new actors after the training people.
 */
OnlineSet iasSet(const Args& args, const std::vector<SampleRef>& samples, int streams, int actions, std::uint64_t seed)
{
  OnlineSet out;
  out.training = samples;
  std::vector<std::string> persons;
  int last = 0;
  for (const auto& s : samples)
  {
    persons.push_back(s.person);
    last = std::max(last, personNumber(s.person));
  }
  out.people = uniqueSorted(persons);
  out.tuners = tuningPeople(args, out.people);
  const int stream_people = static_cast<int>(args.integer("stream-people", 6, 1, 50));
  if (last + stream_people > 99)
    throw UsageError("--stream-people: new actors would go past p99");
  for (const auto& p : out.people)
    for (const auto& s : trainingStreams(args, { p }, actions, seed, {}))
      (out.tuners.count(p) ? out.tuning : out.no_action).push_back(s);
  out.test = synth::streamSamples(last + 1, stream_people, streams, actions, seed);
  for (const auto& s : out.test)
    out.test_people.push_back(s.person);
  out.test_people = uniqueSorted(out.test_people);
  return out;
}

/**
 * --synth msr: trains on the samples of the cross-subject training subjects (--train-persons); tunes
 * on the MSR streams of each tuning subject; tests on --streams MSR streams of every other subject.
 * The streams draw from the actions trained on (all 20, or those --actions keeps).
 */
OnlineSet msrSet(const Args& args, const std::vector<SampleRef>& samples, int streams, int actions, std::uint64_t seed)
{
  const std::vector<std::string> train = trainPersons(args);
  OnlineSet out;
  std::vector<std::string> persons, trained;
  for (const auto& s : samples)
  {
    persons.push_back(s.person);
    if (std::find(train.begin(), train.end(), s.person) != train.end())
    {
      out.training.push_back(s);
      out.people.push_back(s.person);
      trained.push_back(s.action);
    }
  }
  out.people = uniqueSorted(out.people);
  for (const auto& p : train)
    if (!std::binary_search(out.people.begin(), out.people.end(), p))
      throw UsageError("--train-persons: no MSR sample of '" + p + "'");
  for (const auto& p : uniqueSorted(persons))
    if (std::find(train.begin(), train.end(), p) == train.end())
      out.test_people.push_back(p);
  if (out.test_people.empty())
    throw UsageError("--protocol online: every MSR subject is in --train-persons; none is left to test on");
  out.tuners = tuningPeople(args, out.people);
  const std::vector<std::string> pool = msrPool(trained);
  out.tuning = trainingStreams(args, std::vector<std::string>(out.tuners.begin(), out.tuners.end()), actions, seed, pool);
  std::vector<std::string> others;
  for (const auto& p : out.people)
    if (!out.tuners.count(p))
      others.push_back(p);
  out.no_action = trainingStreams(args, others, actions, seed, pool);
  out.test = synth::msrStreamSamples(args.get("msr-dir"), out.test_people, streams, actions, seed, pool);
  return out;
}

}  // namespace

std::vector<PredictedSegment> runPolicy(const std::shared_ptr<const ActionModel>& model, const PolicyParams& params,
                                        const SampleFrames& frames)
{
  PolicyParams p = params;
  p.mode = PolicyParams::Mode::Online;
  RecognitionPolicy policy(model, p);
  std::vector<PredictedSegment> out;
  std::map<std::uint32_t, std::size_t> last_of_track;  // the track's last label, which Ended closes
  const auto take = [&](const std::vector<LabelEvent>& events, double now) {
    for (const LabelEvent& e : events)
    {
      const auto last = last_of_track.find(e.track);
      if (e.closes_published && last != last_of_track.end())
        out[last->second].end = e.end;
      else
      {
        last_of_track[e.track] = out.size();
        out.push_back({ e.result.label, e.start, e.end, now });
      }
    }
  };
  // Every track as the live pipeline would see it: a track not seen for more than a second has
  // ended (the tracker's own patience is shorter), also when a person re-identified under its id
  // comes back later (TrackerParams::reid_after): they start a new sequence.
  std::map<std::uint32_t, double> last_seen;
  for (Eigen::Index r = 0; r < frames.descriptors.rows(); ++r)
  {
    const std::size_t i = static_cast<std::size_t>(r);
    const double stamp = frames.stamps[i];
    const std::uint32_t track = frames.tracks.empty() ? 1u : frames.tracks[i];
    for (auto it = last_seen.begin(); it != last_seen.end();)
      if (stamp - it->second > 1.0)
      {
        take(policy.end(it->first), stamp);
        it = last_seen.erase(it);
      }
      else
        ++it;
    last_seen[track] = stamp;
    take(policy.add(track, frames.descriptors.row(r).transpose(), stamp), stamp);
  }
  if (!frames.stamps.empty())
    take(policy.endAll(), frames.stamps.back());
  return out;
}

std::vector<PolicyParams> policyCandidates(Recognizer recognizer)
{
  std::vector<PolicyParams> out;
  PolicyParams base;
  base.mode = PolicyParams::Mode::Online;
  if (recognizer == Recognizer::PostureFlow)
  {
    for (double on : { 0.5, 0.8, 1.2 })
      for (double rest : { 0.5, 1.0 })
        // The linear classifier's confidence is calibrated (a probability of being right on new
        // people), so the rejection thresholds run up to 0.7.
        for (double confidence : { 0.0, 0.2, 0.3, 0.5, 0.7 })
          for (int stable : { 0, 2, 3 })  // 0: no early label, only when the segment ends
            for (double trim : { 0.0, 1.0 })  // only for labels given when the segment ends
            {
              if (stable > 0 && trim > 0.0)
                continue;
              PolicyParams p = base;
              p.motion_on = on;
              p.motion_off = 0.6 * on;
              p.rest_time = rest;
              p.min_confidence = confidence;
              p.publish_early = stable > 0;
              p.stable_count = std::max(stable, 1);
              p.trim = trim;
              out.push_back(p);
            }
  }
  // The sliding window: the only way for the paper's descriptors (they carry no shape), and a
  // candidate for posture_flow too.
  {
    for (double window : { 2.0, 3.0 })
      for (double confidence : { 0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7 })
        for (int stable : { 2, 3, 5 })
        {
          PolicyParams p = base;
          p.motion_segments = false;
          p.window = window;
          p.min_confidence = confidence;
          p.stable_count = stable;
          out.push_back(p);
        }
  }
  return out;
}

PolicyParams choosePolicy(const std::shared_ptr<const ActionModel>& model, const std::vector<StreamCase>& streams,
                          const std::vector<PolicyParams>& candidates, StreamScore* score)
{
  if (candidates.empty() || streams.empty())
    throw std::invalid_argument("choosePolicy: no candidates or no streams");
  std::size_t best = 0;
  StreamScore best_score;
  for (std::size_t k = 0; k < candidates.size(); ++k)
  {
    std::vector<StreamScore> scores;
    for (const StreamCase& c : streams)
      scores.push_back(scoreCase(c, runPolicy(model, candidates[k], *c.frames)));
    const StreamScore s = combineScores(scores);
    if (k == 0 || s.f1 > best_score.f1 + 1e-12 ||
        (std::fabs(s.f1 - best_score.f1) <= 1e-12 && s.false_per_minute() < best_score.false_per_minute() - 1e-12))
    {
      best = k;
      best_score = s;
    }
  }
  if (score)
    *score = best_score;
  return candidates[best];
}

json policyJson(const PolicyParams& p)
{
  return { { "motion_segments", p.motion_segments }, { "motion_on", p.motion_on },         { "motion_off", p.motion_off },   { "rest_time", p.rest_time },
           { "min_confidence", p.min_confidence },
           { "publish_early", p.publish_early }, { "stable_count", p.stable_count }, { "classify_every", p.classify_every },
           { "trim", p.trim },
           { "window", p.window },               { "idle_labels", p.idle_labels } };
}

void addOnlineOptions(Options& o)
{
  o.group("online protocol (--protocol online, with --synth ias or --synth msr for the training samples)")
      .value("stream-people", "N", "ias: new actors after the training people, one set of streams each (default 6)")
      .value("streams", "N", "streams per new actor (ias) or per test subject (msr) (default 1)")
      .value("stream-actions", "N", "actions (msr: MSR sequences) per stream (default 8)")
      .value("training-streams", "N", "streams of each training person: of the tuning people to choose the "
                                      "policy by, of the others for windows to learn from (default 1)")
      .value("tuning-people", "N", "training people whose streams choose the policy's thresholds, with a model "
                                   "trained on the other training people (default: a third)");
}

namespace
{
/** --synth and the streams' options, then the route's training samples and streams. */
OnlineSet onlineSet(const Args& args, const std::vector<SampleRef>& samples, int& max_frames)
{
  const std::string dataset = args.get("synth");
  if (dataset != "ias" && dataset != "msr")
    throw UsageError("--protocol online renders its streams: give --synth ias or --synth msr");
  const int streams = static_cast<int>(args.integer("streams", 1, 1, 20));
  const int actions = static_cast<int>(args.integer("stream-actions", 8, 2, 40));
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1000000000));
  max_frames = static_cast<int>(args.integer("max-frames", 0, 0, 100000));
  OnlineSet set = dataset == "ias" ? iasSet(args, samples, streams, actions, seed)
                                   : msrSet(args, samples, streams, actions, seed);
  set.dataset = dataset;
  return set;
}

/** The streams of a run, rendered: of the tuning people, then of the people tested. */
struct OnlineStreams
{
  std::vector<synth::SampleSpec> specs;
  std::size_t tuning = 0;     // the first ones, of the tuning people
  std::size_t no_action = 0;  // the next ones, of the other training people
  std::vector<SampleRef> refs;
};

OnlineStreams renderStreams(const OnlineSet& set, int max_frames)
{
  OnlineStreams out;
  out.specs = set.tuning;
  out.tuning = out.specs.size();
  out.specs.insert(out.specs.end(), set.no_action.begin(), set.no_action.end());
  out.no_action = set.no_action.size();
  out.specs.insert(out.specs.end(), set.test.begin(), set.test.end());
  for (auto& s : out.specs)
  {
    s.max_frames = max_frames;
    out.refs.push_back(renderedSample(s));
  }
  return out;
}

/** The descriptor sets the variants read: the paper's SUMFLOW (0) and posture_flow (1). */
std::vector<RecognitionParams> onlineExtractions(const Args& args)
{
  RecognitionParams sum = methodParams(args), pf = sum;
  sum.recognizer = Recognizer::Paper;
  sum.grid.aggregation = FlowAggregation::Sum;
  sum.use_pca = false;
  pf.recognizer = Recognizer::PostureFlow;
  return { sum, pf };
}

/** --variants, of posture_flow, posture_flow_closed (no no-action class) and sumflow. */
std::vector<std::string> onlineVariants(const Args& args)
{
  const std::vector<std::string> variants =
      splitList(args.get("variants", "posture_flow,posture_flow_closed,sumflow"));
  for (const auto& v : variants)
    if (v != "posture_flow" && v != "posture_flow_closed" && v != "sumflow")
      throw UsageError("--protocol online runs the variants posture_flow, posture_flow_closed and sumflow, not '" +
                       v + "'");
  return variants;
}

/**
 * The windows per training stream the variant may learn (as no_action, and as the action they
 * hold), chosen on the tuning streams: posture_flow chooses among these (0 and 0: the segmented
 * samples only); the others learn none (sumflow is the paper's recognizer, unchanged).
 */
std::vector<StreamWindowCounts> windowCandidates(const std::string& variant)
{
  if (variant != "posture_flow")
    return { {} };
  std::vector<StreamWindowCounts> out;
  // 48 of either is about all a one-minute stream holds.
  for (int action : { 0, 24, 48 })
    for (int no_action : { 0, 6, 12, 24, 48 })
      out.push_back({ no_action, action });
  return out;
}

/** What every variant of a run reads: the training samples, the streams and their descriptors. */
struct OnlineRun
{
  const std::vector<SampleRef>& training;
  const OnlineStreams& streams;
  const std::vector<RecognitionParams>& extractions;
  const std::vector<std::vector<SampleFrames>>& train_frames;   // per extraction, per sample
  const std::vector<std::vector<SampleFrames>>& stream_frames;  // per extraction, per stream
  std::vector<std::size_t> all_rows;    // every training sample
  std::vector<std::size_t> inner_rows;  // those of no tuning person
  int jobs;                             // models trained at once while tuning
};

/** One stream's rows of timeline.csv: its truth, then the labels predicted. */
void appendTimeline(std::string& timeline, const std::string& name,
                    const std::vector<TruthSegment>& truth,
                    const std::vector<PredictedSegment>& predicted)
{
  for (const auto& t : truth)
    timeline += name + ",truth," + t.label + "," + std::to_string(t.start) + "," +
                std::to_string(t.end) + ",\n";
  for (const auto& p : predicted)
    timeline += name + ",predicted," + p.label + "," + std::to_string(p.start) + "," +
                std::to_string(p.end) + "," + std::to_string(p.published) + "\n";
}

/**
 * The chosen policy of variant @p v on each test stream: its scores into @p scores, its truth and
 * labels into @p timeline; returns the streams' report entries.
 */
json testStreams(const std::shared_ptr<const ActionModel>& model, const PolicyParams& chosen,
                 const std::vector<StreamCase>& test, const std::string& v,
                 std::vector<StreamScore>& scores, std::string& timeline)
{
  json per_stream = json::array();
  for (const StreamCase& c : test)
  {
    const auto predicted = runPolicy(model, chosen, *c.frames);
    scores.push_back(scoreCase(c, predicted));
    const std::set<std::uint32_t> ids(c.frames->tracks.begin(), c.frames->tracks.end());
    per_stream.push_back({ { "stream", c.name }, { "descriptors", c.frames->stamps.size() },
                           { "tracks", ids.size() }, { "frames", c.frame_stamps.size() },
                           { "score", scoreJson(scores.back()) } });
    appendTimeline(timeline, v + "_" + c.name, c.truth, predicted);
  }
  return per_stream;
}

void printVariantScore(const std::string& v, const StreamScore& all)
{
  std::printf("%-14s segment F1@0.5 %.2f (P %.2f R %.2f), frame accuracy %.1f%%, "
              "%.1f false labels/min in idle (%.1f/min overall), "
              "median latency %.2f s from the start, %.2f s from the end\n",
              v.c_str(), all.f1, all.precision, all.recall, 100 * all.frame_accuracy,
              all.idle_false_per_minute(), all.false_per_minute(), median(all.start_latency),
              median(all.end_latency));
}

/**
 * Adds to @p labelled (and its index to @p rows) the no-action windows and the action windows of
 * @p streams (no_action.h), at most @p counts of each a stream, as samples of the stream's person;
 * @p store keeps their frames. Action windows only of the actions @p labelled already holds.
 */
void addStreamWindows(const std::vector<StreamCase>& streams, const std::vector<std::string>& persons,
                      const StreamWindowCounts& counts, std::vector<LabelledSample>& labelled,
                      std::vector<std::size_t>& rows, std::deque<SampleFrames>& store)
{
  NoActionWindows idle;
  idle.per_stream = counts.no_action;
  ActionWindows acting;
  acting.per_stream = counts.action;
  std::set<std::string> known;
  for (const LabelledSample& s : labelled)
    known.insert(s.action);
  const auto add = [&](const std::string& person, const std::string& label, SampleFrames&& f) {
    store.push_back(std::move(f));
    rows.push_back(labelled.size());
    labelled.push_back({ person, label, &store.back() });
  };
  for (std::size_t i = 0; i < streams.size(); ++i)
  {
    for (SampleFrames& f : noActionWindows(streams[i].truth, *streams[i].frames, idle))
      add(persons[i], kNoActionLabel, std::move(f));
    for (ActionWindow& a : actionWindows(streams[i].truth, *streams[i].frames, acting))
      if (known.count(a.label))
        add(persons[i], a.label, std::move(a.frames));
  }
}

/** The persons of the streams [first, first + n) of the run. */
std::vector<std::string> streamPersons(const OnlineStreams& streams, std::size_t first, std::size_t n)
{
  std::vector<std::string> out;
  for (std::size_t i = first; i < first + n; ++i)
    out.push_back(streams.specs[i].person);
  return out;
}

/** A variant's streams, split by their use, and the people of each. */
struct VariantStreams
{
  std::vector<StreamCase> tuning, sources, test;
  std::vector<std::string> tuning_persons, source_persons;
};

VariantStreams variantStreams(const OnlineRun& run, std::size_t e)
{
  const auto cases = streamCases(run.streams.specs, run.stream_frames[e]);
  const auto first_source = cases.begin() + static_cast<long>(run.streams.tuning);
  const auto first_test = first_source + static_cast<long>(run.streams.no_action);
  return { { cases.begin(), first_source },
           { first_source, first_test },
           { first_test, cases.end() },
           streamPersons(run.streams, 0, run.streams.tuning),
           streamPersons(run.streams, run.streams.tuning, run.streams.no_action) };
}

/** What a model tried on the tuning streams gives: the policy chosen with it, its score, its report entry. */
struct Tuned
{
  PolicyParams policy;
  StreamScore score;
  json entry;
};

/** The pyramid's pooling into @p entry, for posture_flow (the paper's recognizer has no pyramid). */
void addPooling(json& entry, const RecognitionParams& params)
{
  if (params.recognizer != Recognizer::PostureFlow)
    return;
  entry["max_pooling"] = params.pyramid.max_pooling;
  entry["fourier"] = params.pyramid.fourier;
}

/** Ranks tuning scores: the higher F1, then the fewer false labels a minute in idle periods. */
bool betterTuning(const StreamScore& a, const StreamScore& b)
{
  return a.f1 > b.f1 + 1e-12 ||
         (std::fabs(a.f1 - b.f1) <= 1e-12 && a.idle_false_per_minute() < b.idle_false_per_minute() - 1e-12);
}

/**
 * A model of the training people who do not tune (@p labelled at run.inner_rows), with @p windows
 * of the source streams, pyramid pooling as in @p params; the policy chosen with it on the tuning streams.
 */
Tuned tune(const OnlineRun& run, const std::vector<LabelledSample>& labelled, const VariantStreams& s,
           const StreamWindowCounts& windows, const RecognitionParams& params)
{
  std::vector<LabelledSample> inner = labelled;
  std::vector<std::size_t> rows = run.inner_rows;
  std::deque<SampleFrames> store;
  addStreamWindows(s.sources, s.source_persons, windows, inner, rows, store);
  auto model = std::make_shared<const ActionModel>(trainModel(inner, rows, params));
  Tuned t;
  t.policy = choosePolicy(model, s.tuning, policyCandidates(params.recognizer), &t.score);
  const std::size_t idle = noActionCount(inner, labelled.size());
  t.entry = { { "no_action_windows", windows.no_action },
              { "action_windows", windows.action },
              { "samples", idle },
              { "action_samples", inner.size() - labelled.size() - idle },
              { "policy", policyJson(t.policy) },
              { "tuning_score", scoreJson(t.score) } };
  addPooling(t.entry, params);
  return t;
}

/**
 * The pyramid poolings a variant chooses among on the tuning streams: posture_flow tries @p base
 * (by default means, maxima and Fourier magnitudes), then means and maxima, then means only, each
 * once (a sliding window's maxima and magnitudes also hold the transitions around an action); the
 * others keep @p base.
 */
std::vector<PyramidParams> poolingCandidates(const std::string& variant, const PyramidParams& base)
{
  std::vector<PyramidParams> out{ base };
  if (variant != "posture_flow")
    return out;
  PyramidParams p = base;
  for (const bool maxima : { true, false })
  {
    p.fourier = 0;
    p.max_pooling = maxima;
    const bool tried = std::any_of(out.begin(), out.end(), [&](const PyramidParams& q) {
      return q.fourier == p.fourier && q.max_pooling == p.max_pooling;
    });
    if (!tried)
      out.push_back(p);
  }
  return out;
}

/**
 * Tunes candidates 0..n-1 with @p tune_one, up to @p jobs at once; appends their report entries to
 * @p entries in candidate order, moves the best (betterTuning; the first of equals) into @p best and
 * returns its index. The choice does not depend on @p jobs.
 */
std::size_t chooseCandidate(int jobs, std::size_t n, json& entries, Tuned& best,
                            const std::function<Tuned(std::size_t)>& tune_one)
{
  std::vector<Tuned> tried(n);
  forEachParallel(jobs, n, [&](std::size_t i) { tried[i] = tune_one(i); });
  std::size_t chosen = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    entries.push_back(tried[i].entry);
    if (betterTuning(tried[i].score, tried[chosen].score))
      chosen = i;
  }
  best = std::move(tried.at(chosen));
  return chosen;
}

/** The windows a stream gives while the pooling is chosen: fixed in the code before the choice was first measured. */
constexpr StreamWindowCounts kPoolingWindows{ 24, 24 };

/**
 * Variant @p v: the pyramid's pooling, then the windows a stream gives (when the variant learns from
 * them) and the policy's thresholds, chosen on the tuning streams with models trained without the
 * tuning people; then the model of every training person on the test streams. Returns its report
 * entry and adds its test streams to @p timeline.
 */
json onlineVariant(const OnlineRun& run, const std::string& v, std::string& timeline)
{
  const std::size_t e = v == "sumflow" ? 0 : 1;
  std::vector<LabelledSample> labelled;
  for (std::size_t i = 0; i < run.training.size(); ++i)
    labelled.push_back({ run.training[i].person, run.training[i].action, &run.train_frames[e][i] });
  const VariantStreams streams = variantStreams(run, e);
  const auto report = [&](const char* stage, const Tuned& t) {
    std::string pooling;
    if (t.entry.contains("fourier"))
      pooling = std::string(", pyramid maxima ") + (t.entry["max_pooling"].get<bool>() ? "on" : "off") + ", " +
                std::to_string(t.entry["fourier"].get<int>()) + " Fourier";
    std::fprintf(stderr,
                 "evaluate: %s %s: %d no-action and %d action windows a stream%s: tuning F1 %.2f, "
                 "%.1f false labels/min in idle\n",
                 v.c_str(), stage, t.entry["no_action_windows"].get<int>(), t.entry["action_windows"].get<int>(),
                 pooling.c_str(), t.score.f1, t.score.idle_false_per_minute());
  };

  // First the pooling, at kPoolingWindows; then the windows, with that pooling.
  RecognitionParams params = run.extractions[e];
  const std::vector<PyramidParams> poolings = poolingCandidates(v, params.pyramid);
  json per_pooling = json::array();
  Tuned best;
  if (poolings.size() > 1)
    params.pyramid = poolings[chooseCandidate(run.jobs, poolings.size(), per_pooling, best, [&](std::size_t i) {
      RecognitionParams p = params;
      p.pyramid = poolings[i];
      Tuned t = tune(run, labelled, streams, kPoolingWindows, p);
      report("pooling", t);
      return t;
    })];
  const Tuned pooled = best;
  const std::vector<StreamWindowCounts> window_candidates = windowCandidates(v);
  json per_windows = json::array();
  const StreamWindowCounts windows =
      window_candidates[chooseCandidate(run.jobs, window_candidates.size(), per_windows, best, [&](std::size_t i) {
        const StreamWindowCounts& candidate = window_candidates[i];
        const bool done = !per_pooling.empty() && candidate.no_action == kPoolingWindows.no_action &&
                          candidate.action == kPoolingWindows.action;
        Tuned t = done ? pooled : tune(run, labelled, streams, candidate, params);
        report("windows", t);
        return t;
      })];
  std::vector<std::size_t> rows = run.all_rows;
  std::deque<SampleFrames> store;
  const std::size_t segmented = labelled.size();
  addStreamWindows(streams.sources, streams.source_persons, windows, labelled, rows, store);
  addStreamWindows(streams.tuning, streams.tuning_persons, windows, labelled, rows, store);
  const std::size_t idle = noActionCount(labelled, segmented);
  auto model = std::make_shared<const ActionModel>(trainModel(labelled, rows, params));

  std::vector<StreamScore> scores;
  const json per_stream = testStreams(model, best.policy, streams.test, v, scores, timeline);
  const StreamScore all = combineScores(scores);
  printVariantScore(v, all);
  json entry = { { "variant", v },
                 { "policy", policyJson(best.policy) },
                 { "pooling_candidates", per_pooling },
                 { "no_action_windows", windows.no_action },
                 { "no_action_samples", idle },
                 { "action_windows", windows.action },
                 { "action_window_samples", labelled.size() - segmented - idle },
                 { "no_action_candidates", per_windows },
                 { "tuning_score", scoreJson(best.score) },
                 { "test", scoreJson(all) },
                 { "streams", per_stream } };
  addPooling(entry, params);
  return entry;
}

/** OUTPUT/online.json and OUTPUT/timeline.csv, then (unless --no-plots) the timeline pictures. */
void writeOnlineReport(const Args& args, const std::string& dir, const json& report,
                       const std::string& timeline)
{
  writeTextAtomically(dir + "/online.json", report.dump(2) + "\n");
  writeTextAtomically(dir + "/timeline.csv", timeline);
  std::printf("evaluate: report in %s/online.json\n", dir.c_str());
  if (!args.has("no-plots"))
    runPlotScript("plot_timeline.py", { dir + "/timeline.csv", dir });
}
}  // namespace

std::size_t appendStreamWindows(const Args& args, const std::vector<SampleRef>& samples, const StreamWindowCounts& counts,
                                  const RecognitionParams& params, std::vector<LabelledSample>& labelled,
                                  std::vector<std::size_t>& rows, std::deque<SampleFrames>& store)
{
  const std::string dataset = args.get("synth");
  if (dataset != "ias" && dataset != "msr")
    throw UsageError("--no-action-windows and --action-windows render streams of the training people: give --synth ias or --synth msr");
  std::vector<std::string> persons, actions;
  for (const auto& s : samples)
  {
    persons.push_back(s.person);
    actions.push_back(s.action);
  }
  persons = uniqueSorted(persons);
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1000000000));
  const int count = static_cast<int>(args.integer("stream-actions", 8, 2, 40));
  const std::vector<synth::SampleSpec> specs = trainingStreams(args, persons, count, seed, msrPool(actions));
  std::vector<SampleRef> refs;
  for (const auto& s : specs)
    refs.push_back(renderedSample(s));
  std::fprintf(stderr, "train: %zu streams of the training people for windows to learn from\n", refs.size());
  const auto frames = extractAll(refs, { params }, trackerParams(args), cacheDir(args), jobsOption(args));
  const auto cases = streamCases(specs, frames[0]);
  std::vector<std::string> of;
  for (const auto& s : specs)
    of.push_back(s.person);
  const std::size_t before = rows.size();
  // The frames live in `frames`, which ends here: the windows copy what they take.
  addStreamWindows(cases, of, counts, labelled, rows, store);
  return rows.size() - before;
}

int runOnlineProtocol(const Args& args, const std::vector<SampleRef>& samples, const std::string& dir)
{
  int max_frames = 0;
  const OnlineSet set = onlineSet(args, samples, max_frames);
  const std::vector<SampleRef>& training = set.training;
  const std::set<std::string>& tuners = set.tuners;
  const OnlineStreams streams = renderStreams(set, max_frames);
  const std::vector<RecognitionParams> extractions = onlineExtractions(args);
  const std::vector<std::string> variants = onlineVariants(args);

  std::fprintf(stderr,
               "evaluate: online protocol (%s): %zu training samples of %zu people; "
               "thresholds chosen on %zu streams of %zu of them; %zu streams of the others for windows to learn from; "
               "tested on %zu streams of %zu new people\n",
               set.dataset.c_str(), training.size(), set.people.size(), streams.tuning, tuners.size(),
               streams.no_action, streams.specs.size() - streams.tuning - streams.no_action,
               set.test_people.size());
  const TrackerParams tracker = trackerParams(args);
  const int jobs = jobsOption(args);
  installInterruptHandler();
  const auto train_frames = extractAll(training, extractions, tracker, cacheDir(args), jobs);
  refuseEmptySamples(training, train_frames[0], args.has("allow-empty"));
  const auto stream_frames = extractAll(streams.refs, extractions, tracker, cacheDir(args), jobs);

  OnlineRun run{ training, streams, extractions, train_frames, stream_frames, {}, {}, jobs };
  for (std::size_t i = 0; i < training.size(); ++i)
  {
    run.all_rows.push_back(i);
    if (!tuners.count(training[i].person))
      run.inner_rows.push_back(i);
  }
  json report = { { "protocol", "online" },
                  { "dataset", set.dataset },
                  { "training", { { "samples", training.size() }, { "people", set.people } } },
                  { "tuning_people", std::vector<std::string>(tuners.begin(), tuners.end()) },
                  { "tuning_streams", streams.tuning },
                  { "window_streams", streams.no_action },
                  { "test_people", set.test_people },
                  { "iou_threshold", 0.5 } };
  json results = json::array();
  std::string timeline = "stream,kind,label,start,end,published\n";
  for (const std::string& v : variants)
    results.push_back(onlineVariant(run, v, timeline));
  report["variants"] = results;
  writeOnlineReport(args, dir, report, timeline);
  return 0;
}

}  // namespace tools
}  // namespace action_flow
