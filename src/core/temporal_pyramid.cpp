#include <action_flow/temporal_pyramid.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace action_flow
{
std::string toString(PyramidClassifier c)
{
  return paramText(c);
}

PyramidClassifier pyramidClassifierFromString(const std::string& name)
{
  PyramidClassifier c;
  parseParam(name, c);
  return c;
}

Eigen::VectorXf selectFrameFeatures(const Eigen::VectorXf& full, const PostureFlowDescriptor& layout,
                                    const PyramidParams& params)
{
  if (full.size() != layout.size())
    throw std::invalid_argument("selectFrameFeatures: frame descriptor of length " + std::to_string(full.size()) +
                                ", expected " + std::to_string(layout.size()));
  if (params.flow == FlowEncoding::Choose)
    throw std::invalid_argument("selectFrameFeatures: the flow encoding has not been chosen yet");
  if (params.posture == PostureMode::Choose)
    throw std::invalid_argument("selectFrameFeatures: whether to use posture has not been chosen yet");
  const bool bins = params.flow == FlowEncoding::Bins;
  const bool posture = params.posture == PostureMode::On;
  const int per_cell = (posture ? 1 : 0) + (bins ? 6 : 3);
  const int first = params.coarse_to_fine ? 0 : PostureFlowDescriptor::kLevels - 1;
  int cells = 0;
  for (int l = first; l < PostureFlowDescriptor::kLevels; ++l)
    cells += layout.cells(l);
  Eigen::VectorXf out(cells * per_cell + (params.geometry ? kGeometryValues : 0));
  int at = 0;
  for (int l = first; l < PostureFlowDescriptor::kLevels; ++l)
    for (int c = 0; c < layout.cells(l); ++c)
    {
      const auto cell = full.segment<kPostureFlowValuesPerCell>(layout.offset(l) + kPostureFlowValuesPerCell * c);
      if (posture)
        out[at++] = cell[0];
      for (int a = 0; a < 3; ++a)
        if (bins)
        {
          out[at++] = cell[1 + 2 * a];
          out[at++] = cell[2 + 2 * a];
        }
        else
          out[at++] = cell[1 + 2 * a] - cell[2 + 2 * a];
    }
  if (params.geometry)
    out.tail(kGeometryValues) = params.geometry_weight * full.segment<kGeometryValues>(layout.geometryOffset());
  return out;
}

int pyramidParts(int levels)
{
  return (1 << levels) - 1;
}

Eigen::VectorXf temporalPyramid(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps,
                                int levels, bool power, Pooling pooling)
{
  if (frames.empty() || frames.size() != stamps.size())
    throw std::invalid_argument("temporalPyramid: needs as many stamps as frames, and at least one frame");
  if (levels < 1 || levels > 4)
    throw std::invalid_argument("temporalPyramid: levels must be 1..4");
  const Eigen::Index length = frames.front().size();
  for (std::size_t i = 0; i < frames.size(); ++i)
  {
    if (frames[i].size() != length)
      throw std::invalid_argument("temporalPyramid: frames differ in length");
    if (!std::isfinite(stamps[i]) || (i > 0 && stamps[i] < stamps[i - 1]))
      throw std::invalid_argument("temporalPyramid: stamps must be finite and non-decreasing");
  }
  const double t0 = stamps.front(), span = stamps.back() - stamps.front();
  // Where frame i lies in the sequence, in [0,1]: by time, or by position when all stamps are equal.
  const auto position = [&](std::size_t i) {
    if (span > 0.0)
      return (stamps[i] - t0) / span;
    return frames.size() > 1 ? static_cast<double>(i) / static_cast<double>(frames.size() - 1) : 0.0;
  };
  const bool with_max = pooling == Pooling::MeanMax;
  Eigen::VectorXf out(length * pyramidParts(levels) * (with_max ? 2 : 1));
  Eigen::Index at = 0;
  for (int l = 0; l < levels; ++l)
  {
    const int parts = 1 << l;
    for (int p = 0; p < parts; ++p)
    {
      // Part p covers positions [p/parts, (p+1)/parts), the last one closed.
      Eigen::VectorXf sum = Eigen::VectorXf::Zero(length);
      Eigen::VectorXf peak = Eigen::VectorXf::Constant(length, -std::numeric_limits<float>::infinity());
      int n = 0;
      for (std::size_t i = 0; i < frames.size(); ++i)
      {
        const int in = std::min(parts - 1, static_cast<int>(position(i) * parts));
        if (in == p)
        {
          sum += frames[i];
          if (with_max)
            peak = peak.cwiseMax(frames[i]);
          ++n;
        }
      }
      if (n == 0)  // a part no frame falls in: the frame nearest its middle
      {
        const double middle = (p + 0.5) / parts;
        std::size_t best = 0;
        double best_d = 1e300;
        for (std::size_t i = 0; i < frames.size(); ++i)
        {
          if (std::abs(position(i) - middle) < best_d)
          {
            best_d = std::abs(position(i) - middle);
            best = i;
          }
        }
        sum = peak = frames[best];
        n = 1;
      }
      out.segment(at, length) = sum / static_cast<float>(n);
      at += length;
      if (with_max)
      {
        out.segment(at, length) = peak;
        at += length;
      }
    }
  }
  if (power)
    out = out.unaryExpr([](float v) { return std::copysign(std::sqrt(std::abs(v)), v); });
  return out;
}

}  // namespace action_flow
