// The fuzz suite's runner (see harness.h).
#include "harness.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <poll.h>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace action_flow
{
namespace fuzz
{
namespace
{
constexpr int kCiCorpus = 2000;  // the inputs the CI corpus has in total (the scale of the long mode)

long envNumber(const char* name, long fallback)
{
  const char* v = std::getenv(name);
  if (!v || !*v)
    return fallback;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  return end && *end == '\0' ? n : fallback;
}

std::string readAll(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

double since(std::chrono::steady_clock::time_point t0)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

bool longMode()
{
  return envNumber("ACTION_FLOW_FUZZ_INPUTS", 0) > 0;
}

int inputCount(int ci)
{
  const long total = envNumber("ACTION_FLOW_FUZZ_INPUTS", 0);
  if (total <= 0)
    return ci;
  return static_cast<int>((static_cast<long long>(ci) * total + kCiCorpus - 1) / kCiCorpus);
}

std::uint64_t inputSeed(const std::string& kind, int i)
{
  std::uint64_t h = 1469598103934665603ull ^ static_cast<std::uint64_t>(envNumber("ACTION_FLOW_FUZZ_SEED", 1));
  for (unsigned char c : kind)
    h = (h ^ c) * 1099511628211ull;
  return (h ^ static_cast<std::uint64_t>(i)) * 1099511628211ull % 1000000000000ull;
}

std::vector<std::uint64_t> seeds(const std::string& kind, int ci)
{
  const long replay = envNumber("ACTION_FLOW_FUZZ_REPLAY", -1);
  if (replay >= 0)
    return { static_cast<std::uint64_t>(replay) };
  std::vector<std::uint64_t> out;
  for (int i = 0, n = inputCount(ci); i < n; ++i)
    out.push_back(inputSeed(kind, i));
  return out;
}

std::string outDir()
{
  const char* v = std::getenv("ACTION_FLOW_FUZZ_OUT");
  // Default: action_flow_fuzz in the system's temporary folder ($TMPDIR if set).
  const std::string d = v && *v ? std::string(v) : (std::filesystem::temp_directory_path() / "action_flow_fuzz").string();
  ::mkdir(d.c_str(), 0755);
  return d;
}

std::string scratchDir(const std::string& name)
{
  const std::string d = outDir() + "/scratch_" + name + "_" + std::to_string(::getpid());
  std::system(("rm -rf '" + d + "' && mkdir -p '" + d + "'").c_str());
  return d;
}

Outcome runIsolated(const std::function<std::string()>& body, double timeout)
{
  int fds[2];
  if (::pipe(fds) != 0)
    return { Outcome::Failed, "pipe: " + std::string(std::strerror(errno)) };
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid == 0)
  {
    ::close(fds[0]);
    std::string error;
    try
    {
      error = body();
    }
    catch (const std::exception& e)
    {
      error = std::string("escaped exception: ") + e.what();
    }
    catch (...)
    {
      error = "escaped non-standard exception";
    }
    for (std::size_t done = 0; done < error.size();)
    {
      const ssize_t n = ::write(fds[1], error.data() + done, error.size() - done);
      if (n <= 0)
        break;
      done += static_cast<std::size_t>(n);
    }
    ::_exit(error.empty() ? 0 : 3);
  }
  ::close(fds[1]);
  if (pid < 0)
  {
    ::close(fds[0]);
    return { Outcome::Failed, "fork failed" };
  }
  std::string message;
  const auto t0 = std::chrono::steady_clock::now();
  bool hung = false;
  for (;;)
  {
    const double left = timeout - since(t0);
    if (left <= 0)
    {
      hung = true;
      break;
    }
    pollfd p{ fds[0], POLLIN, 0 };
    const int r = ::poll(&p, 1, static_cast<int>(left * 1000) + 1);
    if (r < 0 && errno == EINTR)
      continue;
    if (r <= 0)
      continue;
    char buf[4096];
    const ssize_t n = ::read(fds[0], buf, sizeof(buf));
    if (n <= 0)
      break;  // the child closed its end: it ended
    message.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fds[0]);
  if (hung)
  {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    return { Outcome::Hung, "no end after " + std::to_string(timeout) + " s" };
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFSIGNALED(status))
    return { Outcome::Crashed, std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" +
                                   ::strsignal(WTERMSIG(status)) + ")",
             WTERMSIG(status) };
  if (WEXITSTATUS(status) != 0 || !message.empty())
    return { Outcome::Failed, message.empty() ? "exit status " + std::to_string(WEXITSTATUS(status)) : message };
  return {};
}

Process runProcess(const std::vector<std::string>& argv, const std::string& cwd, const std::string& home,
                   double timeout)
{
  Process r;
  static int counter = 0;
  const std::string base = outDir() + "/proc_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string out = base + ".out", err = base + ".err";
  const auto t0 = std::chrono::steady_clock::now();
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = ::fork();
  if (pid == 0)
  {
    ::setpgid(0, 0);
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = ::open("/dev/null", O_RDONLY);
    ::dup2(in, 0);
    ::dup2(o, 1);
    ::dup2(e, 2);
    if (::chdir(cwd.c_str()) != 0)
      ::_exit(126);
    ::setenv("HOME", home.c_str(), 1);
    ::setenv("ROS_HOME", (home + "/.ros").c_str(), 1);
    ::setenv("ROS_LOG_DIR", (home + "/log").c_str(), 1);
    std::vector<char*> args;
    for (const auto& a : argv)
      args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  for (;;)
  {
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid)
      break;
    if (since(t0) > timeout)
    {
      ::kill(-pid, SIGKILL);
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      r.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = since(t0);
  if (!r.timed_out)
  {
    if (WIFSIGNALED(status))
      r.signal = WTERMSIG(status);
    else
      r.status = WEXITSTATUS(status);
  }
  r.out = readAll(out);
  r.err = readAll(err);
  ::unlink(out.c_str());
  ::unlink(err.c_str());
  return r;
}

std::vector<std::string> lines(const std::string& text)
{
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l))
    out.push_back(l);
  return out;
}

std::string shellLine(const std::vector<std::string>& argv)
{
  std::string s;
  for (const auto& a : argv)
  {
    std::string q = "'";
    for (char c : a)
      q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    s += (s.empty() ? "" : " ") + q + "'";
  }
  return s;
}

bool Tally::record(const std::string& variant, std::uint64_t seed, const Outcome& o,
                   const std::function<std::string()>& reproducer)
{
  Count& c = cases_[variant];
  ++inputs_;
  ++c.inputs;
  ++all_.inputs;
  if (o.kind == Outcome::Ok)
    return true;
  (o.kind == Outcome::Crashed ? c.crashes : o.kind == Outcome::Hung ? c.hangs : c.failures)++;
  (o.kind == Outcome::Crashed ? all_.crashes : o.kind == Outcome::Hung ? all_.hangs : all_.failures)++;
  const std::string what = o.kind == Outcome::Crashed ? "CRASH" : o.kind == Outcome::Hung ? "HANG" : "FAILURE";
  const std::string repro = reproducer ? reproducer() : std::string();
  auto known = known_.find(variant);
  if (known == known_.end())
    known = known_.find("*");
  if (known != known_.end() && o.message.find(known->second.second) == std::string::npos)
    known = known_.end();
  std::ostringstream line;
  line << (known != known_.end() ? "KNOWN " : "") << what << " " << kind_ << "/" << variant << " seed " << seed << ": "
       << o.message << (repro.empty() ? "" : "\n    reproducer: " + repro);
  if (known != known_.end())
  {
    ++c.known;
    ++all_.known;
    ++known_hits_[known->first];
    line << "\n    (known failure, reported: " << known->second.first << ")";
  }
  std::printf("%s\n", line.str().c_str());
  std::fflush(stdout);
  if (known != known_.end())
    return true;
  ++unexpected_;
  if (first_.size() < 5)
    first_.push_back(line.str());
  return false;
}

void Tally::print() const
{
  std::printf("fuzz kind %s: inputs=%d crashes=%d hangs=%d failures=%d known=%d\n", kind_.c_str(), all_.inputs,
              all_.crashes, all_.hangs, all_.failures, all_.known);
  std::string cases;
  for (const auto& [name, c] : cases_)
  {
    cases += " " + name + "=" + std::to_string(c.inputs);
    if (c.crashes + c.hangs + c.failures)
      cases += "(" + std::to_string(c.crashes) + "c/" + std::to_string(c.hangs) + "h/" + std::to_string(c.failures) +
               "f)";
  }
  std::printf("  cases:%s\n", cases.c_str());
  for (const auto& [name, why] : known_)
    std::printf("  known failure %s/%s: %s (%d of %d inputs)\n", kind_.c_str(), name.c_str(), why.first.c_str(),
                known_hits_.count(name) ? known_hits_.at(name) : 0,
                name == "*" ? all_.inputs : cases_.count(name) ? cases_.at(name).inputs : 0);
  std::fflush(stdout);
}

}  // namespace fuzz
}  // namespace action_flow
