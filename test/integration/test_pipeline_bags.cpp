// The whole live pipeline on synthetic bags, as a user runs it: a model trained with `train`,
// bags written by `synth`, each played through `roslaunch action_flow bag.launch` (nodelet
// manager, depth_image_proc, tracker, flow, descriptor, classifier), labels read off the topic.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
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
}  // namespace

TEST(Pipeline, RecognisesActionsOfAnUnseenActorFromBags)
{
  const std::string dir = ::testing::TempDir() + "action_flow_pipeline";
  std::system(("rm -rf '" + dir + "' && mkdir -p '" + dir + "'").c_str());
  const std::string actions = "walk,pick_up,get_up";
  int status = 0;
  std::string out = run(kBin + "/train --synth ias --people 3 --repetitions 1 --actions " + actions + " --output '" +
                            dir + "/model' --cache '" + dir + "/cache' --jobs 2",
                        status);
  ASSERT_EQ(status, 0) << out;

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
