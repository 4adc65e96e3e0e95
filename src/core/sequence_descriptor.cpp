#include <action_flow/sequence_descriptor.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace action_flow
{
std::vector<std::size_t> selectFrames(const std::vector<double>& stamps, int frames)
{
  if (frames < 1)
    throw std::invalid_argument("selectFrames: need at least one frame per sequence");
  if (stamps.empty())
    throw std::invalid_argument("selectFrames: the sequence has no frames");
  for (std::size_t i = 0; i < stamps.size(); ++i)
  {
    if (!std::isfinite(stamps[i]) || (i > 0 && stamps[i] < stamps[i - 1]))
      throw std::invalid_argument("selectFrames: frame times must be finite and non-decreasing");
  }
  const std::size_t n = stamps.size();
  const double t0 = stamps.front(), t1 = stamps.back();
  std::vector<std::size_t> out(frames);
  for (int k = 0; k < frames; ++k)
  {
    const double frac = frames == 1 ? 0.5 : static_cast<double>(k) / (frames - 1);
    if (t1 <= t0)
    {
      out[k] = static_cast<std::size_t>(std::lround(frac * (n - 1)));
      continue;
    }
    const double t = t0 + frac * (t1 - t0);
    // First frame at or after t, then the nearer of it and its predecessor.
    const auto it = std::lower_bound(stamps.begin(), stamps.end(), t);
    std::size_t j = static_cast<std::size_t>(it - stamps.begin());
    if (j == n)
      j = n - 1;
    else if (j > 0 && t - stamps[j - 1] <= stamps[j] - t)
      j = j - 1;
    out[k] = j;
  }
  return out;
}

SequenceDescriptor::SequenceDescriptor(int frames) : frames_(frames)
{
  if (frames_ < 1)
    throw std::invalid_argument("SequenceDescriptor: need at least one frame per sequence");
}

Eigen::VectorXf SequenceDescriptor::compute(const std::vector<Eigen::VectorXf>& descriptors,
                                            const std::vector<double>& stamps, const Pca& pca) const
{
  if (descriptors.size() != stamps.size())
    throw std::invalid_argument("SequenceDescriptor: descriptors and stamps differ in number");
  const std::vector<std::size_t> idx = selectFrames(stamps, frames_);
  const Eigen::Index per = pca.empty() ? descriptors.front().size() : pca.outputSize();
  Eigen::VectorXf out(per * frames_);
  for (int k = 0; k < frames_; ++k)
  {
    const Eigen::VectorXf& d = descriptors[idx[k]];
    if (d.size() != descriptors.front().size())
      throw std::invalid_argument("SequenceDescriptor: frame descriptors differ in length");
    out.segment(k * per, per) = pca.project(d);
  }
  return out;
}

}  // namespace action_flow
