// Fuzz corpus, in-process part: malformed messages against the input checks (and the tracker core
// behind them), malformed bags through the tools' bag reader and feature pipeline, damaged models
// through ActionModel::load, malformed index CSVs through readIndex and malformed MSR skeleton files
// through the parser and the renderer. Every input runs in a forked child with a timeout: a signal
// is a crash, the timeout a hang; a wrong answer is a failure. See harness.h for the long mode.
#include "generators.h"
#include "harness.h"

#include "../../src/offline/sample_sources.h"

#include <action_flow/action_model.h>
#include "../../src/eval/evaluation.h"
#include "../../src/offline/feature_extractor.h"
#include <action_flow/files.h>
#include <action_flow/people_tracker.h>
#include <action_flow/ros/input_checks.h>
#include <action_flow/synth/skeleton.h>
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

using namespace action_flow;
using namespace action_flow::fuzz;

namespace
{
constexpr double kTimeout = 20.0;  // seconds per input (generous: the machine may be busy)

void writeFile(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

/** Fails the test with the tally's first failures, after printing the tally. */
void finish(const Tally& t)
{
  t.print();
  std::string first;
  for (const auto& f : t.firstFailures())
    first += f + "\n";
  EXPECT_EQ(t.unexpected(), 0) << t.unexpected() << " inputs failed; the first:\n" << first;
}

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

// ---- messages: what a check passes must be safe to read as its header says ---------------------

std::string cloudVerdict(const sensor_msgs::PointCloud2& m)
{
  const std::string error = checkPointCloud2(m);
  InputCloud in;
  InputCloud::fromWire(m, in);
  if (in.error != error)
    return "fromWire's error '" + in.error + "' differs from the check's '" + error + "'";
  if (!error.empty())
    return in.cloud ? "refused (" + error + ") but converted" : "";
  if (!in.cloud)
    return "accepted but not converted";
  // Accepted: every field a reader uses lies inside each point. PCL's conversion, like any reader
  // matching by name and type, uses the first field of each name that is one FLOAT32 (count 1, or 0).
  for (const char* name : { "x", "y", "z", "rgb", "rgba" })
    for (const auto& f : m.fields)
      if (f.name == name && f.datatype == sensor_msgs::PointField::FLOAT32 && f.count <= 1)
      {
        if (static_cast<std::uint64_t>(f.offset) + 4 > m.point_step)
          return "accepted a cloud whose FLOAT32 field '" + f.name + "' (the one a reader uses) lies at offset " +
                 std::to_string(f.offset) + ", beyond its point_step " + std::to_string(m.point_step);
        break;
      }
  if (in.cloud->size() != static_cast<std::size_t>(m.width) * m.height)
    return "converted to " + std::to_string(in.cloud->size()) + " points, the header says " +
           std::to_string(static_cast<std::uint64_t>(m.width) * m.height);
  // The tracker core takes whatever the checks pass: NaN-only, infinite, empty and unorganized clouds.
  PeopleTracker tracker;
  for (int k = 0; k < 3; ++k)
    tracker.update(*in.cloud, m.header.stamp.toSec() + k * 0.1);
  return "";
}

std::string imageVerdict(const sensor_msgs::Image& m)
{
  static const std::map<std::string, std::uint64_t> bytes = { { "rgb8", 3 },  { "bgr8", 3 },   { "rgba8", 4 },
                                                              { "bgra8", 4 }, { "mono8", 1 },  { "mono16", 2 },
                                                              { "16UC1", 2 }, { "32FC1", 4 } };
  const std::string error = checkImage(m);
  if (!error.empty())
    return "";
  const auto it = bytes.find(m.encoding);
  if (it == bytes.end())
    return "accepted the unknown encoding '" + m.encoding + "'";
  if (m.width == 0 || m.height == 0)
    return "accepted a " + std::to_string(m.width) + "x" + std::to_string(m.height) + " image";
  if (static_cast<std::uint64_t>(m.width) * it->second > m.step ||
      static_cast<std::uint64_t>(m.height - 1) * m.step + static_cast<std::uint64_t>(m.width) * it->second > m.data.size())
    return "accepted an image whose pixels lie beyond its data";
  return "";
}

std::string infoVerdict(const sensor_msgs::CameraInfo& m)
{
  if (!checkCameraInfo(m).empty())
    return "";
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(m.K[0]) || !positive(m.K[4]) || !std::isfinite(m.K[2]) || !std::isfinite(m.K[5]) || m.width == 0 ||
      m.height == 0)
    return "accepted a camera_info with unusable intrinsics or size";
  return "";
}
}  // namespace

