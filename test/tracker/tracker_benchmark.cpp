// Per-frame time of PeopleTracker::update on the real 640x480 clouds in ../shared/data/real_rgbd,
// with what it found in each. Not a test: prints figures.
//   tracker_benchmark [--runs N] [--hog FILE] [--data DIR]
#include "real_data.h"

#include <action_flow/people_tracker.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

using namespace action_flow;

namespace
{
void run(const std::string& name, const Cloud& cloud, const TrackerParams& params, int runs)
{
  // Each run is a fresh tracker: the first frame of a stream, ground search included (the worst case),
  // then one more frame of the same tracker (the steady state: ground refined, tracks associated).
  std::vector<double> first, steady;
  TrackerResult last;
  for (int r = 0; r < runs; ++r)
  {
    PeopleTracker tracker(params);
    auto t0 = std::chrono::steady_clock::now();
    tracker.update(cloud, 0.0);
    auto t1 = std::chrono::steady_clock::now();
    last = tracker.update(cloud, 0.1);
    auto t2 = std::chrono::steady_clock::now();
    first.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    steady.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  std::sort(first.begin(), first.end());
  std::sort(steady.begin(), steady.end());
  std::printf("%-45s %zu points: median %.1f ms first frame, %.1f ms next frame (%d runs); ground %s "
              "(%.3f %.3f %.3f %.3f), %zu people%s\n",
              name.c_str(), cloud.size(), first[first.size() / 2], steady[steady.size() / 2], runs,
              last.ground_valid ? "found" : "NOT found", last.ground[0], last.ground[1], last.ground[2], last.ground[3],
              last.people.size(), last.hog_applied ? " (HOG applied)" : "");
  for (const auto& p : last.people)
  {
    const float dist = std::hypot(p.position.x(), p.position.z());
    std::printf("    id %u at (%.2f %.2f %.2f), %.2f m away, height %.2f m, %zu points at %.2f m, hog %.2f\n", p.id,
                p.position.x(), p.position.y(), p.position.z(), dist, p.height, p.cloud->size(),
                params.person_voxel_size, p.hog_confidence);
  }
}
}  // namespace

int main(int argc, char** argv)
{
  int runs = 30;
  std::string data = test::dataDir();
  TrackerParams params;
  params.confirm_after = 1;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--hog" && i + 1 < argc)
      params.hog_classifier_file = argv[++i];
    else if (a == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (a == "--max-range" && i + 1 < argc)
      params.max_range = std::atof(argv[++i]);
    else if (a == "--min-height" && i + 1 < argc)
      params.min_height = std::atof(argv[++i]);
    else
    {
      std::fprintf(stderr, "tracker_benchmark: unknown argument '%s' (use --runs N, --hog FILE, --data DIR, "
                           "--max-range M, --min-height M)\n", a.c_str());
      return 2;
    }
  }
  const std::string dir = data + "/real_rgbd";
  const auto bags = test::listFiles(dir, "tue_hsr_person_", ".bag");
  const std::string pcd = dir + "/pcl_five_people.pcd";
  if (bags.empty() && !test::fileExists(pcd))
  {
    std::fprintf(stderr, "tracker_benchmark: no real data in %s\n", dir.c_str());
    return 1;
  }
  try
  {
    if (test::fileExists(pcd))
      run("pcl_five_people.pcd", test::loadPcd(pcd), params, runs);
    for (const auto& b : bags)
      run(b.substr(b.rfind('/') + 1), test::loadTueBag(b), params, runs);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "tracker_benchmark: %s\n", e.what());
    return 1;
  }
  return 0;
}
