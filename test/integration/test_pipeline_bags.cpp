// The whole live pipeline on synthetic recordings, as a user runs it: a model trained with `train`,
// bags written by `synth`, each played through `roslaunch action_flow bag.launch` (nodelet
// manager, depth_image_proc, tracker, flow, descriptor, classifier), and a fakenect dump written by
// `synth --fakenect` played through `roslaunch action_flow kinect.launch backend:=freenect` (the
// Kinect v1 driver on libfreenect's replay library); labels read off the topic.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace
{
const std::string kBin = ACTION_FLOW_BIN_DIR;
const std::string kScripts = ACTION_FLOW_SOURCE_DIR "/scripts";

std::string run(const std::string& cmd, int& status)
{
  std::string out;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  char buf[4096];
  while (p && std::fgets(buf, sizeof(buf), p))
    out += buf;
  status = p ? ::pclose(p) : -1;
  return out;
}

// One model for every case here: trained once on p01-p03 performing walk, pick_up and get_up.
class Pipeline : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    dir_ = ::testing::TempDir() + "action_flow_pipeline";
    std::system(("rm -rf '" + dir_ + "' && mkdir -p '" + dir_ + "'").c_str());
    train_output_ = run(kBin + "/train --synth ias --people 3 --repetitions 1 --actions walk,pick_up,get_up --output '" +
                            dir_ + "/model' --cache '" + dir_ + "/cache' --jobs 2",
                        train_status_);
  }
  static void TearDownTestSuite() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void SetUp() override { ASSERT_EQ(train_status_, 0) << train_output_; }

  static std::string dir_, train_output_;
  static int train_status_;
};
std::string Pipeline::dir_, Pipeline::train_output_;
int Pipeline::train_status_ = -1;
}  // namespace

TEST_F(Pipeline, RecognisesActionsOfAnUnseenActorFromBags)
{
  const std::string& dir = dir_;
  int status = 0;
  std::string out;
  std::set<std::string> right;
  std::string table;
  for (const std::string action : { "walk", "pick_up", "get_up" })
  {
    out = run(kBin + "/synth --out '" + dir + "/" + action + "' --people 4 --person p04 --action " + action +
                  " --repetitions 1 --raw-images --quiet",
              status);
    ASSERT_EQ(status, 0) << out;
    const std::string bag = dir + "/" + action + "/ias/p04_" + action + "_1.bag";
    out = run("/usr/bin/python3 " + kScripts + "/label_bag.py '" + bag + "' '" + dir + "/model' --timeout 150", status);
    std::istringstream words(out);
    std::string label;
    words >> label;
    table += action + " -> " + (status == 0 ? label : "(no label)") + "\n";
    if (status == 0 && label == action)
      right.insert(action);
  }
  EXPECT_GE(right.size(), 2u) << "truth -> recognised:\n" << table;
  std::printf("%s", table.c_str());
}

TEST_F(Pipeline, LabelsAnUnseenActorFromAFakenectDumpThroughKinectLaunch)
{
  int status = 0;
  std::string out = run(kBin + "/synth --out '" + dir_ + "/fakenect' --people 4 --person p04 --action get_up" +
                            " --repetitions 1 --fakenect --quiet",
                        status);
  ASSERT_EQ(status, 0) << out;
  const std::string dump = dir_ + "/fakenect/ias/p04_get_up_1.fakenect";
  out = run("/usr/bin/python3 " + kScripts + "/label_bag.py '" + dump + "' '" + dir_ + "/model' --timeout 150", status);
  ASSERT_EQ(status, 0) << out;
  std::istringstream words(out);
  std::string label;
  words >> label;
  EXPECT_EQ(label, "get_up") << out;
  std::printf("fakenect dump: get_up -> %s\n", label.c_str());
  std::system(("rm -rf '" + dir_ + "/fakenect'").c_str());
}

// A user's own actions, recorded from a sensor (a Kinect v1 replaying fakenect dumps of p01-p03
// performing walk and get_up once each), with record.launch; a model trained on the recordings'
// index; then one of them performing get_up again (another repetition, never recorded) recognised
// through kinect.launch with that model, as a user who trained on their own actions would.
TEST_F(Pipeline, RecordTrainAndRecogniseYourOwnActionsFromAKinect)
{
  const std::string recordings = dir_ + "/recordings", dumps = dir_ + "/dumps";
  int status = 0, port = 11431;
  std::string out;
  for (const std::string person : { "p01", "p02", "p03" })
    for (const std::string action : { "walk", "get_up" })
    {
      out = run(kBin + "/synth --out '" + dumps + "' --people 4 --person " + person + " --action " + action +
                    " --repetitions 1 --fakenect --quiet",
                status);
      ASSERT_EQ(status, 0) << out;
      const std::string dump = dumps + "/ias/" + person + "_" + action + "_1.fakenect";
      const std::string p = std::to_string(port++);
      out = run("PATH=/usr/bin:/bin:$PATH ROS_MASTER_URI=http://localhost:" + p + " timeout 150 roslaunch -p " + p +
                    " action_flow record.launch backend:=freenect device_uri:='" + dump + "' person:=" + person +
                    " action:=" + action + " dir:='" + recordings + "' idle_stop:=2",
                status);
      EXPECT_NE(out.find("added to " + recordings + "/index.csv"), std::string::npos) << out;
      std::system(("rm -rf '" + dump + "'").c_str());
    }
  std::ifstream index(recordings + "/index.csv");
  std::string line;
  int rows = -1;  // the header
  while (std::getline(index, line))
    rows += !line.empty();
  ASSERT_EQ(rows, 6) << "every recording in the index";

  out = run(kBin + "/train --index '" + recordings + "/index.csv' --output '" + recordings + "/model' --cache '" +
                recordings + "/cache' --jobs 2",
            status);
  ASSERT_EQ(status, 0) << out;

  out = run(kBin + "/synth --out '" + dumps + "' --people 4 --person p02 --action get_up --repetitions 2 --repetition 2" +
                " --fakenect --quiet",
            status);
  ASSERT_EQ(status, 0) << out;
  out = run("/usr/bin/python3 " + kScripts + "/label_bag.py '" + dumps + "/ias/p02_get_up_2.fakenect' '" + recordings +
                "/model' --timeout 150 --port 11441",
            status);
  ASSERT_EQ(status, 0) << out;
  std::istringstream words(out);
  std::string label;
  words >> label;
  EXPECT_EQ(label, "get_up") << out;
  std::printf("recorded, trained, recognised: get_up -> %s\n", label.c_str());
}
