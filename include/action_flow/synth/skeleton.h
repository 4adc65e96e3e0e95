/**
 * @file skeleton.h
 * @brief The 15-joint skeleton that OpenNI/NITE tracks, and the MSR Action3D skeleton file parser.
 *        ROS-free.
 */
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace action_flow
{
namespace synth
{
/** @brief The 15 joints of OpenNI/NITE (openni_tracker's frames, without the "_<user>" suffix). */
enum class Joint : int
{
  Head = 0,
  Neck,
  Torso,
  LeftShoulder,
  LeftElbow,
  LeftHand,
  RightShoulder,
  RightElbow,
  RightHand,
  LeftHip,
  LeftKnee,
  LeftFoot,
  RightHip,
  RightKnee,
  RightFoot
};
constexpr int kJointCount = 15;

/** @brief The joints of one body side's arm and leg. */
struct LimbJoints
{
  Joint shoulder, elbow, hand, hip, knee, foot;
};

/** @brief The limb joints of the person's left (@p side 0) or right (@p side 1) side. */
inline LimbJoints limbJoints(int side)
{
  return side == 0 ? LimbJoints{ Joint::LeftShoulder, Joint::LeftElbow, Joint::LeftHand,
                                 Joint::LeftHip,      Joint::LeftKnee,  Joint::LeftFoot }
                   : LimbJoints{ Joint::RightShoulder, Joint::RightElbow, Joint::RightHand,
                                 Joint::RightHip,      Joint::RightKnee,  Joint::RightFoot };
}

/** @brief openni_tracker's name of a joint: "head", "neck", "torso", "left_shoulder", ... "right_foot". */
const std::string& jointName(Joint j);

/**
 * @brief Joint positions of one frame. "Left" is the person's own left. The frame of the positions
 *        is stated where a skeleton is returned.
 */
struct Skeleton
{
  std::array<Eigen::Vector3f, kJointCount> joints;

  Eigen::Vector3f& operator[](Joint j) { return joints[static_cast<int>(j)]; }
  const Eigen::Vector3f& operator[](Joint j) const { return joints[static_cast<int>(j)]; }
};

/**
 * @brief One MSR Action3D skeleton file: 20 joints per frame at 15 fps, as recorded.
 *
 * Positions are as in the file (metres; x, y up, z away from the camera). The files' x axis is
 * mirrored with respect to a real camera's view: the subjects used their right arm, and its joints
 * (the second of each pair) lie at larger x. Frames whose 20 joints are all exactly zero were not
 * tracked; they are kept here and flagged.
 */
struct MsrSkeletonFile
{
  std::string path;
  int action = 0, subject = 0, take = 0;   ///< from the file name aAA_sSS_eEE_skeleton3D.txt (0 if absent)
  /** frames[f][k] = joint k+1 of the file's numbering (1..20) in frame f. */
  std::vector<std::array<Eigen::Vector3f, 20>> frames;
  std::vector<std::array<float, 20>> confidence;
  std::vector<bool> tracked;               ///< false where all 20 joints are zero
  int trackedFrames() const;
};

/**
 * @brief Reads an MSR Action3D skeleton file.
 * @throws std::runtime_error "<path>:<line>: <what is wrong>" on a line that is not four numbers, a
 *         confidence outside [0,1], a non-finite value, or a line count that is not a multiple of 20;
 *         "<path>: cannot open" if unreadable.
 */
MsrSkeletonFile parseMsrSkeletonFile(const std::string& path);

/** @brief The 20 MSR Action3D action names in snake_case, index 0 = action 01 ("high_arm_wave"). */
const std::vector<std::string>& msrActions();

/**
 * @brief Converts one MSR frame to the 15 OpenNI joints in the MSR camera frame un-mirrored
 *        (x right as a real camera sees it, y up, z away): hands are the file's hand joints,
 *        feet its ankles, torso its spine joint.
 */
Skeleton msrToOpenNi(const std::array<Eigen::Vector3f, 20>& frame);

}  // namespace synth
}  // namespace action_flow
