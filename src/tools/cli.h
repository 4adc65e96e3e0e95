// Command-line handling shared by the offline tools: "--name value" and "--flag" options, and the
// method's parameters as options, so train and evaluate agree on them.
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/people_tracker.h>

#include <pcl/console/print.h>

#include <cstdio>
#include <functional>
#include <map>
#include <new>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>
#include <algorithm>

namespace action_flow
{
namespace tools
{
/** A bad command line: the tools exit with status 2 (usage) on it, 1 on any other error. */
class UsageError : public std::invalid_argument
{
public:
  using std::invalid_argument::invalid_argument;
};

/** Thrown when Ctrl-C stopped the work; the tools exit with 130. */
class Interrupted : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/**
 * Runs a tool's main body and turns what it throws into one line on stderr, "<tool>: <what>", and
 * the tools' exit codes: 0 done, 1 error, 2 usage, 130 interrupted.
 */
inline int runTool(const char* tool, const std::function<int()>& body)
{
  // PCL's console (RANSAC on a degenerate cloud, a field without a match) comments on inputs the
  // tools check and report themselves: stderr keeps the tools' own lines (progress, one error).
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  try
  {
    return body();
  }
  catch (const UsageError& e)
  {
    std::fprintf(stderr, "%s: %s (--help lists the options)\n", tool, e.what());
    return 2;
  }
  catch (const Interrupted& e)
  {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return 130;
  }
  catch (const std::bad_alloc&)
  {
    std::fprintf(stderr, "%s: out of memory (too many or too large samples for this machine?)\n", tool);
    return 1;
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return 1;
  }
}

/** Runs @p worker on max(1, @p jobs) threads at once and waits for all of them (the workers take
 *  their items from a shared counter and keep their own error; nothing may escape a worker). */
inline void runWorkers(int jobs, const std::function<void()>& worker)
{
  std::vector<std::thread> pool;
  for (int j = 0; j < std::max(1, jobs); ++j)
    pool.emplace_back(worker);
  for (auto& t : pool)
    t.join();
}

class Args
{
public:
  /** @throws std::invalid_argument on an option not in @p known (names without "--"). */
  Args(int argc, char** argv, const std::set<std::string>& flags, const std::set<std::string>& valued)
  {
    for (int i = 1; i < argc; ++i)
    {
      std::string a = argv[i];
      if (a.rfind("--", 0) != 0)
        throw UsageError("unexpected argument '" + a + "'");
      a = a.substr(2);
      if (flags.count(a))
        values_[a] = "1";
      else if (valued.count(a))
      {
        if (i + 1 >= argc)
          throw UsageError("option --" + a + " needs a value");
        values_[a] = argv[++i];
      }
      else
        throw UsageError("unknown option --" + a);
    }
  }
  bool has(const std::string& k) const { return values_.count(k) > 0; }
  std::string get(const std::string& k, const std::string& def = "") const
  {
    auto it = values_.find(k);
    return it == values_.end() ? def : it->second;
  }
  double number(const std::string& k, double def) const
  {
    if (!has(k))
      return def;
    try
    {
      std::size_t used = 0;
      const double v = std::stod(get(k), &used);
      if (used == get(k).size())
        return v;
    }
    catch (const std::exception&)
    {
    }
    throw UsageError("option --" + k + " needs a number, got '" + get(k) + "'");
  }
  /** @brief A whole number in [lo, hi] (decimal digits only); @throws UsageError naming the option otherwise. */
  long integer(const std::string& k, long def, long lo, long hi) const
  {
    if (!has(k))
      return def;
    const std::string v = get(k);
    const bool digits = !v.empty() && v.size() <= 12 &&
                        v.find_first_not_of("0123456789", v[0] == '-' ? 1 : 0) == std::string::npos && v != "-";
    const long n = digits ? std::stol(v) : 0;
    if (!digits || n < lo || n > hi)
      throw UsageError("option --" + k + " must be a whole number in " + std::to_string(lo) + ".." + std::to_string(hi) +
                       ", got '" + v + "'");
    return n;
  }

private:
  std::map<std::string, std::string> values_;
};

/** The --jobs option: 1..64 threads (default 2). */
inline int jobsOption(const Args& a)
{
  return static_cast<int>(a.integer("jobs", 2, 1, 64));
}

/** Options naming the method's parameters. */
inline const std::set<std::string>& methodOptions()
{
  static const std::set<std::string> o = { "recognizer", "descriptor", "frames", "pca-variance", "neighbours", "k",
                                            "classifier", "c", "temporal-levels" };
  return o;
}

/** Flags naming the method's parameters. */
inline const std::set<std::string>& methodFlags()
{
  static const std::set<std::string> o = { "pca", "no-outlier-rejection", "no-posture", "no-direction-histogram",
                                           "single-level", "no-mirror", "mirror", "direction-histogram", "no-geometry",
                                           "align-to-facing" };
  return o;
}

/** Usage lines of the method's options. */
inline const char* methodUsage()
{
  return "  --recognizer posture_flow|paper posture_flow (default): posture and flow, temporal pyramid, linear\n"
         "                                  classifier; paper: Munaro et al.'s SUMFLOW/MEANFLOW, F frames, k-NN\n"
         "  posture_flow:\n"
         "  --classifier linear|nn          logistic regression (default) or 1-NN\n"
         "  --c C                           the linear classifier's C (default: chosen by cross-validation\n"
         "                                  over the training people)\n"
         "  --temporal-levels N             pyramid levels, 1 = whole sequence only (default 3)\n"
         "  --no-posture, --no-direction-histogram, --single-level, --no-geometry, --no-mirror\n"
         "                                  switch off one part (for ablations); mirrored training copies\n"
         "                                  are otherwise used or not as the cross-validation chooses\n"
         "  paper:\n"
         "  --descriptor sumflow|meanflow   frame descriptor (default sumflow)\n"
         "  --frames F                      frames per sequence descriptor (default 30)\n"
         "  --pca [--pca-variance 0.99]     project frames on a PCA basis keeping that variance\n"
         "  --neighbours K                  k of the k-NN classifier (default 1)\n"
         "  both:\n"
         "  --k K                           flow: nearest neighbours in XYZ (default 50)\n"
         "  --no-outlier-rejection          skip the flow's speed and isolation rules\n"
         "  --align-to-facing               the tracker turns each person's grid to where they face\n"
         "                                  (TrackerParams::align_to_facing; run the live tracker so too)\n";
}

/** The tracker's parameters from the options: the defaults, but for --align-to-facing. */
inline TrackerParams trackerParams(const Args& a)
{
  TrackerParams t;
  if (a.has("align-to-facing"))
    t.align_to_facing = true;
  return t;
}

/** The method's parameters from the options (defaults: the default recognizer, posture_flow). */
inline RecognitionParams methodParams(const Args& a)
{
  RecognitionParams p = defaultRecognitionParams();
  p.recognizer = recognizerFromString(a.get("recognizer", toString(p.recognizer)));
  p.pyramid.classifier = pyramidClassifierFromString(a.get("classifier", toString(p.pyramid.classifier)));
  p.pyramid.c = a.number("c", p.pyramid.c);
  p.pyramid.temporal_levels = static_cast<int>(a.integer("temporal-levels", p.pyramid.temporal_levels, 1, 4));
  p.pyramid.posture = !a.has("no-posture");
  if (a.has("no-direction-histogram"))
    p.pyramid.flow = FlowEncoding::Sums;
  if (a.has("direction-histogram"))
    p.pyramid.flow = FlowEncoding::Bins;
  p.pyramid.coarse_to_fine = !a.has("single-level");
  p.pyramid.geometry = !a.has("no-geometry");
  if (a.has("no-mirror"))
    p.pyramid.mirror = MirrorMode::Off;
  if (a.has("mirror"))
    p.pyramid.mirror = MirrorMode::On;
  if (!(p.pyramid.c >= 0.0 && p.pyramid.c <= 1e6))
    throw UsageError("option --c must be in 0..1e6 (0: chosen by cross-validation)");
  p.grid.aggregation = aggregationFromString(a.get("descriptor", "sumflow"));
  p.frames = static_cast<int>(a.integer("frames", p.frames, 1, 1000));
  p.use_pca = a.has("pca");
  p.pca_variance = a.number("pca-variance", p.pca_variance);
  p.neighbours = static_cast<int>(a.integer("neighbours", p.neighbours, 1, 1000));
  p.flow.k = static_cast<int>(a.integer("k", p.flow.k, 1, 1000));
  p.flow.reject_outliers = !a.has("no-outlier-rejection");
  if (!(p.pca_variance > 0 && p.pca_variance <= 1))
    throw UsageError("option --pca-variance must be in (0,1]");
  return p;
}

}  // namespace tools
}  // namespace action_flow
