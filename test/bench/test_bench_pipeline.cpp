// The whole-pipeline benchmark (launch/bench_pipeline.launch), a short closed-loop run: the
// bench_player nodelet writes its results, and they say that every frame it published came out of
// the classifier, in order, with a positive finite latency. No timing thresholds.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <ros/package.h>
#include <ros/ros.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace
{
std::string g_output;
int g_frames = 0;
double g_wait = 90.0;

std::vector<std::vector<std::string>> readCsv(const std::string& path, std::string& header)
{
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::getline(in, header);
  std::string line;
  while (std::getline(in, line))
  {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ','))
      cells.push_back(cell);
    if (!line.empty() && line.back() == ',')
      cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}
}  // namespace

TEST(BenchPipeline, EveryFrameReachesTheClassifierInOrder)
{
  namespace fs = std::filesystem;
  const std::string summary_path = g_output + "/summary.json";
  // The player writes summary.json last, through a temporary name: once it exists, all files do.
  const auto until = ros::WallTime::now() + ros::WallDuration(g_wait);
  while (!fs::exists(summary_path) && ros::WallTime::now() < until && ros::ok())
    ros::WallDuration(0.2).sleep();
  ASSERT_TRUE(fs::exists(summary_path)) << "no " << summary_path << " within " << g_wait << " s";

  nlohmann::json s;
  std::ifstream(summary_path) >> s;
  for (const char* key :
       { "complete", "mode", "frames_requested", "frames_published", "frames_processed", "frames_dropped",
         "frames_out_of_order", "states_unmatched", "frames_with_person", "fps", "cpu_cores", "player_cpu_cores",
         "latency_ms", "label_latency_ms", "copy_ms", "rss_mb", "rss_growth_mb_per_1000_frames", "bag_frames",
         "load_average_start", "wall_s" })
    EXPECT_TRUE(s.contains(key)) << "summary.json lacks " << key;
  ASSERT_TRUE(s.value("complete", false)) << s.value("error", std::string());
  EXPECT_EQ(s["mode"], "max");
  // Results are kept in the project: a bag inside the package is recorded relative to it.
  const std::string package = ros::package::getPath("action_flow");
  ASSERT_FALSE(package.empty());
  for (const auto& bag : s["bags"])
    EXPECT_NE(bag.get<std::string>().rfind(package + "/", 0), 0u) << bag << " under " << package;
  EXPECT_EQ(s["frames_requested"].get<int>(), g_frames);
  EXPECT_EQ(s["frames_published"].get<int>(), g_frames);
  EXPECT_EQ(s["frames_processed"].get<int>(), g_frames) << "frames lost in a closed loop";
  EXPECT_EQ(s["frames_dropped"].get<int>(), 0);
  EXPECT_EQ(s["frames_out_of_order"].get<int>(), 0);
  EXPECT_EQ(s["states_unmatched"].get<int>(), 0);
  // The synthetic actor stands in the middle of the picture: the tracker must find him.
  EXPECT_GE(s["frames_with_person"].get<int>(), g_frames / 2) << "the tracker missed the person";
  EXPECT_GT(s["fps"].get<double>(), 0.0);
  EXPECT_GT(s["cpu_cores"].get<double>(), 0.0);
  ASSERT_TRUE(s["latency_ms"].is_object());
  const double median = s["latency_ms"]["median"], p95 = s["latency_ms"]["p95"], max = s["latency_ms"]["max"];
  EXPECT_TRUE(std::isfinite(median) && median > 0.0) << median;
  EXPECT_LE(median, p95);
  EXPECT_LE(p95, max);
  EXPECT_TRUE(std::isfinite(max));
  EXPECT_GT(s["rss_mb"]["max"].get<double>(), 0.0);

  std::string header;
  const auto frames = readCsv(g_output + "/frames.csv", header);
  EXPECT_EQ(header, "frame,stamp_us,published_s,arrived_s,latency_ms,arrival_order,tracks");
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(g_frames));
  unsigned long long last_stamp = 0;
  double last_arrival = -1.0;
  for (std::size_t i = 0; i < frames.size(); ++i)
  {
    const auto& r = frames[i];
    ASSERT_EQ(r.size(), 7u) << "frames.csv row " << i;
    EXPECT_EQ(std::stoul(r[0]), i);
    const unsigned long long stamp = std::stoull(r[1]);
    EXPECT_GT(stamp, last_stamp) << "stamps must increase (row " << i << ")";
    last_stamp = stamp;
    ASSERT_FALSE(r[4].empty()) << "no states for frame " << i;
    const double latency = std::stod(r[4]), arrived = std::stod(r[3]);
    EXPECT_TRUE(std::isfinite(latency) && latency > 0.0) << "frame " << i << ": " << latency;
    EXPECT_EQ(std::stoi(r[5]), static_cast<int>(i)) << "states arrived out of order";
    EXPECT_GT(arrived, last_arrival);
    EXPECT_GE(arrived, std::stod(r[2])) << "states before the frame was published (row " << i << ")";
    last_arrival = arrived;
  }

  const auto samples = readCsv(g_output + "/samples.csv", header);
  ASSERT_GE(samples.size(), 2u);
  EXPECT_EQ(samples.front()[0], "0");
  EXPECT_EQ(samples.back()[0], std::to_string(g_frames));
  for (const auto& r : samples)
    EXPECT_GT(std::stod(r[2]), 0.0) << "RSS";

  // Each stage's latency once a second, from /diagnostics: every stage of the chain reports.
  const auto stages = readCsv(g_output + "/stages.csv", header);
  EXPECT_EQ(header, "at_s,stage,latency_ms");
  std::map<std::string, int> seen;
  for (const auto& r : stages)
  {
    ASSERT_EQ(r.size(), 3u);
    const double at = std::stod(r[0]), ms = std::stod(r[2]);
    EXPECT_GE(at, 0.0);
    EXPECT_LE(at, s["wall_s"].get<double>() + 1.0);
    EXPECT_TRUE(std::isfinite(ms) && ms > 0.0) << r[1] << ": " << ms;
    ++seen[r[1]];
  }
  for (const char* stage : { "people_tracker: people tracker", "flow: flow", "descriptor: descriptor",
                             "classifier: classifier" })
    EXPECT_GE(seen[stage], 1) << "no latency from " << stage << " in stages.csv";
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_bench_pipeline");
  ros::NodeHandle pnh("~");
  pnh.getParam("output", g_output);
  pnh.getParam("frames", g_frames);
  pnh.getParam("wait", g_wait);
  // A summary from an earlier run must not pass for this one (the player writes it only at its end).
  std::filesystem::remove(g_output + "/summary.json");
  return RUN_ALL_TESTS();
}
