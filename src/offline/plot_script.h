// The tools' pictures: each is drawn by a Python script of the package's scripts/ folder.
#pragma once

#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
/**
 * @brief The path of scripts/@p name: the package's (rospack) inside a ROS environment, the build's
 *        source folder outside one.
 */
std::string scriptPath(const std::string& name);

/**
 * @brief Runs scripts/@p name with python3 on @p arguments (each passed as one word).
 * @throws std::runtime_error "plotting failed: <command>" when the script fails
 */
void runPlotScript(const std::string& name, const std::vector<std::string>& arguments);
}  // namespace tools
}  // namespace action_flow
