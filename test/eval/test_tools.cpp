// train and evaluate end to end on a tiny rendered dataset, and their errors on bad input.
#include <gtest/gtest.h>

#include <action_flow/action_model.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace
{
const std::string kBin = ACTION_FLOW_BIN_DIR;  // where train, evaluate and synth are built
const std::string kScripts = ACTION_FLOW_SOURCE_DIR "/scripts";

struct Result
{
  int status;
  std::string output;
};

Result run(const std::string& cmd)
{
  Result r{ 0, "" };
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  char buf[4096];
  while (p && std::fgets(buf, sizeof(buf), p))
    r.output += buf;
  r.status = p ? ::pclose(p) : -1;
  return r;
}

std::string tempDir(const std::string& name)
{
  const std::string d = ::testing::TempDir() + "action_flow_tools_" + name;
  std::system(("rm -rf '" + d + "' && mkdir -p '" + d + "'").c_str());
  return d;
}

// A tiny dataset: 3 people x 3 actions x 1 repetition, 40 frames each, rendered to bags by synth
// (one run per action), with one index over all of them.
const std::string& tinyDataset()
{
  static std::string index;
  if (!index.empty())
    return index;
  const std::string d = tempDir("data");
  std::string csv = "path,person,action,repetition,frames\n";
  for (const std::string action : { "wave", "kick", "sit_down" })
  {
    const Result r = run(kBin + "/synth --out '" + d + "/" + action + "' --people 3 --repetitions 1 --action " + action +
                      " --frames 40 --jobs 2 --quiet");
    EXPECT_EQ(r.status, 0) << r.output;
    std::ifstream part(d + "/" + action + "/ias/index.csv");
    std::string line;
    std::getline(part, line);  // header
    while (std::getline(part, line))
      csv += action + "/ias/" + line + "\n";
  }
  std::ofstream(d + "/index.csv") << csv;
  index = d + "/index.csv";
  return index;
}
}  // namespace

TEST(Tools, TinyDatasetTrainsAndEvaluatesEndToEnd)
{
  const std::string index = tinyDataset();
  const std::string out = tempDir("report"), cache = tempDir("cache");
  const std::string model = out + "/tiny.model";

  // The default recognizer: 9 samples (mirrored too if the cross-validation chose so), a linear classifier.
  Result r = run(kBin + "/train --index '" + index + "' --output '" + model + "' --cache '" + cache + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const action_flow::ActionModel m = action_flow::ActionModel::load(model);
  EXPECT_EQ(m.params.recognizer, action_flow::Recognizer::PostureFlow);
  EXPECT_EQ(m.labels.size(), m.params.pyramid.mirror == action_flow::MirrorMode::On ? 18u : 9u);
  EXPECT_NE(m.params.pyramid.mirror, action_flow::MirrorMode::Choose);
  EXPECT_FALSE(m.linear.empty());
  EXPECT_GT(m.descriptors.norm(), 0.0f) << "the actors moved: some flow must have been found";
  // The paper's recognizer, as before.
  r = run(kBin + "/train --index '" + index + "' --output '" + model + "' --recognizer paper --frames 10 --cache '" +
          cache + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  const action_flow::ActionModel paper = action_flow::ActionModel::load(model);
  EXPECT_EQ(paper.params.recognizer, action_flow::Recognizer::Paper);
  EXPECT_EQ(paper.labels.size(), 9u);
  EXPECT_EQ(paper.params.frames, 10);

  r = run(kBin + "/evaluate --index '" + index + "' --output '" + out + "' --frames 10 --sweep 4 --cache '" + cache +
          "'");
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("/usr/bin/python3 " + kScripts + "/validate_report.py '" + out + "'");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("report OK"), std::string::npos) << r.output;

  // A broken report is caught by the validator (so the check above could fail).
  std::ofstream(out + "/report.json") << "{\"protocol\": \"lopo\"}";
  EXPECT_NE(run("/usr/bin/python3 " + kScripts + "/validate_report.py '" + out + "'").status, 0);
}

TEST(Tools, PersonsOptionKeepsOnlyThosePeople)
{
  // The development protocol (settings tried on the training people alone) depends on this filter.
  const std::string out = tempDir("persons"), cache = tempDir("persons_cache");
  const Result r = run(kBin + "/evaluate --index '" + tinyDataset() + "' --output '" + out +
                       "' --persons p01,p03 --variants posture_flow_nn --sweep 0 --no-plots --cache '" + cache + "'");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out + "/report.json");
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["samples"]["people"], 2);
  EXPECT_EQ(report["samples"]["total"], 6);
  EXPECT_EQ(report["folds"], 2);
  const Result help = run(kBin + "/evaluate --help");
  EXPECT_NE(help.output.find("--persons"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--msr-dir"), std::string::npos) << "the sample options are listed: " << help.output;
}

TEST(Tools, MalformedIndexGivesOneLineNamingTheLine)
{
  const std::string d = tempDir("badindex");
  std::ofstream(d + "/index.csv") << "path,person,action,repetition,frames\nnope.bag,p01,wave,1,30\n";
  const Result r = run(kBin + "/train --index '" + d + "/index.csv' --output '" + d + "/m.model'");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find(d + "/index.csv:2: sample file"), std::string::npos) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  const Result bad_option = run(kBin + "/evaluate --output x --index i --protocol nonsense");
  EXPECT_NE(bad_option.status, 0);
}

