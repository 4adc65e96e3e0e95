// Where the tools get samples from: bags listed in a dataset index (this file) or the virtual
// Kinect rendering in-process.
#pragma once

#include "feature_extractor.h"
#include <action_flow/synth/synth.h>

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
/** A sample the tools can open any number of times. */
struct SampleRef
{
  std::string key;          // unique and file-name safe, e.g. "p03_wave_2"
  std::string person, action;
  int repetition = 0;
  std::string fingerprint;  // changes when the sample's content would (file size+mtime, renderer version)
  std::string skeleton_file;  // MSR Action3D samples: the skeleton file they were rendered from
  int copy = 0;               // a training copy (synth::SampleSpec::copy): it trains, it is never tested
  std::string where;          // for messages: the bag's path, or "rendered <key>"
  bool all_tracks = false;    // a stream: every track's descriptors, not only the performer's
  std::function<std::unique_ptr<FrameSource>()> open;
};

/** Topics of a bag in the IAS-Lab layout. */
struct BagTopics
{
  std::string points = "/camera/depth_registered/points";
  std::string depth = "/camera/depth_registered/image_raw";
  std::string rgb = "/camera/rgb/image_color";
  std::string info = "/camera/rgb/camera_info";
};

/** The samples of a dataset index (bags); @throws DatasetError naming the line. */
std::vector<SampleRef> samplesFromIndex(const std::string& index, const BagTopics& topics,
                                        const std::vector<std::string>& known_actions = {});

}  // namespace tools
}  // namespace action_flow

namespace action_flow
{
namespace tools
{
class Args;
class Options;
/** Adds the options that choose samples (--index, topic names, --synth ...). */
void addSampleOptions(Options& o);
/** The virtual Kinect's samples (--synth ias|msr, --people, --repetitions, --seed, --msr-dir, --max-frames). */
std::vector<SampleRef> samplesFromSynth(const Args& args);
/** A sample rendered by the virtual Kinect in-process (any dataset, streams included). */
SampleRef renderedSample(const synth::SampleSpec& spec);
/**
 * The cross-view evaluation's samples (--protocol cross-view, --synth ias): the training people
 * (--train-persons, default the first half of --people) facing the camera, 0 +- 15 degrees
 * (--train-spread: 180 trains on every side, the augmentation the virtual Kinect makes cheap),
 * --repetitions takes each; every other person at 0 (+- 15) and at each of --views (default
 * 45,90,135,180, turned to their left or right), --test-repetitions takes each (default 1).
 */
struct CrossViewSet
{
  std::vector<SampleRef> samples;
  std::vector<int> view_of;   // per sample: the index into views, or -1 for a training sample
  std::vector<double> views;  // degrees; views[0] is 0 (frontal)
  double train_spread = 15.0; // degrees either side of facing the camera, for the training people
};
CrossViewSet crossViewSamples(const Args& args);
/** The samples the options name (--actions and --persons keep only those listed). @throws on a bad index or option, naming it. */
std::vector<SampleRef> selectSamples(const Args& args);
/** The default cross-subject training subjects: MSR Action3D's odd subjects, as the dataset's papers split it. */
constexpr const char* kDefaultTrainPersons = "s01,s03,s05,s07,s09";
/** The cross-subject (and online msr) training subjects: --train-persons, default kDefaultTrainPersons. */
std::vector<std::string> trainPersons(const Args& args);
/** The cache folder the options name (default ~/.ros/action_flow/cache). */
std::string cacheDir(const Args& args);
}  // namespace tools
}  // namespace action_flow
