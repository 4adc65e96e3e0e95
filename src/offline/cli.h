// Command-line handling shared by the offline tools: "--name value" and "--flag" options, and the
// method's parameters as options, so train and evaluate agree on them.
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/people_tracker.h>

#include "param_files.h"
#include "../eval/workers.h"

#include <pcl/console/print.h>

#include <boost/program_options.hpp>

#include <cstdio>
#include <unistd.h>
#include <mutex>
#include <chrono>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>
#include <algorithm>
#include <atomic>
#include <exception>

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

/**
 * Progress on stderr, for every tool: on a terminal one line redrawn in place (at most four times a
 * second); in a log (not a terminal) whole lines, at most one every @p log_every seconds, and the
 * last one always. Thread-safe.
 */
class ProgressLine
{
public:
  explicit ProgressLine(double log_every = 10.0)
    : tty_(::isatty(STDERR_FILENO) != 0), log_every_(log_every), start_(std::chrono::steady_clock::now())
  {
  }
  /** Shows @p text (made only when it is shown) now or, if the last was shown too recently, not at all. */
  void show(const std::function<std::string()>& text, bool last = false)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const double t = seconds();
    if (!last && shown_ >= 0 && t - shown_ < (tty_ ? 0.25 : log_every_))
      return;
    shown_ = t;
    const std::string line = text();
    open_ = tty_ && !last;
    std::fprintf(stderr, "%s%s%s", tty_ ? "\r" : "", line.c_str(), open_ ? "" : "\n");
    std::fflush(stderr);
  }
  /** Ends a line left open on a terminal (work stopped before its last line), so what follows starts afresh. */
  void end()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (open_)
      std::fputc('\n', stderr);
    open_ = false;
  }
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
  bool tty_;
  double log_every_;
  std::chrono::steady_clock::time_point start_;
  std::mutex mutex_;
  double shown_ = -1.0;
  bool open_ = false;
};

using action_flow::forEachParallel;
using action_flow::runWorkers;

/**
 * The options a tool takes, each declared once with its help (boost::program_options, Debian's
 * libboost-program-options-dev): --help (-h) prints them all, grouped, and nothing else is
 * accepted. Values are kept as text; Args' number() and integer() check them and name the option.
 */
class Options
{
public:
  explicit Options(const std::string& synopsis) : synopsis_(synopsis)
  {
    group("options");
    flag("help,h", "print this help and exit");
  }
  /** Starts a new section of --help. */
  Options& group(const std::string& caption)
  {
    groups_.push_back(std::make_shared<boost::program_options::options_description>(caption, 100, 50));
    return *this;
  }
  Options& value(const std::string& name, const std::string& arg, const std::string& help)
  {
    groups_.back()->add_options()(name.c_str(), boost::program_options::value<std::string>()->value_name(arg),
                                  help.c_str());
    valued_.insert(name);
    return *this;
  }
  Options& flag(const std::string& name, const std::string& help)
  {
    groups_.back()->add_options()(name.c_str(), boost::program_options::bool_switch(), help.c_str());
    flags_.insert(name);
    return *this;
  }
  /** The synopsis and every option, as --help prints it. */
  std::string help() const
  {
    std::ostringstream out;
    out << synopsis_ << "\n";
    for (const auto& g : groups_)
      out << "\n" << *g;
    return out.str();
  }
  boost::program_options::options_description all() const
  {
    boost::program_options::options_description d;
    for (const auto& g : groups_)
      d.add(*g);
    return d;
  }
  bool isFlag(const std::string& name) const { return flags_.count(name) > 0 || name == "help"; }
  bool isValued(const std::string& name) const { return valued_.count(name) > 0; }
  /** Prints the help on stdout (for --help: exit 0) or, with @p error, on stderr (exit 2). */
  int printHelp(bool error = false) const
  {
    (error ? std::cerr : std::cout) << help();
    return error ? 2 : 0;
  }

private:
  std::string synopsis_;
  std::vector<std::shared_ptr<boost::program_options::options_description>> groups_;
  std::set<std::string> flags_, valued_;
};

