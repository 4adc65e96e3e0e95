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
  const float bc = (colours_.cwiseProduct(other.colours_)).cwiseSqrt().sum();
  return std::sqrt(std::max(0.0f, 1.0f - std::min(1.0f, bc)));
}

}  // namespace action_flow
