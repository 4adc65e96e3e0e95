/**
 * @file tracker_appearance.h
 * @brief What a tracked person looks like, for giving their id back when they return: their height
 *        and the colours of their clothes. ROS-free.
 */
#pragma once

#include <action_flow/types.h>
#include <pcl/types.h>

#include <Eigen/Core>

namespace action_flow
{
/**
 * @brief A person's height and colour histogram, averaged over the frames they were seen in.
 *
 * The histogram counts each point's chromaticity (r/(r+g+b), g/(r+g+b), 6 x 6 bins: the hue and
 * saturation of the clothes, whatever the shading) and, apart, its brightness ((r+g+b)/3, 4 bins),
 * the two halves weighted equally. Black, dark grey and white points (r+g+b below 30) count in
 * brightness only.
 */
class Appearance
{
public:
  static constexpr int kChromaBins = 6, kBrightnessBins = 4;
  static constexpr int kBins = kChromaBins * kChromaBins + kBrightnessBins;
  using Histogram = Eigen::Matrix<float, kBins, 1>;

  /** @brief The histogram of @p cloud's finite points (sums to 1; all zero for no point). */
  static Histogram histogram(const Cloud& cloud);
  /** @brief The histogram of the finite points of @p cloud at @p indices, every @p stride-th. */
  static Histogram histogram(const Cloud& cloud, const pcl::Indices& indices, std::size_t stride = 1);

  /** @brief Adds one frame: a running mean of the first 10 frames, then an exponential mean
   *         (weight 0.1) that follows a person turning or taking off a jacket. */
  void add(const Cloud& cloud, float height);
  /** @brief The same with the frame's histogram (histogram()) already computed. */
  void add(const Histogram& colours, float height);

  /** @brief The Hellinger distance of the colour histograms: 0 for the same, 1 for disjoint ones
   *         (and 1 when either has not been seen). */
  float colourDistance(const Appearance& other) const;
  /** @brief The same against one frame's histogram (histogram()); 1 when either is empty. */
  float colourDistance(const Histogram& colours) const;

  float height() const { return height_; }
  int frames() const { return frames_; }
  const Histogram& colours() const { return colours_; }

private:
  Histogram colours_ = Histogram::Zero();
  float height_ = 0.0f;
  int frames_ = 0;
};

}  // namespace action_flow
