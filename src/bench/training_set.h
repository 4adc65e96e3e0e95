/**
 * @file training_set.h
 * @brief Random but realistic frame-descriptor sequences, to time classification against a
 *        training set of the paper's size without rendering hundreds of actions.
 *
 * Each action moves a few body regions (a handful of the 64 grid cubes) along its own periodic
 * trajectory; each performance varies amplitude, pace, phase and direction a little and adds
 * sparse noise where the flow's outlier rejection lets some through. Frame descriptors are
 * L2-normalised SUMFLOW vectors as GridDescriptor makes them, so the PCA keeps a similar number of
 * components as on real data (the paper: 61 of 192 at 99 % variance).
 */
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace action_flow
{
namespace bench
{
/** @brief One performance: its frame descriptors, their stamps and its action. */
struct DescriptorSequence
{
  std::vector<Eigen::VectorXf> frames;
  std::vector<double> stamps;
  std::string label;
};

/**
 * @brief @p count sequences of @p actions actions (round robin), 1.3-5 s at 30 fps each.
 * @param descriptor_size 3 x grid cells (192 for the paper's 4x4x4 grid)
 */
std::vector<DescriptorSequence> makeSequences(int count, int actions, int descriptor_size, std::uint32_t seed);

}  // namespace bench
}  // namespace action_flow
