/**
 * @file harness.h
 * @brief The fuzz suite's runner: how many inputs (the bounded CI corpus, or the long mode's
 *        ACTION_FLOW_FUZZ_INPUTS), each input's seed, running an input isolated in a child process
 *        with a timeout (a crash is a signal, a hang a timeout), running a tool as a process, and
 *        the per-kind tally with known failures and the summary lines.
 *
 * Environment:
 *   ACTION_FLOW_FUZZ_INPUTS=N   long mode: about N inputs over the whole suite (CI: about 2,000)
 *   ACTION_FLOW_FUZZ_SEED=S     base seed (default 1); every input's own seed is printed on failure
 *   ACTION_FLOW_FUZZ_REPLAY=S   run only the input of seed S (with --gtest_filter for its kind)
 *   ACTION_FLOW_FUZZ_OUT=DIR    where reproducers are written (default action_flow_fuzz in $TMPDIR, else the system's temporary folder)
 */
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace action_flow
{
namespace fuzz
{
/** @brief The inputs a kind gets: @p ci in CI, scaled by ACTION_FLOW_FUZZ_INPUTS / 2000 in the long mode. */
int inputCount(int ci);
/** @brief Whether the long mode is on. */
bool longMode();
/** @brief The seed of input @p i of @p kind (a hash of the base seed, the kind and i). */
std::uint64_t inputSeed(const std::string& kind, int i);
/** @brief The seeds to run for @p kind: inputCount(@p ci) of them, or the one of ACTION_FLOW_FUZZ_REPLAY. */
std::vector<std::uint64_t> seeds(const std::string& kind, int ci);
/** @brief The reproducer folder (created). */
std::string outDir();
/** @brief A fresh scratch folder under outDir() (emptied). */
std::string scratchDir(const std::string& name);

/** @brief How an input ended. */
struct Outcome
{
  enum Kind
  {
    Ok,       ///< handled as it should be
    Failed,   ///< handled, but wrongly (message says how)
    Crashed,  ///< killed by a signal
    Hung      ///< did not end within the timeout
  } kind = Ok;
  std::string message;
  int signal = 0;
};

/**
 * @brief Runs @p body in a forked child with @p timeout seconds; the body returns "" when the input
 *        was handled correctly, else what was wrong. A signal is a crash, the timeout a hang.
 */
Outcome runIsolated(const std::function<std::string()>& body, double timeout);

/** @brief A finished process. */
struct Process
{
  bool timed_out = false;
  int signal = 0;   ///< the signal that ended it, 0 if it exited
  int status = -1;  ///< exit status when it exited
  std::string out, err;
  double seconds = 0.0;
};

/**
 * @brief Runs @p argv (argv[0] a path) in @p cwd with HOME, ROS_HOME and ROS_LOG_DIR set to @p home
 *        (so that no default cache or log under the real home is touched), killing its process
 *        group after @p timeout seconds.
 */
Process runProcess(const std::vector<std::string>& argv, const std::string& cwd, const std::string& home,
                   double timeout);

/** @brief The lines of @p text. */
std::vector<std::string> lines(const std::string& text);
/** @brief A shell-quoted command line, for reproducers. */
std::string shellLine(const std::vector<std::string>& argv);

/**
 * @brief Counts inputs per kind and case; reports each failure with its seed and reproducer, and
 *        decides which make the test fail: all but those of a case declared a known failure, which
 *        are printed as KNOWN FAILURE and counted.
 */
class Tally
{
public:
  explicit Tally(std::string kind) : kind_(std::move(kind)) {}
  /**
   * @brief Declares failures of @p variant of this kind whose message contains @p match (any, if
   *        empty) a known failure: a product bug reported, not fixed here. Other failures of the
   *        same case still fail the test. @p variant "*" stands for every case without its own entry.
   */
  void knownFailure(const std::string& variant, const std::string& why, const std::string& match = "")
  {
    known_[variant] = { why, match };
  }
  /**
   * @brief Records one input. On a bad outcome @p reproducer is called to write what reproduces it
   *        and returns a description (a file, a command); the failure is printed with the seed.
   * @return false if the input failed and its case is not a known failure
   */
  bool record(const std::string& variant, std::uint64_t seed, const Outcome& o,
              const std::function<std::string()>& reproducer);
  /** @brief Prints "fuzz kind <kind>: inputs=N crashes=C hangs=H failures=F known=K" and the cases. */
  void print() const;
  const std::string& kind() const { return kind_; }
  int inputs() const { return inputs_; }
  int unexpected() const { return unexpected_; }
  /** @brief The first unexpected failures (for the test's failure message). */
  const std::vector<std::string>& firstFailures() const { return first_; }

private:
  struct Count
  {
    int inputs = 0, crashes = 0, hangs = 0, failures = 0, known = 0;
  };
  std::string kind_;
  std::map<std::string, std::pair<std::string, std::string>> known_;  // case -> why, message part
  std::map<std::string, Count> cases_;
  std::map<std::string, int> known_hits_;  // per known_ entry
  Count all_;
  int inputs_ = 0, unexpected_ = 0;
  std::vector<std::string> first_;
};

}  // namespace fuzz
}  // namespace action_flow