TEST(Tools, OutOfRangeOptionsAreUsageErrorsNamingTheOption)
{
  for (const std::string bad : { "--jobs 100000", "--jobs -3", "--people 0x10", "--max-frames -5", "--sweep 1000000",
                                 "--frames 10x", "--temporal-levels 9", "--c -1", "--bogus",
                                 "--training-copies 2" /* msr only */, "--training-copies 100", "--copy-changes hat" })
  {
    const Result r = run(kBin + "/evaluate --output /nonexistent --synth ias " + bad);
    EXPECT_EQ(WEXITSTATUS(r.status), 2) << bad << ": " << r.output;
    const std::string option = bad.substr(0, bad.find(' '));
    EXPECT_NE(r.output.find(option), std::string::npos) << bad << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << bad << ": " << r.output;
  }
  EXPECT_EQ(WEXITSTATUS(run(kBin + "/train --output /nonexistent --synth ias --jobs 0").status), 2);
}

// The output folder is made, parents and all, before the work; one that cannot be made is a usage
// error before any sample is described, naming --output.
TEST(Tools, OutputFolderIsMadeBeforeTheWork)
{
  const std::string d = tempDir("output_folder");
  const Result made = run(kBin + "/evaluate --output '" + d + "/a/b' --synth ias --people 2 --repetitions 1 "
                                 "--actions wave,kick --max-frames 4 --variants sumflow --sweep 0 --cache '" + d + "/cache'");
  ASSERT_EQ(made.status, 0) << made.output;
  EXPECT_TRUE(std::ifstream(d + "/a/b/report.json").good()) << made.output;
  std::ofstream(d + "/file") << "not a folder";
  const Result bad = run(kBin + "/evaluate --output '" + d + "/file/report' --synth ias --people 2 --repetitions 1 "
                                "--actions wave,kick --max-frames 4 --variants sumflow --sweep 0 --cache '" + d + "/cache2'");
  EXPECT_EQ(WEXITSTATUS(bad.status), 2) << bad.output;
  EXPECT_NE(bad.output.find("--output"), std::string::npos) << bad.output;
  EXPECT_EQ(std::count(bad.output.begin(), bad.output.end(), '\n'), 1) << bad.output;
  EXPECT_FALSE(std::ifstream(d + "/cache2").good()) << "no sample was described";
}

// evaluate --protocol cross-view, small: one fold per view, each variant's accuracy per view, and
// the report says which grid the tracker used (camera-aligned, or turned with --align-to-facing).
TEST(Tools, CrossViewReportsEachViewAndTheGrid)
{
  const std::string d = tempDir("cross_view");
  for (const bool turned : { false, true })
  {
    const std::string out = d + (turned ? "/turned" : "/plain");
    const Result r = run(kBin + "/evaluate --synth ias --protocol cross-view --people 2 --repetitions 1 "
                                "--actions wave,kick --views 90 --max-frames 12 --variants posture_flow_nn,sumflow "
                                "--allow-empty --no-plots --jobs 2 --cache '" + d + "/cache' --output '" + out + "'" +
                                (turned ? " --align-to-facing" : ""));
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(out + "/report.json");
    const nlohmann::json cv = nlohmann::json::parse(in).at("cross_view");
    EXPECT_EQ(cv.at("grid"), turned ? "turned to the facing" : "camera-aligned");
    EXPECT_EQ(cv.at("views"), nlohmann::json::array({ 0.0, 90.0 }));
    EXPECT_EQ(cv.at("train_spread"), 15.0);
    for (const char* v : { "posture_flow_nn", "sumflow" })
    {
      const nlohmann::json& acc = cv.at("accuracy").at(v);
      ASSERT_EQ(acc.size(), 2u) << v;
      for (const auto& a : acc)
        EXPECT_TRUE(a.get<double>() >= 0.0 && a.get<double>() <= 1.0) << v;
    }
    EXPECT_NE(r.output.find(turned ? "grid turned to the facing" : "grid camera-aligned"), std::string::npos) << r.output;
  }
}

