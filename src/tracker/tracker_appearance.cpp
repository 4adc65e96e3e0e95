#include "tracker_appearance.h"

#include <algorithm>
#include <cmath>

namespace action_flow
{
Appearance::Histogram Appearance::histogram(const Cloud& cloud)
{
  Histogram chroma = Histogram::Zero(), bright = Histogram::Zero();
  const auto bin = [](float v, int n) { return std::min(n - 1, std::max(0, static_cast<int>(v * n))); };
  for (const PointT& p : cloud.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    const float sum = static_cast<float>(p.r) + p.g + p.b;
    bright(kChromaBins * kChromaBins + bin(sum / (3.0f * 256.0f), kBrightnessBins)) += 1.0f;
    if (sum >= 30.0f)
      chroma(bin(p.r / sum, kChromaBins) * kChromaBins + bin(p.g / sum, kChromaBins)) += 1.0f;
  }
  Histogram out = Histogram::Zero();
  const float c = chroma.sum(), b = bright.sum();
  if (b > 0.0f)
    out += (c > 0.0f ? 0.5f : 1.0f) * bright / b;
  if (c > 0.0f)
    out += 0.5f * chroma / c;
  return out;
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
