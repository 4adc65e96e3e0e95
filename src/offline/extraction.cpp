#include "extraction.h"

#include "cli.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <functional>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace action_flow
{
namespace tools
{
namespace
{
std::atomic<bool> g_stop{ false };

extern "C" void onSignal(int)
{
  g_stop = true;
}

}  // namespace

void refuseEmptySamples(const std::vector<SampleRef>& samples, const std::vector<SampleFrames>& frames,
                        bool allow_empty)
{
  std::size_t empty = 0, first = 0;
  for (std::size_t i = 0; i < samples.size() && i < frames.size(); ++i)
    if (frames[i].descriptors.rows() == 0 && empty++ == 0)
      first = i;
  if (empty > 0 && !allow_empty)
    throw DatasetError(samples[first].where + ": no person was tracked in it long enough for a frame descriptor" +
                       (empty > 1 ? " (nor in " + std::to_string(empty - 1) + " other samples)" : std::string()) +
                       "; --allow-empty keeps such samples as still frames");
}

void installInterruptHandler()
{
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
}

void makeOutputDir(const std::string& dir)
{
  std::error_code ec;
  if (!dir.empty())
    std::filesystem::create_directories(dir, ec);
  if (dir.empty() || ec || !std::filesystem::is_directory(dir, ec) || ::access(dir.c_str(), W_OK) != 0)
    throw UsageError("--output: cannot create or write the folder '" + dir + "'");
}

std::vector<std::string> splitList(const std::string& s)
{
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty())
      out.push_back(item);
  return out;
}

std::string paramsFingerprint(const RecognitionParams& p, const TrackerParams& t)
{
  // Every parameter that shapes a frame descriptor (Shapes::Frames: the recognizer's kind, flow,
  // grid; the whole tracker), by name. The leading revision changes with the code of those stages
  // (v3: a top at the image's edge no longer always rejects a person; v4: posture_flow's geometry
  // block; v5: walls removed before clustering, a cut surface by its length at the image's edge,
  // hidden people kept; v7: parameters by name, flow/max_gap among them).
  std::string key = "v7";
  for (const ParamEntry& e : paramEntries(p))
    if (e.shapes == Shapes::Frames)
      key += " " + e.name + "=" + e.value;
  for (const ParamEntry& e : paramEntries(t))
    key += " " + e.name + "=" + e.value;
  const std::string kind = p.recognizer == Recognizer::Paper ? toString(p.grid.aggregation) : toString(p.recognizer);
  return kind + (p.flow.reject_outliers ? "" : "_raw") + "_" + stableHash(key);
}

std::vector<std::vector<SampleFrames>> extractAll(const std::vector<SampleRef>& samples,
                                                  const std::vector<RecognitionParams>& variants,
                                                  const TrackerParams& tracker, const std::string& cache_dir, int jobs)
{
  std::vector<std::string> dirs;
  for (const auto& v : variants)
  {
    dirs.push_back(cache_dir + "/" + paramsFingerprint(v, tracker));
    std::error_code ec;  // a folder that cannot be made shows when the first sample cannot be cached
    std::filesystem::create_directories(dirs.back(), ec);
  }
  std::vector<std::vector<SampleFrames>> out(variants.size(), std::vector<SampleFrames>(samples.size()));
  const auto cachePath = [&](std::size_t v, std::size_t s) {
    return dirs[v] + "/" + samples[s].key + "_" + stableHash(samples[s].fingerprint) + ".frames";
  };

  std::atomic<std::size_t> next{ 0 }, done{ 0 }, cached{ 0 };
  std::mutex print;
  std::string error;
  ProgressLine progress;
  const auto worker = [&]() {
    for (std::size_t s = next++; s < samples.size() && !g_stop; s = next++)
    {
      try
      {
        bool all = true;
        for (std::size_t v = 0; v < variants.size(); ++v)
          // A file of another descriptor length (an older layout) is made again.
          all = loadSampleFrames(cachePath(v, s), out[v][s]) &&
                (out[v][s].descriptors.rows() == 0 ||
                 out[v][s].descriptors.cols() == frameDescriptorLength(variants[v])) &&
                all;
        if (all)
          ++cached;
        else
        {
          auto source = samples[s].open();
          auto frames = extractSample(*source, tracker, variants, samples[s].all_tracks);
          for (std::size_t v = 0; v < variants.size(); ++v)
          {
            saveSampleFrames(cachePath(v, s), frames[v]);
            out[v][s] = std::move(frames[v]);
          }
        }
      }
      catch (const std::exception& e)
      {
        std::lock_guard<std::mutex> lock(print);
        if (error.empty())
          error = samples[s].key + ": " + e.what();
        g_stop = true;
      }
      const std::size_t n = ++done;
      progress.show(
          [&] {
            const double secs = progress.seconds();
            char line[160];
            std::snprintf(line, sizeof line, "  descriptors: %zu/%zu samples (%zu cached)  %.0f s elapsed, about %.0f s left", n,
                          samples.size(), cached.load(), secs, secs / n * (samples.size() - n));
            return std::string(line);
          },
          n == samples.size());
    }
  };
  runWorkers(jobs, worker);
  progress.end();
  // From here on nothing is half-written (reports are renamed into place): Ctrl-C ends the tool.
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (!error.empty())
    throw std::runtime_error(error);
  if (g_stop)
    throw Interrupted("interrupted after " + std::to_string(done.load()) + " of " +
                             std::to_string(samples.size()) + " samples; their descriptors are cached");
  return out;
}

}  // namespace tools
}  // namespace action_flow
