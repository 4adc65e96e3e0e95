// evaluate: runs a protocol (leave-one-person-out, or MSR Action3D's cross-subject) over the
// default recognizer, its ablations, the paper's variants and (for MSR Action3D) a joint-position
// baseline, and writes a report folder: report.json, confusion matrices (CSV and PNG), the paper's
// accuracy against frames per sequence (its Figure 8) and an ablation table.
#include "../offline/cli.h"
#include "../offline/plot_script.h"
#include "../offline/extraction.h"
#include "../offline/detection_protocol.h"
#include "../offline/online_protocol.h"
#include "../offline/sample_sources.h"
#include "../offline/crowd_protocol.h"
#include "../offline/variant_report.h"

#include <action_flow/files.h>
#include <action_flow/synth/skeleton.h>


#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <fstream>

using namespace action_flow;
using namespace action_flow::tools;
using json = nlohmann::json;

namespace
{
Options options()
{
  Options o("usage: evaluate --output DIR (--index INDEX.csv | --synth ias|msr [sample options]) [options]");
  o.value("output", "DIR", "where the report, confusion matrices and pictures go")
      .value("protocol", "lopo|cross-subject|cross-view|online|crowd|detection",
             "leave-one-person-out (default), train on --train-persons, train on people facing the camera and "
             "test others seen from the side and behind, labels on continuous streams of new people, several "
             "new people at once against each alone, or the people tracker alone (see below)")
      .value("views", "a,b,...", "cross-view: the test views, degrees from frontal (default 45,90,135,180)")
      .value("test-repetitions", "R", "cross-view: repetitions of each test person's actions (default 1)")
      .value("train-spread", "DEG", "cross-view: the training people face the camera +- DEG (default 15; 180 = seen "
                                    "from every side)")
      .value("train-persons", "a,b,...", std::string("cross-subject and online msr: the training people (default ") +
                                         kDefaultTrainPersons + "); the others are tested")
      .value("variants", "v1,v2,...",
             "of posture_flow, posture_flow_no_posture, posture_flow_choose_posture, posture_flow_no_geometry, posture_flow_sums, "
             "posture_flow_bins, posture_flow_single_level, posture_flow_no_pyramid, posture_flow_means_only, posture_flow_no_fourier, posture_flow_nn, "
             "posture_flow_no_mirror, posture_flow_mirror, meanflow, sumflow_raw, sumflow, sumflow_pca, joints (MSR "
             "Action3D only) (default: all; online: posture_flow and/or sumflow)")
      .value("sweep", "N", "the paper's accuracy for 1..N frames, with and without PCA (default 40, cross-view 0; "
                           "0 = none)")
      .value("jobs", "N", "samples processed in parallel (default 2)")
      .value("cache", "DIR", "frame descriptor cache (default ~/.ros/action_flow/cache)")
      .flag("no-plots", "write no pictures")
      .flag("allow-empty", "keep samples in which nobody was tracked (as still frames) instead of refusing them");
  addSampleOptions(o);
  addOnlineOptions(o);
  addCrowdOptions(o);
  addDetectionOptions(o);
  addMethodOptions(o);
  return o;
}

using Variant = RecognizerVariant;

// The joint-position baseline's frames of one MSR Action3D skeleton file: per tracked frame the 20
// joints relative to the hip centre and their velocities, both divided by the body's size (the
// mean spine length, shoulder centre to hip centre), at the files' 15 fps.
SampleFrames jointFrames(const std::string& skeleton_file)
{
  const synth::MsrSkeletonFile file = synth::parseMsrSkeletonFile(skeleton_file);
  constexpr int kHipCentre = 6, kShoulderCentre = 2;
  double size = 0.0;
  int n = 0;
  for (std::size_t f = 0; f < file.frames.size(); ++f)
    if (file.tracked[f])
    {
      size += (file.frames[f][kShoulderCentre] - file.frames[f][kHipCentre]).norm();
      ++n;
    }
  if (n < 2 || !(size > 0.0))
    throw std::runtime_error(skeleton_file + ": fewer than 2 tracked frames, or a collapsed skeleton");
  const float scale = static_cast<float>(n / size);
  SampleFrames out;
  std::vector<Eigen::VectorXf> rows;
  Eigen::VectorXf previous;
  for (std::size_t f = 0; f < file.frames.size(); ++f)
  {
    if (!file.tracked[f])
      continue;
    Eigen::VectorXf pos(60);
    for (int j = 0; j < 20; ++j)
      pos.segment<3>(3 * j) = (file.frames[f][j] - file.frames[f][kHipCentre]) * scale;
    Eigen::VectorXf row(120);
    row << pos, (previous.size() ? Eigen::VectorXf((pos - previous) * 15.0f) : Eigen::VectorXf::Zero(60));
    previous = pos;
    rows.push_back(row);
    out.stamps.push_back(static_cast<double>(f) / 15.0);
  }
  out.descriptors.resize(static_cast<Eigen::Index>(rows.size()), 120);
  for (std::size_t r = 0; r < rows.size(); ++r)
    out.descriptors.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  return out;
}

// The joint baseline over the folds: temporal pyramid of the joint frames, linear classifier with
// C chosen inside each fold's training people.
Confusion jointBaseline(const std::vector<SampleRef>& samples, const std::vector<Fold>& folds,
                        std::vector<double>& fold_accuracy)
{
  // A row per original sample; a training copy (a rendering of the same skeleton file) has the
  // same joints, so it has no row and never trains here.
  std::vector<std::string> labels, persons;
  std::vector<Eigen::Index> row_of(samples.size(), -1);
  std::vector<Eigen::VectorXf> rows;
  for (std::size_t i = 0; i < samples.size(); ++i)
  {
    if (samples[i].skeleton_file.empty())
      throw std::invalid_argument("the joints baseline needs MSR Action3D samples (--synth msr)");
    if (samples[i].copy != 0)
      continue;
    const SampleFrames f = jointFrames(samples[i].skeleton_file);
    std::vector<Eigen::VectorXf> frames;
    for (Eigen::Index r = 0; r < f.descriptors.rows(); ++r)
      frames.push_back(f.descriptors.row(r).transpose());
    // Means and maxima of coordinates and speeds as they are (no power normalisation): the baseline's
    // recipe with the default recognizer's pooling, less its Fourier magnitudes, which did not help
    // the joints on MSR Action3D's training subjects (docs/evaluation.md).
    row_of[i] = static_cast<Eigen::Index>(rows.size());
    rows.push_back(temporalPyramid(frames, f.stamps, 3, false, Pooling{ true, 0 }));
    labels.push_back(samples[i].action);
    persons.push_back(samples[i].person);
  }
  Eigen::MatrixXf x(static_cast<Eigen::Index>(rows.size()), rows.empty() ? 0 : rows[0].size());
  for (std::size_t r = 0; r < rows.size(); ++r)
    x.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  Confusion all(uniqueSorted(labels));
  for (const Fold& fold : folds)
  {
    std::vector<Eigen::Index> train;
    for (std::size_t i : fold.train)
      if (row_of[i] >= 0)
        train.push_back(row_of[i]);
    std::vector<std::string> train_labels, train_persons;
    for (auto r : train)
    {
      train_labels.push_back(labels[r]);
      train_persons.push_back(persons[r]);
    }
    const Eigen::MatrixXf xt = x(train, Eigen::all);
    const LinearChoice choice = chooseLinear(xt, nullptr, train_labels, train_persons, { false }, linearCandidates());
    const LinearClassifier c = LinearClassifier::train(xt, train_labels, choice.c).calibrated(choice.temperature);
    Confusion mine(all.labels);
    for (std::size_t t : fold.test)
    {
      const Classification answer = c.classify(x.row(row_of[t]).transpose());
      all.add(labels[row_of[t]], answer.label, answer.confidence);
      mine.add(labels[row_of[t]], answer.label);
    }
    fold_accuracy.push_back(mine.accuracy());
  }
  return all;
}

}  // namespace