TEST(FuzzMessages, MalformedCloudsAreRefusedOrSafe)
{
  Tally tally("cloud");
  for (const std::uint64_t seed : seeds("cloud", 400))
  {
    const auto g = badCloud(seed);
    const Outcome o = runIsolated([&] { return cloudVerdict(g.value); }, kTimeout);
    tally.record(g.variant, seed, o, [&] {
      return "ACTION_FLOW_FUZZ_REPLAY=" + std::to_string(seed) +
             " test_fuzz_inputs --gtest_filter=FuzzMessages.MalformedClouds* (header " + std::to_string(g.value.width) +
             "x" + std::to_string(g.value.height) + " point_step " + std::to_string(g.value.point_step) + " row_step " +
             std::to_string(g.value.row_step) + " data " + std::to_string(g.value.data.size()) + ")";
    });
  }
  finish(tally);
}

TEST(FuzzMessages, MalformedImagesAndCameraInfoAreRefusedOrSafe)
{
  Tally images("image"), infos("camera_info");
  for (const std::uint64_t seed : seeds("image", 250))
  {
    const auto g = badImage(seed, seed % 2 == 0, 64, 48);
    images.record(g.variant, seed, runIsolated([&] { return imageVerdict(g.value); }, kTimeout), [&] {
      return "ACTION_FLOW_FUZZ_REPLAY=" + std::to_string(seed) + " test_fuzz_inputs --gtest_filter=FuzzMessages.MalformedImages*";
    });
  }
  for (const std::uint64_t seed : seeds("camera_info", 100))
  {
    const auto g = badInfo(seed, 64, 48);
    infos.record(g.variant, seed, runIsolated([&] { return infoVerdict(g.value); }, kTimeout), [&] {
      return "ACTION_FLOW_FUZZ_REPLAY=" + std::to_string(seed) + " test_fuzz_inputs --gtest_filter=FuzzMessages.MalformedImages*";
    });
  }
  finish(images);
  finish(infos);
}

// ---- files -------------------------------------------------------------------------------------

TEST(FuzzFiles, MalformedBagsAreRefusedNamingTheBagOrReadSafely)
{
  const std::string dir = scratchDir("bags");
  Tally tally("bag");
  for (const std::uint64_t seed : seeds("bag", 150))
  {
    const std::string bag = dir + "/seed_" + std::to_string(seed) + ".bag";
    const std::string variant = writeBadBag(bag, seed);
    const std::string index = dir + "/seed_" + std::to_string(seed) + ".csv";
    writeFile(index, "path,person,action,repetition,frames\n" + bag + ",p01,wave,1,5\n");
    const Outcome o = runIsolated(
        [&]() -> std::string {
          // The tools' own path: the index's sample, its bag reader, the whole feature pipeline.
          const auto samples = tools::samplesFromIndex(index, tools::BagTopics());
          if (samples.size() != 1)
            return "the index gave " + std::to_string(samples.size()) + " samples";
          try
          {
            auto source = samples[0].open();
            extractSample(*source, TrackerParams(), { defaultRecognitionParams() }, false);
          }
          catch (const DatasetError& e)
          {
            return contains(e.what(), bag) ? "" : std::string("the error does not name the bag: ") + e.what();
          }
          catch (const std::exception& e)
          {
            return std::string("not a DatasetError naming the bag: ") + typeid(e).name() + ": " + e.what();
          }
          return "";
        },
        kTimeout);
    tally.record(variant, seed, o, [&] { return bag + " (index " + index + ")"; });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
    {
      std::remove(bag.c_str());
      std::remove(index.c_str());
    }
  }
  finish(tally);
}

