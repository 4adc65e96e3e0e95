#include <action_flow/action_model.h>

#include <action_flow/files.h>
#include <action_flow/posture_flow.h>
#include <action_flow/sequence_descriptor.h>

#include <boost/crc.hpp>

#include <cmath>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <type_traits>

namespace action_flow
{
namespace
{
constexpr char kMagic[8] = { 'A', 'C', 'T', 'F', 'L', 'O', 'W', 'M' };

// Little helpers that append / consume plain values; the file is written and read on the same
// kind of machine (little-endian x86/ARM), which the magic and checksum make safe to assume.
class Writer
{
public:
  template <class T>
  void put(const T& v)
  {
    static_assert(std::is_trivially_copyable<T>::value, "plain values only");
    const char* p = reinterpret_cast<const char*>(&v);
    buf_.insert(buf_.end(), p, p + sizeof(T));
  }
  void putString(const std::string& s)
  {
    put<std::uint64_t>(s.size());
    buf_.insert(buf_.end(), s.begin(), s.end());
  }
  void putMatrix(const Eigen::MatrixXf& m)
  {
    put<std::uint64_t>(m.rows());
    put<std::uint64_t>(m.cols());
    const char* p = reinterpret_cast<const char*>(m.data());
    buf_.insert(buf_.end(), p, p + sizeof(float) * m.size());
  }
  const std::string& bytes() const { return buf_; }

private:
  std::string buf_;
};

class Reader
{
public:
  Reader(const std::string& buf, const std::string& path) : buf_(buf), path_(path) {}
  template <class T>
  T get()
  {
    need(sizeof(T));
    T v;
    std::memcpy(&v, buf_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string getString()
  {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string s = buf_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  Eigen::MatrixXf getMatrix()
  {
    const auto rows = get<std::uint64_t>();
    const auto cols = get<std::uint64_t>();
    // Each side bounded on its own too: an empty matrix of 0 x 2^60 fits in no bytes, yet walking it
    // (the finiteness check below) would never end.
    constexpr std::uint64_t kMaxSide = 1u << 26;
    if (rows > kMaxSide || cols > kMaxSide || (cols != 0 && rows > (buf_.size() - pos_) / sizeof(float) / cols))
      fail("a matrix of " + std::to_string(rows) + "x" + std::to_string(cols) + " does not fit in the file");
    Eigen::MatrixXf m(rows, cols);
    need(sizeof(float) * m.size());
    std::memcpy(m.data(), buf_.data() + pos_, sizeof(float) * m.size());
    if (!m.allFinite())
      fail("a matrix of " + std::to_string(rows) + "x" + std::to_string(cols) + " at offset " + std::to_string(pos_) +
           " holds NaN or infinite values");
    pos_ += sizeof(float) * m.size();
    return m;
  }
  bool done() const { return pos_ == buf_.size(); }
  [[noreturn]] void fail(const std::string& what) const
  {
    throw ModelError("model file '" + path_ + "': " + what);
  }

private:
  void need(std::size_t n) const
  {
    if (n > buf_.size() - pos_)
      fail("truncated (needs " + std::to_string(n) + " more bytes at offset " + std::to_string(pos_) + ")");
  }
  const std::string& buf_;
  std::string path_;
  std::size_t pos_ = 0;
};

std::uint32_t crc32(const std::string& bytes)
{
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

// The parameters as (name, text) pairs, in RecognitionParams::visit's order (param_table.h).
void putParams(Writer& w, const RecognitionParams& p)
{
  const std::vector<ParamEntry> entries = paramEntries(p);
  w.put<std::uint64_t>(entries.size());
  for (const ParamEntry& e : entries)
  {
    w.putString(e.name);
    w.putString(e.value);
  }
}

// Parameters the file does not name keep the struct's defaults (a newer build may add some), except
// those whose default changed with the format: a file of @p version 5 or older was written before
// the pyramid's maxima, and its weights are for means only; one of version 6 or older, before its
// Fourier magnitudes.
RecognitionParams getParams(Reader& r, std::uint32_t version)
{
  constexpr std::uint32_t kFirstVersionWithMaxima = 6, kFirstVersionWithFourier = 7;
  RecognitionParams p;
  if (version < kFirstVersionWithMaxima)
    p.pyramid.max_pooling = false;
  if (version < kFirstVersionWithFourier)
    p.pyramid.fourier = 0;
  const auto n = r.get<std::uint64_t>();
  if (n > 1000)
    r.fail("implausible number of parameters " + std::to_string(n));
  for (std::uint64_t i = 0; i < n; ++i)
  {
    const std::string name = r.getString(), value = r.getString();
    // Files written before the person clouds' voxel size was declared in the tracker's parameters
    // alone name it here too; the tracker's person_voxel_size is what shapes the clouds.
    if (name == "voxel_size")
      continue;
    try
    {
      if (!setParam(p, name, value))
        r.fail("unknown parameter '" + name + "' (written by a newer build?)");
    }
    catch (const std::invalid_argument& e)
    {
      r.fail(std::string("parameter ") + e.what());
    }
  }
  const std::string problem = p.pyramid.problem();
  if (!problem.empty())
    r.fail(problem);
  return p;
}

// @p version 4 files end before the temperature: they load uncalibrated.
void readLinear(Reader& r, ActionModel& m, std::uint32_t version)
{
  const auto n = r.get<std::uint64_t>();
  if (n > 100000)
    r.fail("implausible number of classes " + std::to_string(n));
  std::vector<std::string> classes;
  for (std::uint64_t i = 0; i < n; ++i)
    classes.push_back(r.getString());
  Eigen::MatrixXf w = r.getMatrix(), b = r.getMatrix(), mean = r.getMatrix(), scale = r.getMatrix();
  const double temperature = version >= 5 ? r.get<double>() : 0.0;
  if (n == 0 && w.size() == 0)
    return;
  if (b.cols() != 1 || mean.cols() != 1 || scale.cols() != 1)
    r.fail("linear classifier: bias, mean and scale must be vectors");
  try
  {
    m.linear = LinearClassifier(classes, w, b.col(0), mean.col(0), scale.col(0), temperature);
  }
  catch (const std::invalid_argument& e)
  {
    r.fail(std::string("linear classifier: ") + e.what());
  }
}
}  // namespace

std::string toString(Recognizer r)
{
  return paramText(r);
}

Recognizer recognizerFromString(const std::string& name)
{
  Recognizer r;
  parseParam(name, r);
  return r;
}

RecognitionParams defaultRecognitionParams()
{
  RecognitionParams p;
  p.recognizer = Recognizer::PostureFlow;
  return p;
}

int frameDescriptorLength(const RecognitionParams& p)
{
  return p.recognizer == Recognizer::Paper ? 3 * p.grid.cells() : PostureFlowDescriptor(p.grid).size();
}

Eigen::VectorXf frameDescriptor(const RecognitionParams& p, const Cloud& cloud, const FlowVectors& flow,
                                const PersonFrame& where)
{
  if (p.recognizer == Recognizer::Paper)
    return GridDescriptor(p.grid).compute(flow, where);
  return PostureFlowDescriptor(p.grid).compute(cloud, flow, where);
}

std::string describeDifferences(const RecognitionParams& m, const RecognitionParams& r)
{
  const std::vector<ParamEntry> model = paramEntries(m), runtime = paramEntries(r);
  std::string out;
  for (std::size_t i = 0; i < model.size(); ++i)
    if (model[i].shapes == Shapes::Frames && model[i].value != runtime[i].value)
      out += (out.empty() ? "" : "; ") + model[i].name + ": model " + model[i].value + ", runtime " + runtime[i].value;
  return out;
}

void ActionModel::save(const std::string& path) const
{
  const auto fail = [&](const std::string& what) { throw ModelError("model file '" + path + "': " + what); };
  if (descriptors.rows() != static_cast<Eigen::Index>(labels.size()) || labels.size() != persons.size())
    fail("cannot save: descriptors, labels and persons differ in number");
  if (params.use_pca != !pca.empty())
    fail("cannot save: use_pca does not agree with the PCA basis");
  Writer w;
  putParams(w, params);
  w.putMatrix(pca.mean());
  w.putMatrix(pca.basis());
  w.putMatrix(pca.variances());
  w.putMatrix(descriptors);
  w.put<std::uint64_t>(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i)
  {
    w.putString(labels[i]);
    w.putString(persons[i]);
  }
  w.put<std::uint64_t>(linear.classes().size());
  for (const auto& c : linear.classes())
    w.putString(c);
  w.putMatrix(linear.weights());
  w.putMatrix(linear.bias());
  w.putMatrix(linear.mean());
  w.putMatrix(linear.scale());
  w.put<double>(linear.temperature());
  const std::string& payload = w.bytes();
  std::string file(kMagic, sizeof(kMagic));
  const std::uint32_t version = kFormatVersion, crc = crc32(payload);
  const std::uint64_t size = payload.size();
  file.append(reinterpret_cast<const char*>(&version), sizeof(version));
  file.append(reinterpret_cast<const char*>(&size), sizeof(size));
  file.append(reinterpret_cast<const char*>(&crc), sizeof(crc));
  file += payload;
  try
  {
    writeTextAtomically(path, file);
  }
  catch (const std::runtime_error& e)
  {
    throw ModelError(std::string("model file '") + path + "': " + e.what());
  }
}

ActionModel ActionModel::load(const std::string& path)
{
  const std::string why = whyNotARegularFile(path);
  if (!why.empty())
    throw ModelError("model file '" + path + "': " + why);
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw ModelError("model file '" + path + "': cannot open (missing or unreadable)");
  const std::string file((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  Reader header(file, path);
  char magic[sizeof(kMagic)];
  for (char& c : magic)
    c = header.get<char>();
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    header.fail("not an action_flow model (bad magic)");
  const auto version = header.get<std::uint32_t>();
  if (version < kOldestReadableVersion || version > kFormatVersion)
    header.fail("format version " + std::to_string(version) + ", this build reads versions " +
                std::to_string(kOldestReadableVersion) + "-" + std::to_string(kFormatVersion) +
                "; retrain the model with this build's train");
  const auto size = header.get<std::uint64_t>();
  const auto crc = header.get<std::uint32_t>();
  const std::size_t head = sizeof(kMagic) + 4 + 8 + 4;
  if (file.size() - head != size)
    header.fail("truncated or padded: payload is " + std::to_string(file.size() - head) + " bytes, header says " +
                std::to_string(size));
  const std::string payload = file.substr(head);
  if (crc32(payload) != crc)
    header.fail("checksum mismatch (the file is corrupt)");

  Reader r(payload, path);
  ActionModel m;
  m.params = getParams(r, version);
  Eigen::MatrixXf mean = r.getMatrix(), basis = r.getMatrix(), variances = r.getMatrix();
  if (basis.size() > 0)
  {
    if (mean.cols() != 1 || variances.cols() != 1 || mean.rows() != basis.rows() || variances.rows() != basis.cols())
      r.fail("inconsistent PCA basis sizes");
    m.pca = Pca(mean, basis, variances);
  }
  m.descriptors = r.getMatrix();
  const auto n = r.get<std::uint64_t>();
  if (n != static_cast<std::uint64_t>(m.descriptors.rows()))
    r.fail("has " + std::to_string(m.descriptors.rows()) + " descriptors but " + std::to_string(n) + " labels");
  for (std::uint64_t i = 0; i < n; ++i)
  {
    m.labels.push_back(r.getString());
    m.persons.push_back(r.getString());
  }
  readLinear(r, m, version);
  if (!r.done())
    r.fail("unexpected data after the last record");
  if (m.params.use_pca == m.pca.empty())
    r.fail("use_pca does not agree with the stored PCA basis");
  if (m.params.recognizer == Recognizer::Paper && !m.pca.empty() && m.pca.inputSize() != 3 * m.params.grid.cells())
    r.fail("PCA basis of input length " + std::to_string(m.pca.inputSize()) + " does not fit frame descriptors of " +
           std::to_string(3 * m.params.grid.cells()));
  if (m.params.recognizer == Recognizer::PostureFlow &&
      (m.params.pyramid.flow == FlowEncoding::Choose || m.params.pyramid.mirror == MirrorMode::Choose ||
       m.params.pyramid.posture == PostureMode::Choose))
    r.fail("holds settings that were never chosen (flow encoding, posture or mirror)");
  if (m.descriptors.rows() > 0 && m.descriptors.cols() != m.sequenceLength())
    r.fail("descriptor length " + std::to_string(m.descriptors.cols()) + " does not match its parameters (" +
           std::to_string(m.sequenceLength()) + ")");
  const bool wants_linear =
      m.params.recognizer == Recognizer::PostureFlow && m.params.pyramid.classifier == PyramidClassifier::Linear;
  if (wants_linear != !m.linear.empty())
    r.fail(wants_linear ? "the linear classifier's weights are missing" : "holds linear weights it does not use");
  if (wants_linear && m.linear.dimension() != m.sequenceLength())
    r.fail("linear classifier of input length " + std::to_string(m.linear.dimension()) + ", sequences have " +
           std::to_string(m.sequenceLength()));
  if (!wants_linear && m.descriptors.rows() == 0)
    r.fail("holds no training sequence");
  return m;
}

void ActionModel::checkCompatible(const RecognitionParams& runtime, const std::string& path) const
{
  const std::string diff = describeDifferences(params, runtime);
  if (!diff.empty())
    throw ModelError("model file '" + path + "' was made with other parameters: " + diff);
}

Eigen::Index ActionModel::sequenceLength() const
{
  if (params.recognizer == Recognizer::Paper)
    return static_cast<Eigen::Index>(pca.empty() ? 3 * params.grid.cells() : pca.outputSize()) * params.frames;
  const PostureFlowDescriptor layout(params.grid);
  const Eigen::VectorXf probe = selectFrameFeatures(Eigen::VectorXf::Zero(layout.size()), layout, params.pyramid);
  return probe.size() * pyramidParts(params.pyramid.temporal_levels) * params.pyramid.pooling().blocks();
}

Eigen::VectorXf ActionModel::sequence(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps) const
{
  if (params.recognizer == Recognizer::Paper)
    return SequenceDescriptor(params.frames).compute(frames, stamps, pca);
  const PostureFlowDescriptor layout(params.grid);
  std::vector<Eigen::VectorXf> selected;
  selected.reserve(frames.size());
  for (const auto& f : frames)
    selected.push_back(selectFrameFeatures(f, layout, params.pyramid));
  return temporalPyramid(selected, stamps, params.pyramid.temporal_levels, true, params.pyramid.pooling());
}

SequenceClassifier ActionModel::classifier() const
{
  if (params.recognizer == Recognizer::PostureFlow && params.pyramid.classifier == PyramidClassifier::Linear)
    return SequenceClassifier(linear);
  return SequenceClassifier(ActionClassifier(descriptors, labels, params.neighbours));
}

}  // namespace action_flow
