// train: a dataset (bags listed in an index, or the virtual Kinect rendering in-process) in, a
// model file out. Same code path as the live pipeline: tracker -> flow -> frame descriptor ->
// sequence descriptor -> classifier.
#include "../eval/no_action.h"
#include "../offline/cli.h"
#include "../offline/extraction.h"
#include "../offline/online_protocol.h"
#include "../offline/sample_sources.h"

#include <cstdio>
#include <deque>
#include <iostream>

using namespace action_flow;
using namespace action_flow::tools;

namespace
{
Options options()
{
  Options o("usage: train --output MODEL (--index INDEX.csv | --synth ias|msr [sample options]) [options]");
  o.value("output", "MODEL", "the model file to write")
      .flag("allow-empty", "keep samples in which nobody was tracked (as still frames) instead of refusing them")
      .value("exclude-person", "P", "leave one person out of the training set")
      .value("jobs", "N", "samples processed in parallel (default 2)")
      .value("cache", "DIR", "frame descriptor cache (default ~/.ros/action_flow/cache)")
      .value("no-action-windows", "N",
             "--synth ias|msr: also learn the class no_action from up to N windows of transitions and idle "
             "periods in the continuous streams of each training person (for the online mode; default 0: none)")
      .value("action-windows", "N",
             "--synth ias|msr: also learn each action from up to N 3 s windows of that stream that hold it with "
             "the transitions around it (default 0: none)")
      .value("stream-actions", "N", "actions in each of those streams (default 8)")
      .value("training-streams", "N", "streams of each training person to take those windows from (default 1)")
      .flag("list-params", "print every parameter (name, type, default, doc) as markdown and exit");
  addSampleOptions(o);
  addMethodOptions(o);
  return o;
}
}  // namespace

int main(int argc, char** argv)
{
  return runTool("train", [&]() -> int {
    const Options o = options();
    const Args args(argc, argv, o);
    if (args.has("list-params"))
    {
      std::fputs(paramsMarkdown().c_str(), stdout);
      return 0;
    }
    if (args.has("help") || !args.has("output"))
      return o.printHelp(!args.has("help"));
    const RecognitionParams params = methodParams(args);
    const int jobs = jobsOption(args);
    const TrackerParams tracker = trackerParams(args);
    std::vector<SampleRef> samples = selectSamples(args);
    if (args.has("exclude-person"))
    {
      std::vector<SampleRef> kept;
      for (auto& s : samples)
        if (s.person != args.get("exclude-person"))
          kept.push_back(std::move(s));
      samples = std::move(kept);
    }
    if (samples.empty())
      throw std::invalid_argument("no samples to train on");
    installInterruptHandler();
    std::fprintf(stderr, "train: %zu samples\n", samples.size());
    const auto frames = extractAll(samples, { params }, tracker, cacheDir(args), jobs);
    refuseEmptySamples(samples, frames[0], args.has("allow-empty"));
    std::vector<LabelledSample> labelled;
    std::vector<std::size_t> rows;
    for (std::size_t i = 0; i < samples.size(); ++i)
    {
      labelled.push_back({ samples[i].person, samples[i].action, &frames[0][i] });
      rows.push_back(i);
    }
    std::deque<SampleFrames> windows;
    StreamWindowCounts counts;
    counts.no_action = static_cast<int>(args.integer("no-action-windows", 0, 0, 100));
    counts.action = static_cast<int>(args.integer("action-windows", 0, 0, 100));
    if (counts.no_action > 0 || counts.action > 0)
    {
      const std::size_t added = appendStreamWindows(args, samples, counts, params, labelled, rows, windows);
      const std::size_t idle = noActionCount(labelled);
      std::fprintf(stderr, "train: %zu no-action samples, %zu action windows from the streams\n", idle, added - idle);
    }
    const ActionModel model = trainModel(labelled, rows, params);
    model.save(args.get("output"));
    std::printf("train: wrote %s: recognizer %s, %zu sequences, %zu actions, descriptor length %ld%s\n",
                args.get("output").c_str(), toString(model.params.recognizer).c_str(), model.labels.size(),
                model.classifier().classes().size(), static_cast<long>(model.descriptors.cols()),
                model.pca.empty() ? "" : (" (PCA " + std::to_string(model.pca.outputSize()) + " per frame)").c_str());
    if (!model.linear.empty())
      std::printf("train: linear classifier, C = %g (%s), mirrored training copies %s, posture %s, flow as %s\n",
                  model.params.pyramid.c,
                  params.pyramid.c > 0 ? "given" : "chosen by cross-validation over the training people",
                  model.params.pyramid.mirror == MirrorMode::On ? "used" : "not used",
                  model.params.pyramid.posture == PostureMode::On ? "used" : "not used",
                  model.params.pyramid.flow == FlowEncoding::Bins ? "direction bins" : "signed sums");
    return 0;
  });
}