class Args
{
public:
  /** @throws UsageError on an option @p options does not declare, a missing value, an option given twice
   *          or a stray argument (boost::program_options' message). */
  Args(int argc, char** argv, const Options& options)
  {
    namespace po = boost::program_options;
    // "--name value" becomes "--name=value" for a valued option, so that a value starting with '-'
    // (a negative number, a stray "--") is taken as the value, as the user meant, not as an option.
    // A word that is neither an option nor an option's value is refused by name.
    std::vector<std::string> tokens;
    for (int i = 1; i < argc; ++i)
    {
      std::string t = argv[i];
      if (t.empty() || t[0] != '-')
        throw UsageError("unexpected argument '" + t + "'");
      if (t.rfind("--", 0) == 0 && t.find('=') == std::string::npos && options.isValued(t.substr(2)) && i + 1 < argc)
      {
        const std::string v = argv[++i];
        if (!v.empty() && v[0] == '-')
          tokens.push_back(t + "=" + v);
        else
        {
          tokens.push_back(t);
          tokens.push_back(v);
        }
        continue;
      }
      tokens.push_back(t);
    }
    po::variables_map vm;
    try
    {
      po::store(po::command_line_parser(tokens)
                    .options(options.all())
                    .style(po::command_line_style::unix_style ^ po::command_line_style::allow_guessing)
                    .run(),
                vm);
    }
    catch (const po::error& e)
    {
      throw UsageError(e.what());
    }
    for (const auto& kv : vm)
    {
      if (options.isFlag(kv.first))
      {
        if (kv.second.as<bool>())
          values_[kv.first] = "1";
      }
      else if (!kv.second.defaulted())
        values_[kv.first] = kv.second.as<std::string>();
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

/** An option whose value is one of an enum's names (param_table.h); @throws UsageError naming the option. */
template <class E>
E choiceOption(const Args& a, const std::string& name, E value)
{
  if (a.has(name))
    try
    {
      parseParam(a.get(name), value);
    }
    catch (const std::invalid_argument& e)
    {
      throw UsageError("option --" + name + ": " + e.what());
    }
  return value;
}

/** The options naming the method's parameters. */
inline void addMethodOptions(Options& o)
{
  o.group("method options (docs/parameters.md)")
      .value("config", "FILE[,FILE...]",
             "parameters from yaml files as the nodelets load them (e.g. config/recognition.yaml,"
             "config/tracker.yaml); the options below override them")
      .value("recognizer", "posture_flow|paper",
             "posture_flow (default): posture and flow, temporal pyramid, linear classifier; paper: Munaro et "
             "al.'s SUMFLOW/MEANFLOW, F frames, k-NN")
      .value("classifier", "linear|nn", "posture_flow: logistic regression (default) or 1-NN")
      .value("c", "C", "posture_flow: the linear classifier's C (default: chosen by cross-validation over the "
                       "training people)")
      .value("temporal-levels", "N", "posture_flow: pyramid levels, 1 = whole sequence only (default 3)")
      .value("fourier", "N", "posture_flow: Fourier magnitudes per pyramid part, 0 = none (default 6)")
      .flag("no-posture", "posture_flow: without the cells' shares of the body (an ablation)")
      .flag("no-direction-histogram", "posture_flow: the flow as signed sums, not direction bins")
      .flag("direction-histogram", "posture_flow: the flow as direction bins (default: chosen by cross-validation)")
      .flag("single-level", "posture_flow: cells at 4 parts per axis only")
      .flag("no-geometry", "posture_flow: without the body-geometry block")
      .flag("no-mirror", "posture_flow: no mirrored training copies (default: chosen by cross-validation)")
      .flag("mirror", "posture_flow: always mirrored training copies")
      .value("descriptor", "sumflow|meanflow", "paper: frame descriptor (default sumflow)")
      .value("frames", "F", "paper: frames per sequence descriptor (default 30)")
      .flag("pca", "paper: project frames on a PCA basis")
      .value("pca-variance", "V", "paper: the variance the PCA basis keeps (default 0.99)")
      .value("neighbours", "K", "k of the k-NN classifier (default 1)")
      .value("k", "K", "flow: nearest neighbours in XYZ (default 50)")
      .flag("no-outlier-rejection", "flow: skip the speed and isolation rules")
      .flag("align-to-facing", "the tracker turns each person's grid to where they face "
                               "(TrackerParams::align_to_facing; run the live tracker so too)");
}

/** The parameters of the --config files (the declared defaults without it). */
inline ToolParams configParams(const Args& a)
{
  ToolParams p;
  std::stringstream files(a.get("config"));
  std::string file;
  while (std::getline(files, file, ','))
    if (!file.empty())
      applyParamFile(file, p);
  return p;
}

/** The tracker's parameters: --config's, and --align-to-facing. */
inline TrackerParams trackerParams(const Args& a)
{
  TrackerParams t = configParams(a).tracker;
  if (a.has("align-to-facing"))
    t.align_to_facing = true;
  return t;
}

/** The method's parameters: --config's (default: the default recognizer, posture_flow), and the options. */
inline RecognitionParams methodParams(const Args& a)
{
  RecognitionParams p = configParams(a).recognition;
  const std::string problem = p.pyramid.problem();
  if (!problem.empty())
    throw std::invalid_argument("--config " + a.get("config") + ": " + problem);
  p.recognizer = choiceOption(a, "recognizer", p.recognizer);
  p.pyramid.classifier = choiceOption(a, "classifier", p.pyramid.classifier);
  p.pyramid.c = a.number("c", p.pyramid.c);
  p.pyramid.temporal_levels = static_cast<int>(a.integer("temporal-levels", p.pyramid.temporal_levels, 1, 4));
  p.pyramid.fourier = static_cast<int>(a.integer("fourier", p.pyramid.fourier, 0, kMaxFourier));
  if (a.has("no-posture"))
    p.pyramid.posture = PostureMode::Off;
  if (a.has("no-direction-histogram"))
    p.pyramid.flow = FlowEncoding::Sums;
  if (a.has("direction-histogram"))
    p.pyramid.flow = FlowEncoding::Bins;
  if (a.has("single-level"))
    p.pyramid.coarse_to_fine = false;
  if (a.has("no-geometry"))
    p.pyramid.geometry = false;
  if (a.has("no-mirror"))
    p.pyramid.mirror = MirrorMode::Off;
  if (a.has("mirror"))
    p.pyramid.mirror = MirrorMode::On;
  if (!(p.pyramid.c >= 0.0 && p.pyramid.c <= 1e6))
    throw UsageError("option --c must be in 0..1e6 (0: chosen by cross-validation)");
  p.grid.aggregation = choiceOption(a, "descriptor", p.grid.aggregation);
  p.frames = static_cast<int>(a.integer("frames", p.frames, 1, 1000));
  if (a.has("pca"))
    p.use_pca = true;
  p.pca_variance = a.number("pca-variance", p.pca_variance);
  p.neighbours = static_cast<int>(a.integer("neighbours", p.neighbours, 1, 1000));
  p.flow.k = static_cast<int>(a.integer("k", p.flow.k, 1, 1000));
  if (a.has("no-outlier-rejection"))
    p.flow.reject_outliers = false;
  if (!(p.pca_variance > 0 && p.pca_variance <= 1))
    throw UsageError("option --pca-variance must be in (0,1]");
  return p;
}

}  // namespace tools
}  // namespace action_flow
