#include "tracker_appearance.h"

#include <algorithm>
#include <cmath>

namespace action_flow
{
namespace
{
// The histogram of the points @p point(k) gives for k < n (see Appearance).
template <typename PointAt>
Appearance::Histogram histogramOf(std::size_t n, const PointAt& point)
{
  constexpr int kChroma = Appearance::kChromaBins, kBright = Appearance::kBrightnessBins;
  Appearance::Histogram chroma = Appearance::Histogram::Zero(), bright = Appearance::Histogram::Zero();
  const auto bin = [](float v, int bins) { return std::min(bins - 1, std::max(0, static_cast<int>(v * bins))); };
  for (std::size_t k = 0; k < n; ++k)
  {
    const PointT& p = point(k);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    const float sum = static_cast<float>(p.r) + p.g + p.b;
    bright(kChroma * kChroma + bin(sum / (3.0f * 256.0f), kBright)) += 1.0f;
    if (sum >= 30.0f)
      chroma(bin(p.r / sum, kChroma) * kChroma + bin(p.g / sum, kChroma)) += 1.0f;
  }
  Appearance::Histogram out = Appearance::Histogram::Zero();
  const float c = chroma.sum(), b = bright.sum();
  if (b > 0.0f)
    out += (c > 0.0f ? 0.5f : 1.0f) * bright / b;
  if (c > 0.0f)
    out += 0.5f * chroma / c;
  return out;
}
}  // namespace

Appearance::Histogram Appearance::histogram(const Cloud& cloud)
{
  return histogramOf(cloud.size(), [&](std::size_t k) -> const PointT& { return cloud.points[k]; });
}

Appearance::Histogram Appearance::histogram(const Cloud& cloud, const pcl::Indices& indices, std::size_t stride)
{
  stride = std::max<std::size_t>(1, stride);
  return histogramOf((indices.size() + stride - 1) / stride, [&](std::size_t k) -> const PointT& {
    return cloud.points[static_cast<std::size_t>(indices[k * stride])];
  });
}

void Appearance::add(const Cloud& cloud, float height) { add(histogram(cloud), height); }

void Appearance::add(const Histogram& h, float height)
{
  if (h.sum() <= 0.0f)
    return;
  ++frames_;
  const float w = std::max(1.0f / static_cast<float>(frames_), 0.1f);
  colours_ = (1.0f - w) * colours_ + w * h;
  height_ = (1.0f - w) * height_ + w * height;
}

float Appearance::colourDistance(const Histogram& colours) const
{
  Appearance one;
  one.add(colours, 0.0f);
  return colourDistance(one);
}

float Appearance::colourDistance(const Appearance& other) const
{
  if (frames_ == 0 || other.frames_ == 0)
    return 1.0f;
  // In double, over the histograms' own sums: the float histograms sum to 1 only to a few ulps, and
  // the square root turns a BC of 1 - 1e-7 into a distance of 3e-4 (its order depended on how the sum
  // was vectorised).
  double bc = 0.0, sum_a = 0.0, sum_b = 0.0;
  for (Eigen::Index i = 0; i < colours_.size(); ++i)
  {
    bc += std::sqrt(double(colours_[i]) * double(other.colours_[i]));
    sum_a += colours_[i];
    sum_b += other.colours_[i];
  }
  if (!(sum_a > 0.0 && sum_b > 0.0))
    return 1.0f;
  bc /= std::sqrt(sum_a * sum_b);
  return float(std::sqrt(std::max(0.0, 1.0 - std::min(1.0, bc))));
}

}  // namespace action_flow