TEST(FuzzFiles, DamagedModelsAreRefusedNamingTheFileOrLoadConsistently)
{
  const std::string dir = scratchDir("models");
  const std::string paper = validModelBytes(dir, false), posture_flow = validModelBytes(dir, true);
  Tally tally("model");
  for (const std::uint64_t seed : seeds("model", 300))
  {
    const auto g = mutateModel(seed % 2 ? paper : posture_flow, seed);
    const std::string path = dir + "/seed_" + std::to_string(seed) + ".afm";
    writeFile(path, g.value);
    const Outcome o = runIsolated(
        [&]() -> std::string {
          ActionModel m;
          try
          {
            m = ActionModel::load(path);
          }
          catch (const ModelError& e)
          {
            return contains(e.what(), path) ? "" : std::string("the error does not name the file: ") + e.what();
          }
          catch (const std::exception& e)
          {
            return std::string("not a ModelError naming the file: ") + typeid(e).name() + ": " + e.what();
          }
          // Loaded: it must be usable as the classifier nodelet uses it.
          const auto c = m.classifier();
          const Eigen::VectorXf query = Eigen::VectorXf::Zero(m.sequenceLength());
          c.classify(query);
          return "";
        },
        kTimeout);
    tally.record(g.variant, seed, o, [&] { return path; });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
      std::remove(path.c_str());
  }
  finish(tally);
}

TEST(FuzzFiles, MalformedIndexesAreRefusedNamingTheFileAndLine)
{
  const std::string dir = scratchDir("indexes");
  const std::string bag = dir + "/sample.bag";
  writeFile(bag, "not read by readIndex");
  Tally tally("index");
  for (const std::uint64_t seed : seeds("index", 200))
  {
    const auto g = badIndex(seed, bag);
    const std::string path = dir + "/seed_" + std::to_string(seed) + ".csv";
    writeFile(path, g.value);
    const Outcome o = runIsolated(
        [&]() -> std::string {
          std::vector<IndexEntry> entries;
          try
          {
            entries = readIndex(path);
          }
          catch (const DatasetError& e)
          {
            return contains(e.what(), path) ? "" : std::string("the error does not name the index: ") + e.what();
          }
          catch (const std::exception& e)
          {
            return std::string("not a DatasetError naming the index: ") + typeid(e).name() + ": " + e.what();
          }
          for (const auto& e : entries)
            if (!whyNotARegularFile(e.path).empty())
              return "accepted the sample '" + e.path + "', which is no regular file";
          return "";
        },
        kTimeout);
    tally.record(g.variant, seed, o, [&] { return path; });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
      std::remove(path.c_str());
  }
  finish(tally);
}

TEST(FuzzFiles, MalformedSkeletonsAreRefusedNamingTheFileOrRendered)
{
  const std::string dir = scratchDir("skeletons");
  Tally tally("skeleton");
  for (const std::uint64_t seed : seeds("skeleton", 200))
  {
    const auto g = badSkeleton(seed);
    const std::string path = dir + "/seed_" + std::to_string(seed) + "_a01_s01_e01_skeleton3D.txt";
    writeFile(path, g.value);
    const bool render = seed % 4 == 0;  // rendering costs ~0.1 s a frame: a quarter of the inputs
    const Outcome o = runIsolated(
        [&]() -> std::string {
          synth::MsrSkeletonFile file;
          try
          {
            file = synth::parseMsrSkeletonFile(path);
          }
          catch (const std::runtime_error& e)
          {
            return contains(e.what(), path) ? "" : std::string("the error does not name the file: ") + e.what();
          }
          bool finite = true;
          for (std::size_t f = 0; f < file.frames.size(); ++f)
            for (const auto& j : file.frames[f])
              finite = finite && j.allFinite();
          const std::string verdict = finite ? "" : "parsed a non-finite joint";
          if (!render && finite)
            return verdict;  // a file with non-finite joints is always rendered too: it must not crash or hang
          synth::SampleSpec spec;
          spec.dataset = "msr";
          spec.person = "s01";
          spec.action = synth::msrActions()[0];
          spec.skeleton_file = path;
          spec.max_frames = 2;
          try
          {
            synth::SampleRenderer r(spec);
            Cloud cloud;
            for (int i = 0; i < r.frames(); ++i)
              r.render(i, cloud);
          }
          catch (const std::runtime_error& e)
          {
            return contains(e.what(), path) ? verdict : std::string("the renderer's error does not name the file: ") + e.what();
          }
          return verdict;
        },
        kTimeout);
    tally.record(g.variant, seed, o, [&] { return path; });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
      std::remove(path.c_str());
  }
  finish(tally);
}