TEST(Tools, SynthAddsToAnExistingIndex)
{
  // Two runs into one folder: the second adds its samples, the first run's rows stay; a row whose
  // bag is gone is dropped, and a sample rendered again is listed once.
  const std::string d = tempDir("index_append");
  const auto render = [&](const std::string& action) {
    const Result r = run(kBin + "/synth --out '" + d + "' --people 1 --repetitions 1 --action " + action +
                         " --frames 2 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
  };
  const auto rows = [&] {
    std::ifstream in(d + "/ias/index.csv");
    std::vector<std::string> out;
    std::string line;
    while (std::getline(in, line))
      out.push_back(line);
    return out;
  };
  render("wave");
  render("kick");
  std::vector<std::string> r = rows();
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0], "path,person,action,repetition,frames");
  EXPECT_EQ(r[1], "p01_wave_1.bag,p01,wave,1,2");
  EXPECT_EQ(r[2], "p01_kick_1.bag,p01,kick,1,2");
  render("kick");
  EXPECT_EQ(rows().size(), 3u) << "a sample rendered again is listed twice";
  std::remove((d + "/ias/p01_wave_1.bag").c_str());
  render("point");
  r = rows();
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[1], "p01_kick_1.bag,p01,kick,1,2");
  EXPECT_EQ(r[2], "p01_point_1.bag,p01,point,1,2");
}

