// The nodelet chain (pipeline.launch: tracker -> flow -> descriptor, in one manager, reading the
// shipped yaml files) and the offline extraction (train's and evaluate's extractSample) give the
// same frame descriptors for the same clouds: the same tracks, stamps and values, to the bit.
// Both read their parameters from the same place (the nodelets' private namespaces here) and keep
// per-track state by the same rules (TrackTable, FlowTrack).
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <action_flow/FrameDescriptorArray.h>
#include <action_flow/PersonFlow.h>
#include "../../src/offline/feature_extractor.h"
#include <action_flow/ros/params.h>
#include <action_flow/synth/synth.h>

#include <pcl_ros/point_cloud.h>
#include <ros/ros.h>

#include <cmath>
#include <map>
#include <vector>

using namespace action_flow;
using namespace action_flow::synth;

namespace
{
class VectorSource : public FrameSource
{
public:
  VectorSource(const std::vector<Cloud>& clouds, const std::vector<double>& stamps) : clouds_(clouds), stamps_(stamps)
  {
  }
  bool next(Cloud& cloud, double& stamp) override
  {
    if (i_ >= clouds_.size())
      return false;
    cloud = clouds_[i_];
    stamp = stamps_[i_++];
    return true;
  }

private:
  const std::vector<Cloud>& clouds_;
  const std::vector<double>& stamps_;
  std::size_t i_ = 0;
};

struct Row
{
  double stamp;
  std::uint32_t track;
  std::vector<float> values;
};
}  // namespace

TEST(Chain, NodeletsAndOfflineExtractionGiveIdenticalDescriptors)
{
  ros::NodeHandle nh;
  // A rendered person waving, then a jump back in time (a bag looping) for the reset rules.
  SampleSpec spec = iasLabSamples(1, 1, 7).front();
  for (const SampleSpec& s : iasLabSamples(1, 1, 7))
    if (s.action == "wave")
      spec = s;
  const SampleRenderer sample(spec);
  const int n = std::min(sample.frames(), 45);
  std::vector<Cloud> clouds;
  std::vector<double> stamps;
  for (int loop = 0; loop < 2; ++loop)
    for (int i = 0; i < n; ++i)
    {
      Cloud c;
      sample.render(i, c);
      // The stamp as ROS carries it (pcl's microseconds), so both sides see the same double.
      c.header.stamp = static_cast<std::uint64_t>(std::llround(sample.stamp(i) * 1e6));
      stamps.push_back(ros::Time().fromNSec(c.header.stamp * 1000ull).toSec());
      clouds.push_back(std::move(c));
    }

  // Offline, with the parameters the nodelets were given.
  const TrackerParams tracker = readTrackerParams(ros::NodeHandle("people_tracker"));
  const RecognitionParams recognition = readRecognitionParams(ros::NodeHandle("descriptor"));
  ASSERT_EQ(describeDifferences(recognition, readRecognitionParams(ros::NodeHandle("flow"))), "");
  VectorSource source(clouds, stamps);
  const SampleFrames offline = extractSample(source, tracker, { recognition }, /*all_tracks=*/true).front();
  ASSERT_GT(offline.descriptors.rows(), 40) << "the offline extraction found too little to compare";

  // Live: each cloud published, its descriptors awaited before the next.
  test::Collector<FrameDescriptorArray> out(nh, "descriptors");
  ros::Publisher pub = nh.advertise<Cloud>("points", 5);
  ASSERT_TRUE(test::waitFor([&] { return pub.getNumSubscribers() > 0; }, 30.0)) << "the tracker never subscribed";
  for (std::size_t i = 0; i < clouds.size(); ++i)
  {
    pub.publish(clouds[i]);
    ASSERT_TRUE(out.waitForCount(i + 1, 20.0)) << "no descriptors for frame " << i;
  }
  std::vector<Row> live;
  for (const auto& m : out.messages())
    for (const auto& d : m->descriptors)
      if (d.status == PersonFlow::FLOW && !d.values.empty())
        live.push_back({ m->header.stamp.toSec(), d.track_id, d.values });

  ASSERT_EQ(live.size(), static_cast<std::size_t>(offline.descriptors.rows()));
  for (std::size_t r = 0; r < live.size(); ++r)
  {
    EXPECT_EQ(live[r].stamp, offline.stamps[r]) << "row " << r;
    EXPECT_EQ(live[r].track, offline.tracks[r]) << "row " << r;
    ASSERT_EQ(live[r].values.size(), static_cast<std::size_t>(offline.descriptors.cols()));
    int differing = 0;
    for (std::size_t k = 0; k < live[r].values.size(); ++k)
      differing += live[r].values[k] != offline.descriptors(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k));
    EXPECT_EQ(differing, 0) << "row " << r << " (stamp " << live[r].stamp << ", track " << live[r].track << ")";
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_chain");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
