// The OpenNI joint names and the MSR Action3D skeleton file parser.
#include <action_flow/files.h>
#include <action_flow/synth/skeleton.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
namespace synth
{
const std::string& jointName(Joint j)
{
  static const std::array<std::string, kJointCount> names = {
    "head",          "neck",           "torso",       "left_shoulder", "left_elbow",
    "left_hand",     "right_shoulder", "right_elbow", "right_hand",    "left_hip",
    "left_knee",     "left_foot",      "right_hip",   "right_knee",    "right_foot"
  };
  const int k = static_cast<int>(j);
  if (k < 0 || k >= kJointCount)
    throw std::out_of_range("jointName: no joint " + std::to_string(k));
  return names[k];
}

int MsrSkeletonFile::trackedFrames() const
{
  int n = 0;
  for (bool t : tracked)
    n += t ? 1 : 0;
  return n;
}

MsrSkeletonFile parseMsrSkeletonFile(const std::string& path)
{
  const std::string why = whyNotARegularFile(path);
  if (!why.empty())
    throw std::runtime_error(path + ": " + why);
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error(path + ": cannot open");
  MsrSkeletonFile file;
  file.path = path;
  static const std::regex name_re(R"(a(\d\d)_s(\d\d)_e(\d\d)_skeleton3D\.txt$)");
  std::smatch m;
  if (std::regex_search(path, m, name_re))
  {
    file.action = std::stoi(m[1]);
    file.subject = std::stoi(m[2]);
    file.take = std::stoi(m[3]);
  }
  std::string line;
  int line_no = 0, joint = 0;
  std::array<Eigen::Vector3f, 20> frame;
  std::array<float, 20> conf{};
  bool all_zero = true;
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + what);
  };
  while (std::getline(in, line))
  {
    ++line_no;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    std::istringstream ls(line);
    double v[4];
    for (int k = 0; k < 4; ++k)
      if (!(ls >> v[k]))
        fail("expected four numbers 'x y z confidence', got '" + line + "'");
    std::string rest;
    if (ls >> rest)
      fail("expected four numbers 'x y z confidence', got '" + line + "'");
    for (double x : v)
      if (!std::isfinite(x))
        fail("non-finite value in '" + line + "'");
    if (v[3] < 0.0 || v[3] > 1.0)
      fail("confidence " + std::to_string(v[3]) + " outside [0,1]");
    frame[joint] = Eigen::Vector3f(float(v[0]), float(v[1]), float(v[2]));
    if (!frame[joint].allFinite())  // finite as a double, but not as the float it is kept in (1e300)
      fail("value out of range in '" + line + "'");
    conf[joint] = float(v[3]);
    all_zero = all_zero && v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0;
    if (++joint == 20)
    {
      file.frames.push_back(frame);
      file.confidence.push_back(conf);
      file.tracked.push_back(!all_zero);
      joint = 0;
      all_zero = true;
    }
  }
  if (joint != 0)
    fail("file ends inside a frame (" + std::to_string(joint) + " of 20 joint lines)");
  if (file.frames.empty())
    throw std::runtime_error(path + ":1: no frames");
  return file;
}

const std::vector<std::string>& msrActions()
{
  static const std::vector<std::string> names = {
    "high_arm_wave", "horizontal_arm_wave", "hammer",     "hand_catch",  "forward_punch",
    "high_throw",    "draw_x",              "draw_tick",  "draw_circle", "hand_clap",
    "two_hand_wave", "side_boxing",         "bend",       "forward_kick", "side_kick",
    "jogging",       "tennis_swing",        "tennis_serve", "golf_swing", "pick_up_and_throw"
  };
  return names;
}

Skeleton msrToOpenNi(const std::array<Eigen::Vector3f, 20>& f)
{
  // File numbering (1-based): 1,2 shoulders; 3 neck; 4 spine; 5,6 hips; 7 hip centre; 8,9 elbows;
  // 10,11 wrists; 12,13 hands; 14,15 knees; 16,17 ankles; 18,19 feet; 20 head. The first of each
  // pair is the left side, the second the right (the side the subjects were asked to use).
  const auto p = [&](int k) { return Eigen::Vector3f(-f[k - 1].x(), f[k - 1].y(), f[k - 1].z()); };
  Skeleton s;
  s[Joint::Head] = p(20);
  s[Joint::Neck] = p(3);
  s[Joint::Torso] = p(4);
  s[Joint::LeftShoulder] = p(1);
  s[Joint::LeftElbow] = p(8);
  s[Joint::LeftHand] = p(12);
  s[Joint::RightShoulder] = p(2);
  s[Joint::RightElbow] = p(9);
  s[Joint::RightHand] = p(13);
  s[Joint::LeftHip] = p(5);
  s[Joint::LeftKnee] = p(14);
  s[Joint::LeftFoot] = p(16);
  s[Joint::RightHip] = p(6);
  s[Joint::RightKnee] = p(15);
  s[Joint::RightFoot] = p(17);
  return s;
}

}  // namespace synth
}  // namespace action_flow