// Every variant evaluate knows, and the frame descriptor sets they read.
struct VariantTable
{
  std::vector<RecognitionParams> extractions;
  std::vector<Variant> all;
};

VariantTable variantTable(const RecognitionParams& base)
{
  // The paper's variants (Figure 7): three sets of frame descriptors cover all four; the default
  // recognizer and its ablations share a fourth. All four share one flow matching per frame.
  RecognitionParams sum = base, mean = base, raw = base;
  sum.recognizer = mean.recognizer = raw.recognizer = Recognizer::Paper;
  sum.grid.aggregation = raw.grid.aggregation = FlowAggregation::Sum;
  mean.grid.aggregation = FlowAggregation::Mean;
  sum.use_pca = mean.use_pca = raw.use_pca = false;
  raw.flow.reject_outliers = false;
  RecognitionParams pca = sum;
  pca.use_pca = true;
  RecognitionParams pf = base;
  pf.recognizer = Recognizer::PostureFlow;
  const auto ablation = [&](auto change) {
    RecognitionParams p = pf;
    change(p.pyramid);
    return p;
  };
  return { { sum, mean, raw, pf }, {
    { "posture_flow", "posture_flow (default)", pf, 3 },
    { "posture_flow_no_posture", "posture_flow without posture",
      ablation([](PyramidParams& p) { p.posture = PostureMode::Off; }), 3 },
    { "posture_flow_choose_posture", "posture_flow, posture chosen by cross-validation",
      ablation([](PyramidParams& p) { p.posture = PostureMode::Choose; }), 3 },
    { "posture_flow_no_geometry", "posture_flow without the body geometry",
      ablation([](PyramidParams& p) { p.geometry = false; }), 3 },
    { "posture_flow_sums", "posture_flow, always signed flow sums",
      ablation([](PyramidParams& p) { p.flow = FlowEncoding::Sums; }), 3 },
    { "posture_flow_bins", "posture_flow, always direction bins",
      ablation([](PyramidParams& p) { p.flow = FlowEncoding::Bins; }), 3 },
    { "posture_flow_single_level", "posture_flow, 4x4x4 grid only",
      ablation([](PyramidParams& p) { p.coarse_to_fine = false; }), 3 },
    { "posture_flow_no_pyramid", "posture_flow, whole-sequence mean only",
      ablation([](PyramidParams& p) { p.temporal_levels = 1; }), 3 },
    { "posture_flow_means_only", "posture_flow, pyramid of means only (no maxima, no Fourier)",
      ablation([](PyramidParams& p) {
        p.max_pooling = false;
        p.fourier = 0;
      }), 3 },
    { "posture_flow_no_fourier", "posture_flow, pyramid of means and maxima (no Fourier)",
      ablation([](PyramidParams& p) { p.fourier = 0; }), 3 },
    { "posture_flow_nn", "posture_flow, 1-NN instead of the linear classifier",
      ablation([](PyramidParams& p) { p.classifier = PyramidClassifier::Nearest; }), 3 },
    { "posture_flow_no_mirror", "posture_flow, never mirrored training copies",
      ablation([](PyramidParams& p) { p.mirror = MirrorMode::Off; }), 3 },
    { "posture_flow_mirror", "posture_flow, always mirrored training copies",
      ablation([](PyramidParams& p) { p.mirror = MirrorMode::On; }), 3 },
    { "meanflow", "paper: MEANFLOW", mean, 1 },
    { "sumflow_raw", "paper: SUMFLOW without outlier rejection", raw, 2 },
    { "sumflow", "paper: SUMFLOW", sum, 0 },
    { "sumflow_pca", "paper: SUMFLOW with PCA", pca, 0 },
    { "joints", "joint-position baseline (skeleton files, not clouds)", pf, 0 } } };
}

