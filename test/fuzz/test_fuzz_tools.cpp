// Fuzz corpus, tools part: train, evaluate and synth run as processes on generated bad command
// lines, bags, index CSVs and MSR skeleton folders. Each must end within the timeout, by exit status
// 1 or 2 (never a signal, never 0: nothing may be learnt from garbage), with one error line on
// stderr, "<tool>: ...", naming the option or file. Progress lines the tools print on the way
// ("train: 1 samples", "  descriptors: ...") are allowed before it and counted. HOME points into
// the scratch folder, so that no default cache under the real home is used.
#include "generators.h"
#include "harness.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sys/stat.h>

using namespace action_flow::fuzz;

namespace
{
const std::string kBin = ACTION_FLOW_BIN_DIR;
constexpr double kTimeout = 60.0;  // seconds per process (a bag or skeleton input renders/tracks a few frames)

void writeFile(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

bool exists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

/** Lines a tool may print on stderr before its error line. */
bool progressLine(const std::string& line)
{
  static const std::regex progress(R"((train|evaluate): \d+ samples.*|  descriptors: .*)");
  return std::regex_match(line, progress);
}

/** Lines that libraries print on stderr by themselves (PCL's console, libpng). */
bool libraryChatter(const std::string& line)
{
  return line.rfind("[pcl::", 0) == 0 || line.rfind("Failed to find match for field", 0) == 0 ||
         line.rfind("libpng ", 0) == 0;
}

/**
 * The verdict on a finished tool run that had to be refused: "" when it exited 1 or 2 with one
 * error line "<tool>: ..." naming one of @p culprits (after progress lines only), else what was wrong.
 */
Outcome verdict(const std::string& tool, const Process& p, const std::vector<std::string>& culprits, int* progress)
{
  if (p.timed_out)
    return { Outcome::Hung, "no exit after " + std::to_string(kTimeout) + " s" };
  if (p.signal)
    return { Outcome::Crashed, "killed by signal " + std::to_string(p.signal) + " (" + ::strsignal(p.signal) + ")",
             p.signal };
  std::vector<std::string> err = lines(p.err);
  while (!err.empty() && err.back().empty())
    err.pop_back();
  const std::string shown = "stderr: " + printable(p.err, 600);
  if (p.status == 0)
    return { Outcome::Failed, "exit status 0 on bad input; " + shown };
  if (p.status != 1 && p.status != 2)
    return { Outcome::Failed, "exit status " + std::to_string(p.status) + " (expected 1 or 2); " + shown };
  if (err.empty())
    return { Outcome::Failed, "nothing on stderr" };
  std::size_t chatter = 0;
  for (std::size_t i = 0; i + 1 < err.size(); ++i)
    if (libraryChatter(err[i]))
      ++chatter;
    else if (!progressLine(err[i]))
      return { Outcome::Failed, std::to_string(err.size()) + " lines on stderr, expected one error line; " + shown };
  if (err.size() > 1)
    ++*progress;
  const std::string& line = err.back();
  if (line.rfind(tool + ": ", 0) != 0)
    return { Outcome::Failed, "the error line does not start with '" + tool + ": '; " + shown };
  for (const auto& c : culprits)
    if (line.find(c) != std::string::npos)
      return chatter == 0 ? Outcome{} :
                            Outcome{ Outcome::Failed, "library chatter on stderr: " + std::to_string(chatter) +
                                                          " lines of PCL/libpng messages besides the error line; " + shown };
  std::string names;
  for (const auto& c : culprits)
    names += (names.empty() ? "'" : " or '") + printable(c, 80) + "'";
  return { Outcome::Failed, "the error line does not name " + names + "; " + shown };
}

void finish(const Tally& t, int progress)
{
  t.print();
  std::printf("  %d of %d runs printed progress lines before their error line\n", progress, t.inputs());
  std::string first;
  for (const auto& f : t.firstFailures())
    first += f + "\n";
  EXPECT_EQ(t.unexpected(), 0) << t.unexpected() << " inputs failed; the first:\n" << first;
}
}  // namespace

class FuzzTools : public ::testing::TestWithParam<const char*>
{
};

TEST_P(FuzzTools, BadCommandLinesAreRefusedNamingTheOption)
{
  const std::string tool = GetParam();
  const std::string kind = "args_" + tool;
  const std::string scratch = scratchDir(kind);
  ::mkdir((scratch + "/home").c_str(), 0755);
  Tally tally(kind);
  int progress = 0;
  for (const std::uint64_t seed : seeds(kind, 30))
  {
    const auto g = badCommand(tool, seed, scratch);
    std::vector<std::string> argv = { kBin + "/" + tool };
    argv.insert(argv.end(), g.value.args.begin(), g.value.args.end());
    const Process p = runProcess(argv, scratch, scratch + "/home", kTimeout);
    tally.record(g.variant, seed, verdict(tool, p, { g.value.culprit }, &progress),
                 [&] { return "cd " + scratch + " && " + shellLine(argv); });
  }
  finish(tally, progress);
}

INSTANTIATE_TEST_SUITE_P(Tools, FuzzTools, ::testing::Values("train", "evaluate", "synth"));

TEST(FuzzToolFiles, BadBagsAreRefusedNamingTheBag)
{
  const std::string scratch = scratchDir("tool_bag");
  ::mkdir((scratch + "/home").c_str(), 0755);
  Tally tally("tool_bag");
  int progress = 0;
  for (const std::uint64_t seed : seeds("tool_bag", 20))
  {
    const std::string bag = scratch + "/seed_" + std::to_string(seed) + ".bag";
    const std::string index = scratch + "/seed_" + std::to_string(seed) + ".csv";
    const std::string model = scratch + "/seed_" + std::to_string(seed) + ".afm";
    const std::string variant = writeBadBag(bag, seed);
    writeFile(index, "path,person,action,repetition,frames\n" + bag + ",p01,wave,1,5\n");
    const std::vector<std::string> argv = { kBin + "/train", "--index", index, "--output", model, "--cache",
                                            scratch + "/cache", "--jobs", "1" };
    const Process p = runProcess(argv, scratch, scratch + "/home", kTimeout);
    Outcome o = verdict("train", p, { bag }, &progress);
    if (o.kind == Outcome::Ok && exists(model))
      o = { Outcome::Failed, "refused, but a model was written" };
    tally.record(variant, seed, o, [&] { return shellLine(argv); });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
    {
      std::remove(bag.c_str());
      std::remove(index.c_str());
    }
  }
  finish(tally, progress);
}

TEST(FuzzToolFiles, BadIndexesAreRefusedNamingTheIndexOrItsSample)
{
  const std::string scratch = scratchDir("tool_index");
  ::mkdir((scratch + "/home").c_str(), 0755);
  const std::string bag = scratch + "/sample.bag";
  writeFile(bag, "");  // exists, but is no bag: an index that passes leads to an error naming it
  Tally tally("tool_index");
  int progress = 0;
  for (const std::uint64_t seed : seeds("tool_index", 15))
  {
    const auto g = badIndex(seed, bag);
    const std::string index = scratch + "/seed_" + std::to_string(seed) + ".csv";
    writeFile(index, g.value);
    const std::string model = scratch + "/seed_" + std::to_string(seed) + ".afm";
    const std::vector<std::string> argv = { kBin + "/train", "--index", index, "--output", model, "--cache",
                                            scratch + "/cache", "--jobs", "1" };
    const Process p = runProcess(argv, scratch, scratch + "/home", kTimeout);
    Outcome o = verdict("train", p, { index, bag, "/proc/self/status" }, &progress);  // the last: a regular file, no bag
    if (o.kind == Outcome::Ok && exists(model))
      o = { Outcome::Failed, "refused, but a model was written" };
    tally.record(g.variant, seed, o, [&] { return shellLine(argv); });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
      std::remove(index.c_str());
  }
  finish(tally, progress);
}

TEST(FuzzToolFiles, BadSkeletonsAreRefusedNamingTheFile)
{
  const std::string scratch = scratchDir("tool_skeleton");
  ::mkdir((scratch + "/home").c_str(), 0755);
  Tally tally("tool_skeleton");
  int progress = 0;
  for (const std::uint64_t seed : seeds("tool_skeleton", 10))
  {
    const auto g = badSkeleton(seed);
    const std::string dir = scratch + "/seed_" + std::to_string(seed);
    ::mkdir(dir.c_str(), 0755);
    writeFile(dir + "/a01_s01_e01_skeleton3D.txt", g.value);
    const std::string model = dir + "/m.afm";
    const std::vector<std::string> argv = { kBin + "/train",  "--synth", "msr", "--msr-dir", dir, "--max-frames",
                                            "3", "--output", model, "--cache", scratch + "/cache", "--jobs", "1" };
    const Process p = runProcess(argv, scratch, scratch + "/home", kTimeout);
    // The error names the file, or the sample rendered from it (a01_s01_e01).
    Outcome o = verdict("train", p, { "a01_s01_e01" }, &progress);
    if (o.kind == Outcome::Ok && exists(model))
      o = { Outcome::Failed, "refused, but a model was written" };
    tally.record(g.variant, seed, o, [&] { return shellLine(argv); });
    if (o.kind == Outcome::Ok)  // every other reproducer is kept, known failures' too
      std::system(("rm -rf '" + dir + "'").c_str());
  }
  finish(tally, progress);
}
