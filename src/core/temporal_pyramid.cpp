#include <action_flow/temporal_pyramid.h>

#include <cmath>
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

std::string PyramidParams::problem() const
{
  if (temporal_levels < 1 || temporal_levels > 4)
    return "pyramid/temporal_levels " + std::to_string(temporal_levels) + " outside 1..4";
  if (fourier < 0 || fourier > kMaxFourier)
    return "pyramid/fourier " + std::to_string(fourier) + " outside 0.." + std::to_string(kMaxFourier);
  if (!(geometry_weight >= 0.0f) || !std::isfinite(geometry_weight))
    return "pyramid/geometry_weight " + std::to_string(geometry_weight) + " is not a finite value >= 0";
  if (!(c >= 0.0) || !std::isfinite(c))
    return "pyramid/c " + std::to_string(c) + " is not a finite value >= 0";
  return "";
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

namespace
{
// @throws std::invalid_argument as temporalPyramid documents
void checkPyramidInputs(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps, int levels,
                        const Pooling& pooling)
{
  if (frames.empty() || frames.size() != stamps.size())
    throw std::invalid_argument("temporalPyramid: needs as many stamps as frames, and at least one frame");
  if (levels < 1 || levels > 4)
    throw std::invalid_argument("temporalPyramid: levels must be 1..4");
  if (pooling.fourier < 0 || pooling.fourier > kMaxFourier)
    throw std::invalid_argument("temporalPyramid: Fourier coefficients must be 0.." + std::to_string(kMaxFourier));
  for (std::size_t i = 0; i < frames.size(); ++i)
  {
    if (frames[i].size() != frames.front().size())
      throw std::invalid_argument("temporalPyramid: frames differ in length");
    if (!std::isfinite(stamps[i]) || (i > 0 && stamps[i] < stamps[i - 1]))
      throw std::invalid_argument("temporalPyramid: stamps must be finite and non-decreasing");
  }
}

// Where each frame lies in the sequence, in [0,1]: by time, or by position when all stamps are equal.
std::vector<double> positions(const std::vector<double>& stamps)
{
  const double t0 = stamps.front(), span = stamps.back() - stamps.front();
  std::vector<double> out(stamps.size());
  for (std::size_t i = 0; i < stamps.size(); ++i)
    out[i] = span > 0.0             ? (stamps[i] - t0) / span
             : stamps.size() > 1 ? static_cast<double>(i) / static_cast<double>(stamps.size() - 1)
                                 : 0.0;
  return out;
}

// The frames of part p of @p parts, which covers positions [p/parts, (p+1)/parts), the last one
// closed; a part no frame falls in takes the frame nearest its middle.
void partMembers(const std::vector<double>& position, int parts, int p, std::vector<std::size_t>& members)
{
  members.clear();
  for (std::size_t i = 0; i < position.size(); ++i)
    if (std::min(parts - 1, static_cast<int>(position[i] * parts)) == p)
      members.push_back(i);
  if (!members.empty())
    return;
  const double middle = (p + 0.5) / parts;
  std::size_t best = 0;
  double best_d = 1e300;
  for (std::size_t i = 0; i < position.size(); ++i)
  {
    if (std::abs(position[i] - middle) < best_d)
    {
      best_d = std::abs(position[i] - middle);
      best = i;
    }
  }
  members.push_back(best);
}

// What one part holds (Pooling), written to @p out from @p at on: the mean, the maxima, then the
// Fourier magnitudes. @p deviations and @p basis are scratch space kept between parts.
void poolPart(const std::vector<Eigen::VectorXf>& frames, const std::vector<std::size_t>& members, const Pooling& pooling,
              Eigen::VectorXf& out, Eigen::Index& at, Eigen::MatrixXf& deviations, Eigen::MatrixXf& basis)
{
  const Eigen::Index length = frames.front().size();
  const float n = static_cast<float>(members.size());
  Eigen::VectorXf sum = Eigen::VectorXf::Zero(length);
  for (std::size_t i : members)
    sum += frames[i];
  const Eigen::VectorXf mean = sum / n;
  out.segment(at, length) = mean;
  at += length;
  if (pooling.maxima)
  {
    Eigen::VectorXf peak = frames[members.front()];
    for (std::size_t i : members)
      peak = peak.cwiseMax(frames[i]);
    out.segment(at, length) = peak;
    at += length;
  }
  if (pooling.fourier == 0)
    return;
  // Coefficients 1..K of the part's frames, taken in order (equal steps, as the stamps nearly are),
  // less their mean: the same for 0 < k < n, and 0 where k aliases to the mean (k = n, 2n...). One
  // product: (values x n deviations) times (n x 2K cosines and sines).
  const Eigen::Index count = static_cast<Eigen::Index>(members.size());
  const int K = pooling.fourier;
  deviations.resize(length, count);
  basis.resize(count, 2 * K);
  for (Eigen::Index j = 0; j < count; ++j)
  {
    deviations.col(j) = frames[members[static_cast<std::size_t>(j)]] - mean;
    for (int k = 1; k <= K; ++k)
    {
      const double angle = 2.0 * M_PI * k * static_cast<double>(j) / static_cast<double>(count);
      basis(j, k - 1) = static_cast<float>(std::cos(angle));
      basis(j, K + k - 1) = static_cast<float>(std::sin(angle));
    }
  }
  const Eigen::MatrixXf coefficients = deviations * basis;
  for (int k = 0; k < K; ++k)
  {
    out.segment(at, length) =
        (coefficients.col(k).array().square() + coefficients.col(K + k).array().square()).sqrt().matrix() / n;
    at += length;
  }
}
}  // namespace

Eigen::VectorXf temporalPyramid(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps,
                                int levels, bool power, Pooling pooling)
{
  checkPyramidInputs(frames, stamps, levels, pooling);
  const std::vector<double> position = positions(stamps);
  Eigen::VectorXf out(frames.front().size() * pyramidParts(levels) * pooling.blocks());
  Eigen::Index at = 0;
  std::vector<std::size_t> members;
  Eigen::MatrixXf deviations, basis;
  for (int l = 0; l < levels; ++l)
    for (int p = 0; p < (1 << l); ++p)
    {
      partMembers(position, 1 << l, p, members);
      poolPart(frames, members, pooling, out, at, deviations, basis);
    }
  if (power)
    out = out.unaryExpr([](float v) { return std::copysign(std::sqrt(std::abs(v)), v); });
  return out;
}

}  // namespace action_flow