// The variants --variants names (default: @p names, or all, the joint baseline only for MSR Action3D).
std::vector<Variant> selectVariants(const std::vector<Variant>& all, const Args& args, std::string names = "")
{
  std::vector<Variant> variants;
  const bool every = names.empty();
  for (const auto& v : all)
    if (every && (v.name != "joints" || args.get("synth") == "msr"))
      names += (names.empty() ? "" : ",") + v.name;
  const auto wanted = splitList(args.get("variants", names));
  for (const auto& w : wanted)
  {
    const auto it = std::find_if(all.begin(), all.end(), [&](const Variant& v) { return v.name == w; });
    if (it == all.end())
      throw UsageError("unknown variant '" + w + "'");
    variants.push_back(*it);
  }

  return variants;
}

// Cross-view: one fold per view, all with the same training samples (those facing the camera).
std::vector<Fold> crossViewFolds(const CrossViewSet& set)
{
  std::vector<Fold> folds(set.views.size());
  std::vector<std::size_t> train;
  for (std::size_t i = 0; i < set.view_of.size(); ++i)
    if (set.view_of[i] < 0)
      train.push_back(i);
    else
      folds[static_cast<std::size_t>(set.view_of[i])].test.push_back(i);
  for (std::size_t v = 0; v < folds.size(); ++v)
  {
    char name[48];
    std::snprintf(name, sizeof name, "view %g degrees", set.views[v]);
    folds[v].name = name;
    folds[v].train = train;
  }
  return folds;
}

