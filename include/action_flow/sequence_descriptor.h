/**
 * @file sequence_descriptor.h
 * @brief The sequence descriptor: F frame descriptors evenly spaced in time, concatenated.
 */
#pragma once

#include <action_flow/pca.h>

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace action_flow
{
/**
 * @brief Picks @p frames indices evenly spaced in time over a sequence.
 *
 * Target times are t_first + k (t_last - t_first) / (F - 1), k = 0..F-1 (the middle time when
 * F = 1); each takes the frame nearest in time (the earlier one on a tie). So the first and last
 * frames are always chosen, and a sequence shorter than F repeats frames: each target time takes
 * its nearest frame, so the result stays in time order and every frame is used about F/N times.
 * If all stamps are equal, indices are spread evenly over positions instead.
 *
 * @param stamps non-decreasing frame times (s)
 * @throws std::invalid_argument if @p stamps is empty, not sorted, not finite, or frames < 1
 */
std::vector<std::size_t> selectFrames(const std::vector<double>& stamps, int frames);

/** @brief Builds sequence descriptors from frame descriptors. */
class SequenceDescriptor
{
public:
  /** @throws std::invalid_argument if frames < 1. */
  explicit SequenceDescriptor(int frames = 30);
  int frames() const { return frames_; }

  /**
   * @brief Concatenates the selected frame descriptors, each projected on @p pca when given
   *        (an empty Pca means no projection).
   * @throws std::invalid_argument if @p descriptors is empty, sizes differ from @p stamps, or the
   *         descriptors' length does not match the PCA input
   */
  Eigen::VectorXf compute(const std::vector<Eigen::VectorXf>& descriptors, const std::vector<double>& stamps,
                          const Pca& pca = Pca()) const;

private:
  int frames_;
};

}  // namespace action_flow