TEST(Tools, SampleWithoutATrackedPersonIsRefused)
{
  // One frame: nobody can be tracked over it, so there is no frame descriptor to learn from.
  const std::string d = tempDir("empty");
  Result r = run(kBin + "/synth --out '" + d + "' --people 2 --repetitions 1 --action wave --frames 1 --quiet");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string index = d + "/ias/index.csv";
  r = run(kBin + "/train --index '" + index + "' --output '" + d + "/m.model' --cache '" + d + "/cache'");
  EXPECT_EQ(WEXITSTATUS(r.status), 1) << r.output;
  EXPECT_NE(r.output.find(".bag: no person was tracked"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--allow-empty"), std::string::npos) << r.output;
  std::ifstream model(d + "/m.model");
  EXPECT_FALSE(model.good()) << "a model was written from empty samples";
}

TEST(Tools, OnlineProtocolScoresStreamsOfNewPeopleOnly)
{
  // evaluate --protocol online end to end, small: 3 training actors x 3 actions, one of them tunes
  // the policy's thresholds with a model of the other two; one new actor's stream of 2 actions is
  // scored. The report must name the people apart and carry every figure the protocol promises.
  const std::string out = tempDir("online"), cache = tempDir("online_cache");
  const Result r = run(kBin + "/evaluate --synth ias --people 3 --repetitions 1 --actions wave,kick,sit_down" +
                       " --protocol online --stream-people 1 --stream-actions 2 --variants posture_flow --no-plots" +
                       " --output '" + out + "' --cache '" + cache + "' --jobs 2");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out + "/online.json");
  ASSERT_TRUE(in.good()) << "no online.json: " << r.output;
  const nlohmann::json report = nlohmann::json::parse(in);
  const std::vector<std::string> training = report["training"]["people"];
  EXPECT_EQ(training, (std::vector<std::string>{ "p01", "p02", "p03" }));
  EXPECT_EQ(report["tuning_streams"], 1) << "one stream of the tuning person, p03";
  EXPECT_EQ(report["window_streams"], 2) << "one stream each of p01 and p02";
  ASSERT_EQ(report["variants"].size(), 1u);
  const nlohmann::json& v = report["variants"][0];
  EXPECT_EQ(v["variant"], "posture_flow");
  for (const auto& s : v["streams"])
  {
    const std::string name = s["stream"];
    EXPECT_EQ(name.rfind("p04_stream_", 0), 0u) << "only the new actor's streams are tested: " << name;
  }
  const nlohmann::json& t = v["test"];
  for (const char* key : { "f1", "precision", "recall", "frame_accuracy", "false_per_minute", "idle_false_per_minute",
                           "median_start_latency_s", "median_end_latency_s", "truths" })
    EXPECT_TRUE(t.contains(key)) << key;
  EXPECT_EQ(t["truths"], 2) << "two actions in the stream";
  EXPECT_GE(t["f1"].get<double>(), 0.0);
  EXPECT_LE(t["f1"].get<double>(), 1.0);
  EXPECT_GE(t["frame_accuracy"].get<double>(), 0.0);
  EXPECT_LE(t["frame_accuracy"].get<double>(), 1.0);
  // The no-action class: 0, 6, 12, 24 or 48 windows a stream of the training people who do not tune
  // (p01, p02), with 0, 24 or 48 action windows, chosen on the tuning person's stream; the final model
  // takes them from p03's too.
  const std::vector<int> idle_counts = { 0, 6, 12, 24, 48 }, action_counts = { 0, 24, 48 };
  const std::size_t n_idle = idle_counts.size();
  ASSERT_EQ(v["no_action_candidates"].size(), n_idle * action_counts.size());
  for (std::size_t a = 0; a < action_counts.size(); ++a)
    for (std::size_t k = 0; k < n_idle; ++k)
    {
      const nlohmann::json& c = v["no_action_candidates"][a * n_idle + k];
      const nlohmann::json& without = v["no_action_candidates"][k];
      EXPECT_EQ(c["no_action_windows"], idle_counts[k]);
      EXPECT_EQ(c["action_windows"], action_counts[a]);
      if (a == 0)
      {
        EXPECT_EQ(c["action_samples"], 0);
      }
      // (the streams draw from all 14 actions: only windows of wave, kick or sit_down can be learnt)
      EXPECT_GE(c["action_samples"].get<int>(), 0);
      EXPECT_EQ(c["samples"], without["samples"]) << "action windows change no no-action count";
      if (a > 0)
      {
        EXPECT_GE(c["action_samples"].get<int>(), v["no_action_candidates"][(a - 1) * n_idle + k]["action_samples"].get<int>());
      }
    }
  EXPECT_EQ(v["no_action_candidates"][0]["samples"], 0);
  const int six = v["no_action_candidates"][1]["samples"];
  EXPECT_GT(six, 0) << "no window of transitions or idle periods in p01's and p02's streams";
  EXPECT_LE(six, 12);
  for (std::size_t k = 2; k < n_idle; ++k)
    EXPECT_GE(v["no_action_candidates"][k]["samples"].get<int>(), v["no_action_candidates"][k - 1]["samples"].get<int>());
  const int chosen = v["no_action_windows"];
  EXPECT_NE(std::find(idle_counts.begin(), idle_counts.end(), chosen), idle_counts.end()) << chosen;
  EXPECT_EQ(v["no_action_samples"].get<int>() > 0, chosen > 0);
  const int chosen_actions = v["action_windows"];
  EXPECT_NE(std::find(action_counts.begin(), action_counts.end(), chosen_actions), action_counts.end()) << chosen_actions;
  if (chosen_actions == 0)
  {
    EXPECT_EQ(v["action_window_samples"], 0);
  }
  // The pyramid's pooling is chosen first, at 24 and 24 windows: the default (means, maxima and 6
  // Fourier magnitudes), means and maxima, means only; the one of the best tuning score (F1, then
  // fewer false labels in idle periods) is chosen, and the windows are then chosen with it, every
  // candidate of them trained with it.
  const nlohmann::json& poolings = v["pooling_candidates"];
  ASSERT_EQ(poolings.size(), 3u);
  const std::vector<std::pair<bool, int>> tried = { { true, 6 }, { true, 0 }, { false, 0 } };
  for (std::size_t k = 0; k < tried.size(); ++k)
  {
    EXPECT_EQ(poolings[k]["max_pooling"], tried[k].first) << k;
    EXPECT_EQ(poolings[k]["fourier"], tried[k].second) << k;
    EXPECT_EQ(poolings[k]["no_action_windows"], 24) << k;
    EXPECT_EQ(poolings[k]["action_windows"], 24) << k;
  }
  std::size_t best = 0;
  for (std::size_t k = 1; k < poolings.size(); ++k)
  {
    const nlohmann::json &s = poolings[k]["tuning_score"], &b = poolings[best]["tuning_score"];
    const double f1 = s["f1"], best_f1 = b["f1"], idle = s["idle_false_per_minute"],
                 best_idle = b["idle_false_per_minute"];
    if (f1 > best_f1 + 1e-12 || (std::fabs(f1 - best_f1) <= 1e-12 && idle < best_idle - 1e-12))
      best = k;
  }
  const std::pair<bool, int> pooling{ v["max_pooling"].get<bool>(), v["fourier"].get<int>() };
  EXPECT_EQ(pooling, tried[best]) << "the pooling of the best tuning score is chosen";
  for (const auto& c : v["no_action_candidates"])
  {
    EXPECT_EQ(c["max_pooling"], pooling.first);
    EXPECT_EQ(c["fourier"], pooling.second);
  }
  const nlohmann::json& middle = v["no_action_candidates"][n_idle + 3];  // 24 and 24
  ASSERT_EQ(middle["no_action_windows"], 24);
  ASSERT_EQ(middle["action_windows"], 24);
  bool same = false;
  for (const auto& p : poolings)
    same = same || p == middle;
  EXPECT_TRUE(same) << "the windows' candidate at 24 and 24 is the chosen pooling's run at 24 and 24";

  // train learns the class from the same streams (from the cache) when asked: one class more.
  const std::string base = kBin + "/train --synth ias --people 3 --repetitions 1 --actions wave,kick,sit_down" +
                           " --stream-actions 2 --cache '" + cache + "' --jobs 2 --output '" + out + "/m.model'";
  const Result closed = run(base);
  ASSERT_EQ(closed.status, 0) << closed.output;
  EXPECT_NE(closed.output.find(" 3 actions"), std::string::npos) << closed.output;
  const Result open = run(base + " --no-action-windows 6");
  ASSERT_EQ(open.status, 0) << open.output;
  EXPECT_NE(open.output.find(" 4 actions"), std::string::npos) << open.output;
  EXPECT_NE(open.output.find("no-action samples"), std::string::npos) << open.output;
  EXPECT_NE(open.output.find("3 streams of the training people"), std::string::npos) << open.output;
  // --training-streams: that many streams of each training person.
  const Result twice = run(base + " --no-action-windows 6 --training-streams 2");
  ASSERT_EQ(twice.status, 0) << twice.output;
  EXPECT_NE(twice.output.find("6 streams of the training people"), std::string::npos) << twice.output;
  // Action windows add samples of the actions it knows, no class (all 15, so that the streams'
  // actions are among them).
  const auto sequences = [](const std::string& output) {
    const std::size_t at = output.find("recognizer ");
    const std::size_t comma = output.find(", ", at);
    return at == std::string::npos || comma == std::string::npos ? -1 : std::stoi(output.substr(comma + 2));
  };
  const std::string all = kBin + "/train --synth ias --people 3 --repetitions 1 --stream-actions 2 --cache '" + cache +
                          "' --jobs 2 --output '" + out + "/all.model'";
  const Result segmented = run(all);
  ASSERT_EQ(segmented.status, 0) << segmented.output;
  const Result in_context = run(all + " --action-windows 6");
  ASSERT_EQ(in_context.status, 0) << in_context.output;
  EXPECT_NE(in_context.output.find(" 15 actions"), std::string::npos) << in_context.output;
  EXPECT_GT(sequences(in_context.output), sequences(segmented.output)) << in_context.output << segmented.output;

  // Out of range: a usage error naming the option.
  const Result bad = run(kBin + "/evaluate --synth ias --protocol online --stream-actions 1 --output '" + out + "'");
  EXPECT_EQ(WEXITSTATUS(bad.status), 2) << bad.output;
  EXPECT_NE(bad.output.find("--stream-actions"), std::string::npos) << bad.output;
}

TEST(Tools, CrowdProtocolScoresEachNewPersonAloneAndAmongOthers)
{
  // evaluate --protocol crowd end to end, small: a model of 2 training actors (every action once),
  // one 12 s scene of 2 new actors (p03, p04: scene 1 would be the training people), each action
  // recognised with the person alone in view and with both in view.
  const std::string out = tempDir("crowd"), cache = tempDir("crowd_cache");
  const Result r = run(kBin + "/evaluate --synth ias --people 2 --repetitions 1 --protocol crowd --crowd-people 2" +
                       " --crowd-seconds 12 --scenes 1 --variants posture_flow --no-plots --output '" + out +
                       "' --cache '" + cache + "' --jobs 2");
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(out + "/crowd.json");
  ASSERT_TRUE(in.good()) << "no crowd.json: " << r.output;
  const nlohmann::json report = nlohmann::json::parse(in);
  EXPECT_EQ(report["training"]["people"], (std::vector<std::string>{ "p01", "p02" }));
  ASSERT_EQ(report["scenes"].size(), 1u);
  EXPECT_EQ(report["scenes"][0]["actors"], "p03+p04") << "the scene's actors are none of the training people";
  ASSERT_EQ(report["variants"].size(), 1u);
  const nlohmann::json& v = report["variants"][0];
  const int segments = v["segments"];
  EXPECT_GE(segments, 2) << "a 12 s scene holds a few actions of each person";
  int per_person = 0;
  for (const auto& p : v["per_person"])
  {
    per_person += p["segments"].get<int>();
    const std::string who = p["person"];
    EXPECT_TRUE(who == "crowd2_2/p03" || who == "crowd2_2/p04") << who;
  }
  EXPECT_EQ(per_person, segments);
  for (const char* key : { "alone", "together" })
  {
    EXPECT_GE(v[key].get<double>(), 0.0) << key;
    EXPECT_LE(v[key].get<double>(), 1.0) << key;
  }
  EXPECT_NEAR(v["difference"].get<double>(), v["together"].get<double>() - v["alone"].get<double>(), 1e-9);
  // Both confusion matrices count every scored action once, "untracked" included.
  for (const char* key : { "alone_confusion", "together_confusion" })
  {
    int total = 0;
    for (const auto& row : v[key]["matrix"])
      for (int n : row)
        total += n;
    EXPECT_EQ(total, segments) << key;
    EXPECT_EQ(v[key]["labels"].back(), "untracked");
  }
  // One line per scored action; alone, one person at 1-5 m in an empty room is always followed.
  std::ifstream csv(out + "/segments.csv");
  std::string line;
  std::getline(csv, line);
  int lines = 0, in_plain_view = 0;
  while (std::getline(csv, line))
  {
    ++lines;
    std::vector<std::string> fields;
    for (std::size_t at = 0, comma; at <= line.size(); at = comma + 1)
    {
      comma = std::min(line.find(',', at), line.size());
      fields.push_back(line.substr(at, comma - at));
    }
    ASSERT_EQ(fields.size(), 13u) << line;
    EXPECT_NE(fields[9], "untracked") << line;  // the label alone
    EXPECT_NE(fields[11], "0") << line;         // the track alone
    in_plain_view += std::stod(fields[8]) >= 0.9 ? 1 : 0;  // shown together
  }
  EXPECT_EQ(lines, segments);
  // The actions in plain view with everyone there (shown together in 90% of their frames or more).
  EXPECT_EQ(report["visible_share"], 0.9);
  EXPECT_EQ(v["visible"]["segments"], in_plain_view);
  EXPECT_NEAR(v["visible"]["difference"].get<double>(),
              v["visible"]["together"].get<double>() - v["visible"]["alone"].get<double>(), 1e-9);
  std::ifstream matrix(out + "/crowd_confusion_posture_flow_together.csv");
  EXPECT_TRUE(matrix.good());

  // Usage errors name what was wrong.
  const Result count = run(kBin + "/evaluate --synth ias --protocol crowd --crowd-people 7 --output '" + out + "'");
  EXPECT_EQ(WEXITSTATUS(count.status), 2) << count.output;
  EXPECT_NE(count.output.find("--crowd-people"), std::string::npos) << count.output;
  const Result joints = run(kBin + "/evaluate --synth ias --protocol crowd --variants joints --output '" + out + "'");
  EXPECT_EQ(WEXITSTATUS(joints.status), 2) << joints.output;
  EXPECT_NE(joints.output.find("joint"), std::string::npos) << joints.output;
}
