#include "plot_script.h"

#include <ros/package.h>

#include <cstdlib>
#include <stdexcept>

namespace action_flow
{
namespace tools
{
std::string scriptPath(const std::string& name)
{
  // Ask rospack only inside a ROS environment; outside it, the build's source folder.
  const std::string pkg = std::getenv("ROS_PACKAGE_PATH") ? ros::package::getPath("action_flow") : "";
  return (pkg.empty() ? std::string(ACTION_FLOW_SOURCE_DIR) : pkg) + "/scripts/" + name;
}

void runPlotScript(const std::string& name, const std::vector<std::string>& arguments)
{
  std::string cmd = "/usr/bin/python3 '" + scriptPath(name) + "'";
  for (const std::string& a : arguments)
    cmd += " '" + a + "'";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("plotting failed: " + cmd);
}
}  // namespace tools
}  // namespace action_flow
