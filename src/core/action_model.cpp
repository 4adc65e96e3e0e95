#include <action_flow/action_model.h>

#include <boost/crc.hpp>

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
    if (cols != 0 && rows > (buf_.size() - pos_) / sizeof(float) / cols)
      fail("a matrix of " + std::to_string(rows) + "x" + std::to_string(cols) + " does not fit in the file");
    Eigen::MatrixXf m(rows, cols);
    need(sizeof(float) * m.size());
    std::memcpy(m.data(), buf_.data() + pos_, sizeof(float) * m.size());
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

void putParams(Writer& w, const RecognitionParams& p)
{
  w.put(p.voxel_size);
  w.put<std::int32_t>(p.flow.k);
  w.put<std::uint8_t>(p.flow.reciprocal);
  w.put<std::uint8_t>(p.flow.reject_outliers);
  w.put(p.flow.min_speed);
  w.put(p.flow.isolation_speed);
  w.put(p.flow.neighbour_radius);
  w.put<std::int32_t>(p.grid.parts_x);
  w.put<std::int32_t>(p.grid.parts_y);
  w.put<std::int32_t>(p.grid.parts_z);
  w.put(p.grid.width);
  w.put(p.grid.height);
  w.put(p.grid.depth);
  w.put(p.grid.reference_height);
  w.put<std::int32_t>(p.grid.aggregation == FlowAggregation::Sum ? 0 : 1);
  w.put<std::int32_t>(p.frames);
  w.put<std::uint8_t>(p.use_pca);
  w.put(p.pca_variance);
  w.put<std::int32_t>(p.neighbours);
}

RecognitionParams getParams(Reader& r)
{
  RecognitionParams p;
  p.voxel_size = r.get<float>();
  p.flow.k = r.get<std::int32_t>();
  p.flow.reciprocal = r.get<std::uint8_t>() != 0;
  p.flow.reject_outliers = r.get<std::uint8_t>() != 0;
  p.flow.min_speed = r.get<float>();
  p.flow.isolation_speed = r.get<float>();
  p.flow.neighbour_radius = r.get<float>();
  p.grid.parts_x = r.get<std::int32_t>();
  p.grid.parts_y = r.get<std::int32_t>();
  p.grid.parts_z = r.get<std::int32_t>();
  p.grid.width = r.get<float>();
  p.grid.height = r.get<float>();
  p.grid.depth = r.get<float>();
  p.grid.reference_height = r.get<float>();
  const auto agg = r.get<std::int32_t>();
  if (agg != 0 && agg != 1)
    r.fail("unknown descriptor type code " + std::to_string(agg));
  p.grid.aggregation = agg == 0 ? FlowAggregation::Sum : FlowAggregation::Mean;
  p.frames = r.get<std::int32_t>();
  p.use_pca = r.get<std::uint8_t>() != 0;
  p.pca_variance = r.get<double>();
  p.neighbours = r.get<std::int32_t>();
  return p;
}

template <class T>
void compare(std::ostringstream& out, const char* name, const T& model, const T& runtime)
{
  if (model == runtime)
    return;
  if (out.tellp() > 0)
    out << "; ";
  out << name << ": model " << model << ", runtime " << runtime;
}
}  // namespace

std::string describeDifferences(const RecognitionParams& m, const RecognitionParams& r)
{
  std::ostringstream out;
  compare(out, "voxel_size", m.voxel_size, r.voxel_size);
  compare(out, "flow.k", m.flow.k, r.flow.k);
  compare(out, "flow.reciprocal", m.flow.reciprocal, r.flow.reciprocal);
  compare(out, "flow.reject_outliers", m.flow.reject_outliers, r.flow.reject_outliers);
  compare(out, "flow.min_speed", m.flow.min_speed, r.flow.min_speed);
  compare(out, "flow.isolation_speed", m.flow.isolation_speed, r.flow.isolation_speed);
  compare(out, "flow.neighbour_radius", m.flow.neighbour_radius, r.flow.neighbour_radius);
  compare(out, "grid.parts_x", m.grid.parts_x, r.grid.parts_x);
  compare(out, "grid.parts_y", m.grid.parts_y, r.grid.parts_y);
  compare(out, "grid.parts_z", m.grid.parts_z, r.grid.parts_z);
  compare(out, "grid.width", m.grid.width, r.grid.width);
  compare(out, "grid.height", m.grid.height, r.grid.height);
  compare(out, "grid.depth", m.grid.depth, r.grid.depth);
  compare(out, "grid.reference_height", m.grid.reference_height, r.grid.reference_height);
  compare(out, "descriptor", toString(m.grid.aggregation), toString(r.grid.aggregation));
  compare(out, "frames", m.frames, r.frames);
  return out.str();
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
  const std::string& payload = w.bytes();
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f)
      fail("cannot open '" + tmp + "' for writing");
    f.write(kMagic, sizeof(kMagic));
    const std::uint32_t version = kFormatVersion, crc = crc32(payload);
    const std::uint64_t size = payload.size();
    f.write(reinterpret_cast<const char*>(&version), sizeof(version));
    f.write(reinterpret_cast<const char*>(&size), sizeof(size));
    f.write(reinterpret_cast<const char*>(&crc), sizeof(crc));
    f.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    if (!f.flush())
      fail("write failed (disk full?)");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    fail("cannot rename the temporary file into place");
  }
}

ActionModel ActionModel::load(const std::string& path)
{
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
  if (version != kFormatVersion)
    header.fail("format version " + std::to_string(version) + ", this build reads version " +
                std::to_string(kFormatVersion) + "; retrain the model");
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
  m.params = getParams(r);
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
  if (!r.done())
    r.fail("unexpected data after the last record");
  if (m.params.use_pca == m.pca.empty())
    r.fail("use_pca does not agree with the stored PCA basis");
  const Eigen::Index per_frame = m.pca.empty() ? 3 * m.params.grid.cells() : m.pca.outputSize();
  if (m.descriptors.rows() > 0 && m.descriptors.cols() != per_frame * m.params.frames)
    r.fail("descriptor length " + std::to_string(m.descriptors.cols()) + " does not match its parameters (" +
           std::to_string(per_frame * m.params.frames) + ")");
  return m;
}

void ActionModel::checkCompatible(const RecognitionParams& runtime, const std::string& path) const
{
  const std::string diff = describeDifferences(params, runtime);
  if (!diff.empty())
    throw ModelError("model file '" + path + "' was made with other parameters: " + diff);
}

ActionClassifier ActionModel::classifier() const
{
  return ActionClassifier(descriptors, labels, params.neighbours);
}

}  // namespace action_flow
