// Per-frame time of PeopleTracker::update on the real 640x480 clouds in ../shared/data/real_rgbd,
// with what it found in each. Not a test: prints figures.
//   tracker_benchmark [--runs N] [--hog FILE] [--data DIR] [--png DIR] [--probe U,V]... [--candidates]
#include "real_data.h"
#include "../../src/offline/cli.h"

#include <action_flow/people_tracker.h>
#include "../../src/tracker/tracker_detector.h"

#include <pcl/io/png_io.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

using namespace action_flow;

namespace
{
bool show_candidates = false;  // --candidates

/** Writes the cloud's colours as a PNG with a box (and its pixel bounds printed) around each person. */
void writePng(const std::string& path, const Cloud& cloud, const TrackerResult& result)
{
  std::vector<unsigned char> image(3 * cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i)
  {
    image[3 * i] = cloud[i].r;
    image[3 * i + 1] = cloud[i].g;
    image[3 * i + 2] = cloud[i].b;
  }
  Eigen::Matrix<float, 3, 4> P;
  if (cloud.height > 1 && fitProjection(cloud, P))
    for (const auto& p : result.people)
    {
      int u0 = 1 << 20, v0 = 1 << 20, u1 = -1, v1 = -1;
      for (const auto& q : p.cloud->points)
      {
        const Eigen::Vector3f x = P * q.getVector3fMap().homogeneous();
        if (!(x.z() > 0))
          continue;
        const int u = static_cast<int>(x.x() / x.z()), v = static_cast<int>(x.y() / x.z());
        u0 = std::min(u0, u);
        v0 = std::min(v0, v);
        u1 = std::max(u1, u);
        v1 = std::max(v1, v);
      }
      if (u1 < 0)
        continue;
      u0 = std::max(0, u0);
      v0 = std::max(0, v0);
      u1 = std::min<int>(cloud.width - 1, u1);
      v1 = std::min<int>(cloud.height - 1, v1);
      std::printf("    id %u: pixels u %d-%d, v %d-%d\n", p.id, u0, u1, v0, v1);
      const auto paint = [&](int u, int v) {
        unsigned char* c = &image[3 * (static_cast<std::size_t>(v) * cloud.width + u)];
        c[0] = 255;
        c[1] = static_cast<unsigned char>(40 * (p.id % 6));
        c[2] = 0;
      };
      for (int t = 0; t < 2; ++t)
      {
        for (int u = u0; u <= u1; ++u)
        {
          paint(u, std::min(v1, v0 + t));
          paint(u, std::max(v0, v1 - t));
        }
        for (int v = v0; v <= v1; ++v)
        {
          paint(std::min(u1, u0 + t), v);
          paint(std::max(u0, u1 - t), v);
        }
      }
    }
  pcl::io::saveRgbPNGFile(path, image.data(), static_cast<int>(cloud.width), static_cast<int>(cloud.height));
}

/** Prints the median point (camera frame) of the 7x7 pixels around each probe (u, v). */
void probe(const Cloud& cloud, const std::vector<std::pair<int, int>>& probes)
{
  for (const auto& uv : probes)
  {
    std::vector<float> x, y, z;
    for (int v = uv.second - 3; v <= uv.second + 3; ++v)
      for (int u = uv.first - 3; u <= uv.first + 3; ++u)
        if (u >= 0 && v >= 0 && u < static_cast<int>(cloud.width) && v < static_cast<int>(cloud.height) &&
            std::isfinite(cloud.at(u, v).z))
        {
          x.push_back(cloud.at(u, v).x);
          y.push_back(cloud.at(u, v).y);
          z.push_back(cloud.at(u, v).z);
        }
    if (z.empty())
    {
      std::printf("    probe (%d, %d): no depth\n", uv.first, uv.second);
      continue;
    }
    for (auto* c : {&x, &y, &z})
      std::nth_element(c->begin(), c->begin() + c->size() / 2, c->end());
    std::printf("    probe (%d, %d): (%.2f %.2f %.2f), %.2f m away\n", uv.first, uv.second, x[x.size() / 2],
                y[y.size() / 2], z[z.size() / 2], std::hypot(x[x.size() / 2], z[z.size() / 2]));
  }
}

/** Every candidate of one frame with the person-likeness cues computed but not applied. */
void candidates(const Cloud& cloud, TrackerParams params)
{
  params.reject_top_at_border = false;
  params.min_free_fraction = 0.0f;
  params.tracked_min_height = params.min_height;
  PeopleDetector detector(params);
  detector.detect(cloud, Eigen::Vector3f::Zero());
  const DetectionResult r = detector.detect(cloud, Eigen::Vector3f::Zero());
  for (const auto& d : r.people)
    std::printf("    candidate at (%.2f %.2f %.2f), %.2f m away: height %.2f, width %.2f, top row %d, free %.2f, "
                "hog %.2f%s\n", d.centroid.x(), d.centroid.y(), d.centroid.z(), std::hypot(d.centroid.x(), d.centroid.z()),
                d.height, d.width, d.top_row, d.free_fraction, d.hog_confidence, d.weak ? " (weak)" : "");
}

void run(const std::string& name, const Cloud& cloud, const TrackerParams& params, int runs,
         const std::string& png_dir = std::string(), const std::vector<std::pair<int, int>>& probes = {})
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
  if (!png_dir.empty())
    writePng(png_dir + "/" + name + ".png", cloud, last);
  probe(cloud, probes);
  if (show_candidates)
    candidates(cloud, params);
}
}  // namespace

int main(int argc, char** argv)
{
  int runs = 30;
  std::string data = test::dataDir();
  std::string png_dir;  // --png DIR: each frame's colour image with the people boxed
  std::vector<std::pair<int, int>> probes;  // --probe U,V: print the point at that pixel
  TrackerParams params;
  params.confirm_after = 1;
  tools::Options o("usage: tracker_benchmark [options]\nTimes the people tracker on the shared real RGB-D frames.");
  o.value("runs", "N", "timed runs per frame (default 30)")
      .value("hog", "FILE", "the HOG classifier file (default: none)")
      .value("data", "DIR", "the shared data folder (default ../shared/data)")
      .value("max-range", "M", "the tracker's max_range")
      .value("min-height", "M", "the tracker's min_height")
      .value("png", "DIR", "each frame's colour image with the people boxed")
      .value("probe", "U,V", "print the point at that pixel")
      .flag("candidates", "print the detector's candidates");
  try
  {
    const tools::Args args(argc, argv, o);
    if (args.has("help"))
      return o.printHelp();
    runs = static_cast<int>(args.integer("runs", runs, 1, 100000));
    params.hog_classifier_file = args.get("hog", params.hog_classifier_file);
    data = args.get("data", data);
    params.max_range = static_cast<float>(args.number("max-range", params.max_range));
    params.min_height = static_cast<float>(args.number("min-height", params.min_height));
    show_candidates = args.has("candidates");
    png_dir = args.get("png");
    int u = 0, v = 0;
    if (args.has("probe") && std::sscanf(args.get("probe").c_str(), "%d,%d", &u, &v) == 2)
      probes.emplace_back(u, v);
  }
  catch (const std::invalid_argument& e)
  {
    std::fprintf(stderr, "tracker_benchmark: %s (--help lists the options)\n", e.what());
    return 2;
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
      run("pcl_five_people.pcd", test::loadPcd(pcd), params, runs, png_dir, probes);
    for (const auto& b : bags)
      run(b.substr(b.rfind('/') + 1), test::loadTueBag(b), params, runs, png_dir, probes);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "tracker_benchmark: %s\n", e.what());
    return 1;
  }
  return 0;
}