// Cross-view: each variant's accuracy per view (its fold accuracies), printed as a table too;
// @p turned: the tracker turned the grid to each person's facing.
json crossViewTable(const CrossViewSet& set, bool turned, const json& results)
{
  const char* grid = turned ? "turned to the facing" : "camera-aligned";
  json table = { { "views", set.views },
                 { "train_spread", set.train_spread },
                 { "grid", grid },
                 { "accuracy", json::object() } };
  std::printf("\ncross-view accuracy (%%), trained facing 0 +- %g degrees, grid %s:\n%-28s", set.train_spread, grid,
              "variant");
  for (double v : set.views)
    std::printf(" %7g", v);
  std::printf("\n");
  for (const json& r : results)
  {
    table["accuracy"][r["variant"].get<std::string>()] = r["fold_accuracy"];
    std::printf("%-28s", r["variant"].get<std::string>().c_str());
    for (const json& a : r["fold_accuracy"])
      std::printf(" %7.1f", 100.0 * a.get<double>());
    std::printf("\n");
  }
  return table;
}

namespace
{
std::vector<LabelledSample> labelledSamples(const std::vector<SampleRef>& samples, const std::vector<SampleFrames>& frames)
{
  std::vector<LabelledSample> out;
  for (std::size_t i = 0; i < samples.size(); ++i)
    out.push_back({ samples[i].person, samples[i].action, &frames[i], samples[i].copy > 0 });
  return out;
}

std::vector<std::string> personsOf(const std::vector<SampleRef>& samples)
{
  std::vector<std::string> persons;
  for (const auto& s : samples)
    persons.push_back(s.person);
  return persons;
}

// The protocol's folds; training copies (--training-copies) train with their person and are never tested.
std::vector<Fold> protocolFolds(const std::string& protocol, const std::vector<SampleRef>& samples, const Args& args,
                                const CrossViewSet& cross_view)
{
  const std::vector<std::string> persons = personsOf(samples);
  std::vector<Fold> folds;
  if (protocol == "lopo")
    folds = leaveOnePersonOut(persons);
  else if (protocol == "cross-subject")
    folds = { crossSubject(persons, trainPersons(args)) };
  else if (protocol == "cross-view")
    folds = crossViewFolds(cross_view);
  else
    throw UsageError("unknown protocol '" + protocol + "' (lopo, cross-subject, cross-view, online, crowd or detection)");
  for (Fold& fold : folds)
    fold.test.erase(std::remove_if(fold.test.begin(), fold.test.end(), [&](std::size_t t) { return samples[t].copy > 0; }),
                    fold.test.end());
  return folds;
}

// Each variant over the folds: its accuracy, per-fold accuracies, confusion matrix (also written
// as DIR/confusion_<variant>.csv) and time.
json variantResults(const std::vector<Variant>& variants, const std::vector<SampleRef>& samples,
                    const std::vector<std::vector<SampleFrames>>& frames, const std::vector<Fold>& folds, int jobs,
                    const std::string& dir, std::vector<Pca>& fold_pcas)
{
  json results = json::array();
  // Variants that ask the same model-selection question on the same folds (the one choosing
  // posture asks those of posture on and off) have it answered once.
  SelectionMemo memo;
  for (const auto& v : variants)
  {
    std::vector<double> fold_acc;
    std::vector<PyramidParams> choices;
    const auto v0 = std::chrono::steady_clock::now();
    const Confusion c = v.name == "joints" ? jointBaseline(samples, folds, fold_acc)
                                           : runFolds(labelledSamples(samples, frames[v.extraction]), folds, v.params,
                                                      &fold_acc, &fold_pcas, jobs, &choices, &memo);
    double mean_fold = 0.0;
    for (double a : fold_acc)
      mean_fold += a / fold_acc.size();
    results.push_back({ { "variant", v.name },
                        { "title", v.title },
                        { "accuracy", c.accuracy() },
                        { "mean_fold_accuracy", mean_fold },
                        { "fold_accuracy", fold_acc },
                        { "confusion", confusionJson(c) },
                        { "seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - v0).count() },
                        { "pca_components", nullptr } });
    if (v.params.use_pca && !fold_pcas.empty())
      results.back()["pca_components"] = fold_pcas.front().outputSize();
    if (v.name != "joints" && v.params.recognizer == Recognizer::PostureFlow &&
        v.params.pyramid.classifier == PyramidClassifier::Linear)
    {
      // What each fold's cross-validation chose, and how often each choice was made.
      json per_fold = json::array();
      int posture = 0, mirror = 0, bins = 0;
      for (const PyramidParams& p : choices)
      {
        per_fold.push_back({ { "c", p.c },
                             { "mirror", paramText(p.mirror) },
                             { "posture", paramText(p.posture) },
                             { "flow", paramText(p.flow) } });
        posture += p.posture == PostureMode::On;
        mirror += p.mirror == MirrorMode::On;
        bins += p.flow == FlowEncoding::Bins;
      }
      results.back()["fold_choices"] = per_fold;
      std::printf("  %s: chosen in %zu folds: posture %d, mirrored copies %d, direction bins %d\n", v.name.c_str(),
                  choices.size(), posture, mirror, bins);
    }
    writeTextAtomically(dir + "/confusion_" + v.name + ".csv", confusionCsv(c));
    std::printf("%-58s accuracy %5.1f%%  (mean over folds %5.1f%%)\n", v.title.c_str(), 100 * c.accuracy(),
                100 * mean_fold);
  }
  return results;
}

// The paper's accuracy for 1..sweep frames per sequence, without and with PCA.
json framesSweep(const RecognitionParams& sum, const RecognitionParams& pca, const std::vector<LabelledSample>& samples,
                 const std::vector<Fold>& folds, int sweep, std::vector<Pca>& fold_pcas)
{
  json curve = { { "frames", json::array() }, { "sumflow", json::array() }, { "sumflow_pca", json::array() } };
  for (int f = 1; f <= sweep; ++f)
  {
    RecognitionParams a = sum, b = pca;
    a.frames = b.frames = f;
    curve["frames"].push_back(f);
    curve["sumflow"].push_back(runFolds(samples, folds, a).accuracy());
    curve["sumflow_pca"].push_back(runFolds(samples, folds, b, nullptr, &fold_pcas).accuracy());
    if (f % 10 == 0 || f == sweep)
      std::fprintf(stderr, "  paper's frames sweep: %d/%d\n", f, sweep);
  }
  return curve;
}

/** A classification protocol's command line, every option checked, and the samples it names. */
struct Evaluation
{
  RecognitionParams base;
  int jobs = 0;
  std::string protocol;
  int sweep = 0;
  TrackerParams tracker;
  CrossViewSet cross_view;
  std::vector<SampleRef> samples;
};

Evaluation parseEvaluation(const Args& args)
{
  Evaluation e;
  e.base = methodParams(args);
  e.jobs = jobsOption(args);
  e.protocol = args.get("protocol", "lopo");
  e.sweep = static_cast<int>(args.integer("sweep", e.protocol == "cross-view" ? 0 : 40, 0, 200));
  e.tracker = trackerParams(args);
  if (e.protocol == "cross-view")
    e.cross_view = crossViewSamples(args);
  e.samples = e.protocol == "cross-view" ? e.cross_view.samples : selectSamples(args);
  if (e.samples.empty())
    throw std::invalid_argument("no samples to evaluate");
  return e;
}

// The report's opening: the protocol, its folds and its samples.
json reportHead(const Evaluation& e, const std::vector<std::string>& persons,
                const std::vector<Fold>& folds, const std::vector<SampleFrames>& frames)
{
  std::size_t no_flow = 0;
  for (const auto& f : frames)
    no_flow += f.descriptors.rows() == 0;
  json report;
  report["protocol"] = e.protocol;
  report["folds"] = folds.size();
  report["samples"] = { { "total", e.samples.size() },
                        { "people", uniqueSorted(persons).size() },
                        { "without_flow", no_flow },
                        { "train_per_fold", folds.front().train.size() },
                        { "test_per_fold", folds.front().test.size() } };
  report["frames"] = e.base.frames;
  return report;
}

// Every variant over the folds (their confusion matrices into dir), the cross-view table and the
// paper's frames sweep, into the report.
void classifyVariants(const Evaluation& e, const VariantTable& table,
                      const std::vector<Variant>& variants, const std::vector<Fold>& folds,
                      const std::vector<std::vector<SampleFrames>>& frames, const std::string& dir,
                      json& report)
{
  const RecognitionParams& sum = table.extractions[0];
  RecognitionParams pca = sum;
  pca.use_pca = true;
  // The PCA basis of each fold, fitted once on its frame descriptors (it does not depend on F),
  // serves the PCA variant and the whole frames sweep.
  std::vector<Pca> fold_pcas;
  const json results = variantResults(variants, e.samples, frames, folds, e.jobs, dir, fold_pcas);
  report["variants"] = results;
  if (e.protocol == "cross-view")
    report["cross_view"] = crossViewTable(e.cross_view, e.tracker.align_to_facing, results);
  if (e.sweep > 0)
    report["frames_sweep"] =
        framesSweep(sum, pca, labelledSamples(e.samples, frames[0]), folds, e.sweep, fold_pcas);
}

// The timing into the report, DIR/report.json, then (unless --no-plots) the report's pictures.
void writeReport(const Args& args, const std::string& dir, json& report, int jobs,
                 std::chrono::steady_clock::time_point t0, std::chrono::steady_clock::time_point t1)
{
  const auto t2 = std::chrono::steady_clock::now();
  report["timing"] = { { "descriptors_s", std::chrono::duration<double>(t1 - t0).count() },
                       { "classification_s", std::chrono::duration<double>(t2 - t1).count() },
                       { "total_s", std::chrono::duration<double>(t2 - t0).count() },
                       { "jobs", jobs } };
  writeTextAtomically(dir + "/report.json", report.dump(2) + "\n");
  std::printf("evaluate: report in %s/report.json (%.0f s)\n", dir.c_str(),
              std::chrono::duration<double>(t2 - t0).count());
  if (!args.has("no-plots"))
    tools::runPlotScript("plot_report.py", { dir });
}

}  // namespace

int main(int argc, char** argv)
{
  return runTool("evaluate", [&]() -> int {
    const Options o = options();
    const Args args(argc, argv, o);
    if (args.has("help") || !args.has("output"))
      return o.printHelp(!args.has("help"));
    if (args.get("protocol") == "detection")  // the people tracker alone, on scenes of its own
      return runDetectionProtocol(args, args.get("output"));
    const auto t0 = std::chrono::steady_clock::now();
    const Evaluation e = parseEvaluation(args);  // every option is checked before any work starts
    makeOutputDir(args.get("output"));            // and the output folder made, not after hours of work
    if (args.get("protocol") == "online")
      return runOnlineProtocol(args, e.samples, args.get("output"));
    const VariantTable table = variantTable(e.base);
    if (args.get("protocol") == "crowd")  // the default and the paper's, unless --variants
      return runCrowdProtocol(args, e.samples, table.extractions,
                              selectVariants(table.all, args, "posture_flow,sumflow_pca"), args.get("output"));
    const std::vector<Variant> variants = selectVariants(table.all, args);
    installInterruptHandler();
    const std::vector<std::string> persons = personsOf(e.samples);
    const std::vector<Fold> folds = protocolFolds(e.protocol, e.samples, args, e.cross_view);
    std::fprintf(stderr, "evaluate: %zu samples, %zu people, %zu folds (%s)\n", e.samples.size(),
                 uniqueSorted(persons).size(), folds.size(), e.protocol.c_str());

    const auto frames = extractAll(e.samples, table.extractions, e.tracker, cacheDir(args), e.jobs);
    refuseEmptySamples(e.samples, frames[0], args.has("allow-empty"));
    const auto t1 = std::chrono::steady_clock::now();

    const std::string dir = args.get("output");
    json report = reportHead(e, persons, folds, frames[0]);
    classifyVariants(e, table, variants, folds, frames, dir, report);
    writeReport(args, dir, report, e.jobs, t0, t1);
    return 0;
  });
}
