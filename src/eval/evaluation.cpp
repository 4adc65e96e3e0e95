#include "evaluation.h"
#include "workers.h"

#include <action_flow/files.h>
#include <action_flow/param_table.h>
#include <action_flow/posture_flow.h>
#include <action_flow/sequence_descriptor.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <sys/stat.h>

namespace action_flow
{
namespace
{
std::vector<std::string> splitCsv(const std::string& line)
{
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ','))
    out.push_back(trimmed(field));
  if (!line.empty() && line.back() == ',')
    out.push_back("");
  return out;
}

std::string folderOf(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

int toInt(const std::string& s, const std::string& where, const char* column)
{
  try
  {
    std::size_t used = 0;
    const int v = std::stoi(s, &used);
    if (used == s.size() && v >= 0)
      return v;
  }
  catch (const std::exception&)
  {
  }
  throw DatasetError(where + ": column '" + column + "' must be a non-negative integer, got '" + s + "'");
}
}  // namespace

std::vector<IndexEntry> readIndex(const std::string& path, const std::vector<std::string>& known_actions)
{
  const std::string why = whyNotARegularFile(path);
  if (!why.empty())
    throw DatasetError(path + ": dataset index " + why);
  std::ifstream f(path);
  if (!f)
    throw DatasetError(path + ": cannot open dataset index");
  std::string line;
  int n = 0;
  std::vector<std::string> header;
  while (header.empty() && std::getline(f, line))
  {
    ++n;
    if (!trimmed(line).empty() && trimmed(line)[0] != '#')
      header = splitCsv(line);
  }
  if (header.empty())
    throw DatasetError(path + ": empty dataset index (no header line)");
  // Only the columns read; others (synth's "frames", a note of your own) are ignored.
  const char* columns[] = { "path", "person", "action", "repetition" };
  int col[4];
  for (int c = 0; c < 4; ++c)
  {
    const auto it = std::find(header.begin(), header.end(), columns[c]);
    if (it == header.end())
      throw DatasetError(path + ":" + std::to_string(n) + ": header lacks column '" + columns[c] + "'");
    col[c] = static_cast<int>(it - header.begin());
  }
  std::vector<IndexEntry> out;
  std::set<std::string> seen;
  const std::string base = folderOf(path);
  while (std::getline(f, line))
  {
    ++n;
    if (trimmed(line).empty() || trimmed(line)[0] == '#')
      continue;
    const std::string where = path + ":" + std::to_string(n);
    const auto fields = splitCsv(line);
    if (fields.size() != header.size())
      throw DatasetError(where + ": expected " + std::to_string(header.size()) + " fields, found " +
                         std::to_string(fields.size()));
    for (int c = 0; c < 3; ++c)
      if (fields[col[c]].empty())
        throw DatasetError(where + ": column '" + columns[c] + "' is empty");
    IndexEntry e;
    e.line = n;
    e.path = fields[col[0]][0] == '/' ? fields[col[0]] : base + fields[col[0]];
    e.person = fields[col[1]];
    e.action = fields[col[2]];
    e.repetition = toInt(fields[col[3]], where, "repetition");
    if (!known_actions.empty() && std::find(known_actions.begin(), known_actions.end(), e.action) == known_actions.end())
      throw DatasetError(where + ": unknown action '" + e.action + "'");
    const std::string sample_why = whyNotARegularFile(e.path);
    if (!sample_why.empty())
      throw DatasetError(where + ": sample file '" + e.path + "' " + sample_why);
    if (!seen.insert(e.person + "/" + e.action + "/" + std::to_string(e.repetition)).second)
      throw DatasetError(where + ": duplicate sample (person " + e.person + ", action " + e.action + ", repetition " +
                         std::to_string(e.repetition) + ")");
    out.push_back(e);
  }
  if (out.empty())
    throw DatasetError(path + ": the dataset index lists no samples");
  return out;
}

std::vector<std::string> uniqueSorted(std::vector<std::string> v)
{
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

std::vector<Fold> leaveOnePersonOut(const std::vector<std::string>& persons)
{
  std::vector<Fold> folds;
  for (const auto& p : uniqueSorted(persons))
  {
    Fold f;
    f.name = "test person " + p;
    for (std::size_t i = 0; i < persons.size(); ++i)
      (persons[i] == p ? f.test : f.train).push_back(i);
    folds.push_back(std::move(f));
  }
  return folds;
}

Fold crossSubject(const std::vector<std::string>& persons, const std::vector<std::string>& train_persons)
{
  Fold f;
  f.name = "cross-subject";
  for (std::size_t i = 0; i < persons.size(); ++i)
  {
    const bool train = std::find(train_persons.begin(), train_persons.end(), persons[i]) != train_persons.end();
    (train ? f.train : f.test).push_back(i);
  }
  return f;
}

namespace
{
constexpr char kCacheMagic[8] = { 'A', 'F', 'F', 'R', 'A', 'M', 'E', '1' };
}

void saveSampleFrames(const std::string& path, const SampleFrames& frames)
{
  if (!frames.tracks.empty() && frames.tracks.size() != frames.stamps.size())
    throw DatasetError(path + ": one track id per row expected");
  const std::uint64_t rows = frames.descriptors.rows(), cols = frames.descriptors.cols();
  std::string bytes(kCacheMagic, sizeof(kCacheMagic));
  const auto put = [&](const void* p, std::size_t n) { bytes.append(static_cast<const char*>(p), n); };
  put(&rows, sizeof(rows));
  put(&cols, sizeof(cols));
  put(frames.stamps.data(), sizeof(double) * rows);
  put(frames.descriptors.data(), sizeof(float) * rows * cols);
  if (!frames.tracks.empty())
    put(frames.tracks.data(), sizeof(std::uint32_t) * rows);
  try
  {
    writeTextAtomically(path, bytes);
  }
  catch (const std::runtime_error& e)
  {
    throw DatasetError(std::string("cache file ") + e.what());
  }
}

bool loadSampleFrames(const std::string& path, SampleFrames& frames)
{
  std::ifstream f(path, std::ios::binary);
  if (!f)
    return false;
  char magic[8];
  std::uint64_t rows = 0, cols = 0;
  f.read(magic, sizeof(magic));
  f.read(reinterpret_cast<char*>(&rows), sizeof(rows));
  f.read(reinterpret_cast<char*>(&cols), sizeof(cols));
  if (!f || std::memcmp(magic, kCacheMagic, sizeof(magic)) != 0 || cols > 100000 || rows > 1000000)
    throw DatasetError(path + ": damaged cache file (delete it to recompute)");
  frames.stamps.resize(rows);
  frames.descriptors.resize(rows, cols);
  f.read(reinterpret_cast<char*>(frames.stamps.data()), sizeof(double) * rows);
  f.read(reinterpret_cast<char*>(frames.descriptors.data()), sizeof(float) * rows * cols);
  frames.tracks.clear();
  if (f && rows > 0 && f.peek() != EOF)  // a stream's track ids follow
  {
    frames.tracks.resize(rows);
    f.read(reinterpret_cast<char*>(frames.tracks.data()), sizeof(std::uint32_t) * rows);
  }
  if (!f || f.peek() != EOF)
    throw DatasetError(path + ": damaged cache file (delete it to recompute)");
  return true;
}

Confusion::Confusion(std::vector<std::string> l)
  : labels(std::move(l)), counts(labels.size(), std::vector<int>(labels.size(), 0))
{
}

void Confusion::add(const std::string& truth, const std::string& predicted)
{
  const auto t = std::find(labels.begin(), labels.end(), truth);
  const auto p = std::find(labels.begin(), labels.end(), predicted);
  if (t == labels.end() || p == labels.end())
    throw std::invalid_argument("Confusion: unknown label '" + (t == labels.end() ? truth : predicted) + "'");
  ++counts[t - labels.begin()][p - labels.begin()];
}

void Confusion::add(const std::string& truth, const std::string& predicted, float confidence)
{
  add(truth, predicted);
  reliability.add(confidence, truth == predicted);
}

void Reliability::add(float confidence, bool right)
{
  const double c = std::isfinite(confidence) ? std::clamp(static_cast<double>(confidence), 0.0, 1.0) : 0.0;
  const int bin = std::min(kBins - 1, static_cast<int>(c * kBins));
  ++count[bin];
  correct[bin] += right ? 1 : 0;
  confidence_sum[bin] += c;
}

int Reliability::total() const
{
  return std::accumulate(count.begin(), count.end(), 0);
}

double Reliability::meanConfidence() const
{
  const int n = total();
  return n == 0 ? 0.0 : std::accumulate(confidence_sum.begin(), confidence_sum.end(), 0.0) / n;
}

double Reliability::expectedCalibrationError() const
{
  const int n = total();
  double e = 0.0;
  for (int b = 0; b < kBins; ++b)
    if (count[b] > 0)
      e += std::abs(static_cast<double>(correct[b]) - confidence_sum[b]) / n;
  return e;
}

int Confusion::total() const
{
  int n = 0;
  for (const auto& row : counts)
    for (int c : row)
      n += c;
  return n;
}

double Confusion::accuracy() const
{
  int right = 0;
  for (std::size_t i = 0; i < labels.size(); ++i)
    right += counts[i][i];
  return total() > 0 ? static_cast<double>(right) / total() : 0.0;
}

std::vector<int> Confusion::support() const
{
  std::vector<int> s(labels.size(), 0);
  for (std::size_t i = 0; i < labels.size(); ++i)
    for (int c : counts[i])
      s[i] += c;
  return s;
}

std::vector<double> Confusion::recall() const
{
  const auto s = support();
  std::vector<double> r(labels.size(), 0.0);
  for (std::size_t i = 0; i < labels.size(); ++i)
    r[i] = s[i] > 0 ? static_cast<double>(counts[i][i]) / s[i] : 0.0;
  return r;
}

std::vector<double> Confusion::precision() const
{
  std::vector<double> p(labels.size(), 0.0);
  for (std::size_t j = 0; j < labels.size(); ++j)
  {
    int predicted = 0;
    for (std::size_t i = 0; i < labels.size(); ++i)
      predicted += counts[i][j];
    p[j] = predicted > 0 ? static_cast<double>(counts[j][j]) / predicted : 0.0;
  }
  return p;
}

namespace
{
// Frame descriptors of a sample as a list; one all-zero frame when it has none (a still person).
void framesOf(const LabelledSample& s, int length, std::vector<Eigen::VectorXf>& out, std::vector<double>& stamps)
{
  out.clear();
  stamps.clear();
  if (s.frames && s.frames->descriptors.rows() > 0)
  {
    for (Eigen::Index r = 0; r < s.frames->descriptors.rows(); ++r)
      out.push_back(s.frames->descriptors.row(r).transpose());
    stamps = s.frames->stamps;
  }
  else
  {
    out.push_back(Eigen::VectorXf::Zero(length));
    stamps.push_back(0.0);
  }
}

// The sequence descriptor of a sample mirrored left to right (posture_flow only).
Eigen::VectorXf mirroredSequenceOf(const LabelledSample& sample, const ActionModel& model)
{
  std::vector<Eigen::VectorXf> frames;
  std::vector<double> stamps;
  framesOf(sample, frameDescriptorLength(model.params), frames, stamps);
  const PostureFlowDescriptor layout(model.params.grid);
  for (auto& f : frames)
    f = layout.mirrored(f);
  return model.sequence(frames, stamps);
}

// What a classifier trained without some people answered on their originals: how many were right,
// and the label scores with the true label's column for those whose label it knows (to fit the
// temperature on).
struct HeldOutAnswers
{
  int right = 0, total = 0;
  std::vector<Eigen::VectorXf> scores;
  std::vector<int> truth;

  void add(const HeldOutAnswers& o)
  {
    right += o.right;
    total += o.total;
    scores.insert(scores.end(), o.scores.begin(), o.scores.end());
    truth.insert(truth.end(), o.truth.begin(), o.truth.end());
  }
  double accuracy() const { return total > 0 ? static_cast<double>(right) / total : 0.0; }
  double temperature() const
  {
    if (scores.empty())
      return 0.0;
    Eigen::MatrixXf s(static_cast<Eigen::Index>(scores.size()), scores.front().size());
    for (std::size_t i = 0; i < scores.size(); ++i)
      s.row(static_cast<Eigen::Index>(i)) = scores[i].transpose();
    return fitTemperature(s, truth);
  }
};

// The answers on the originals of the people in @p held_out, trained on everyone else's rows (and
// their mirrored copies, rows n.. of @p g, when @p mirror), for each of @p cs; empty when the fold
// cannot be used. Rows 0..n-1 of @p g are the originals, labelled and owned as @p labels and @p persons.
std::vector<HeldOutAnswers> foldAnswers(const GramRows& g, bool mirror, const std::vector<std::string>& labels,
                                        const std::vector<std::string>& persons,
                                        const std::vector<std::string>& held_out, const std::vector<double>& cs,
                                        const std::vector<bool>* queries)
{
  const Eigen::Index n = static_cast<Eigen::Index>(labels.size());
  std::vector<Eigen::Index> train, test;
  for (Eigen::Index i = 0; i < n; ++i)
    if (std::find(held_out.begin(), held_out.end(), persons[i]) == held_out.end())
      train.push_back(i);
    else if (!queries || (*queries)[i])
      test.push_back(i);
  std::vector<std::string> train_labels;
  for (Eigen::Index i : train)
    train_labels.push_back(labels[i]);
  if (test.empty() || uniqueSorted(train_labels).size() < 2)
    return {};
  if (mirror)
  {
    const std::size_t originals = train.size();
    for (std::size_t i = 0; i < originals; ++i)
    {
      train.push_back(train[i] + n);
      train_labels.push_back(train_labels[i]);
    }
  }
  // Scores count for the temperature only from classifiers that know every label (all of the
  // same length).
  const std::size_t all_labels = uniqueSorted(labels).size();
  std::vector<std::string> known;
  const std::vector<Eigen::MatrixXf> scores = LinearClassifier::heldOutScores(g, train, train_labels, test, cs, known);
  std::vector<HeldOutAnswers> out;
  for (const Eigen::MatrixXf& s : scores)
  {
    HeldOutAnswers a;
    for (std::size_t q = 0; q < test.size(); ++q)
    {
      // The label classify() gives: every probability it offers is monotonic in the score.
      Eigen::VectorXf row = s.row(static_cast<Eigen::Index>(q)).transpose();
      const std::string& truth = labels[test[q]];
      Eigen::Index best = 0;
      row.maxCoeff(&best);
      a.right += known[static_cast<std::size_t>(best)] == truth;
      ++a.total;
      const auto at = std::lower_bound(known.begin(), known.end(), truth);
      if (known.size() == all_labels && at != known.end() && *at == truth)
      {
        a.scores.push_back(std::move(row));
        a.truth.push_back(static_cast<int>(at - known.begin()));
      }
    }
    out.push_back(std::move(a));
  }
  return out;
}

// The rows chooseLinear works on: the originals, then (when given) their mirrored copies.
GramRows stacked(const Eigen::MatrixXf& x, const Eigen::MatrixXf* mirrored)
{
  if (!mirrored)
    return GramRows(x);
  if (mirrored->rows() != x.rows() || mirrored->cols() != x.cols())
    throw std::invalid_argument("chooseLinear: the mirrored rows must match the rows");
  Eigen::MatrixXf both(2 * x.rows(), x.cols());
  both << x, *mirrored;
  return GramRows(std::move(both));
}

// chooseLinear on rows already stacked: @p g's first labels.size() rows are the originals, and
// with @p has_mirrored the next as many are their mirrored copies.
LinearChoice chooseOnRows(const GramRows& g, bool has_mirrored, const std::vector<std::string>& labels,
                          const std::vector<std::string>& persons, const std::vector<bool>& mirror_options,
                          const std::vector<double>& c_options, int inner_folds, const std::vector<bool>* queries)
{
  if (queries && queries->size() != labels.size())
    throw std::invalid_argument("chooseLinear: one query flag per row is needed");
  if (persons.size() != labels.size() ||
      g.rows() != static_cast<Eigen::Index>(labels.size()) * (has_mirrored ? 2 : 1))
    throw std::invalid_argument("chooseLinear: one label and one person per row are needed");
  const std::vector<std::string> people = uniqueSorted(persons);
  const int k = std::min<int>(inner_folds, static_cast<int>(people.size()));
  LinearChoice best{ c_options.front(), mirror_options.front(), -1.0 };
  if (k < 2)
    return best;  // one person: nothing to cross-validate on
  HeldOutAnswers best_answers;
  for (bool m : mirror_options)
  {
    if (m && !has_mirrored)
      throw std::invalid_argument("chooseLinear: mirrored copies are an option but none were given");
    std::vector<double> sum(c_options.size(), 0.0);
    std::vector<HeldOutAnswers> answers(c_options.size());
    int used = 0;
    for (int f = 0; f < k; ++f)
    {
      std::vector<std::string> held_out;
      for (std::size_t p = f; p < people.size(); p += k)
        held_out.push_back(people[p]);
      const std::vector<HeldOutAnswers> a = foldAnswers(g, m, labels, persons, held_out, c_options, queries);
      if (a.empty())
        continue;
      for (std::size_t i = 0; i < a.size(); ++i)
      {
        sum[i] += a[i].accuracy();
        answers[i].add(a[i]);
      }
      ++used;
    }
    for (std::size_t i = 0; i < c_options.size(); ++i)
    {
      const double mean = used > 0 ? sum[i] / used : 0.0;
      if (mean > best.score + 1e-9)  // ties keep the earlier option: no mirror, the smaller C
      {
        best = { c_options[i], m, mean };
        best_answers = std::move(answers[i]);
      }
    }
  }
  // The chosen setting's held-out answers were given by classifiers trained on fewer people than
  // the final one; their temperature is what the final one is calibrated with.
  best.temperature = best_answers.temperature();
  return best;
}
}  // namespace

std::optional<LinearChoice> SelectionMemo::find(const std::string& question) const
{
  const std::lock_guard<std::mutex> lock(mutex_);
  const auto it = answers_.find(question);
  if (it == answers_.end())
    return std::nullopt;
  ++hits_;
  return it->second;
}

void SelectionMemo::add(const std::string& question, const LinearChoice& answer)
{
  const std::lock_guard<std::mutex> lock(mutex_);
  answers_.emplace(question, answer);
}

int SelectionMemo::hits() const
{
  const std::lock_guard<std::mutex> lock(mutex_);
  return hits_;
}

const std::vector<double>& linearCandidates()
{
  static const std::vector<double> c = { 0.001, 0.01, 0.1, 1.0 };
  return c;
}

LinearChoice chooseLinear(const Eigen::MatrixXf& x, const Eigen::MatrixXf* mirrored,
                          const std::vector<std::string>& labels, const std::vector<std::string>& persons,
                          const std::vector<bool>& mirror_options, const std::vector<double>& c_options,
                          int inner_folds, const std::vector<bool>* queries)
{
  return chooseOnRows(stacked(x, mirrored), mirrored != nullptr, labels, persons, mirror_options, c_options,
                      inner_folds, queries);
}

Eigen::VectorXf sequenceOf(const LabelledSample& sample, const ActionModel& model)
{
  std::vector<Eigen::VectorXf> frames;
  std::vector<double> stamps;
  framesOf(sample, frameDescriptorLength(model.params), frames, stamps);
  return model.sequence(frames, stamps);
}

Pca fitPca(const std::vector<LabelledSample>& samples, const std::vector<std::size_t>& rows, double variance)
{
  Eigen::Index total = 0, length = 0;
  for (std::size_t r : rows)
    if (samples[r].frames)
    {
      total += samples[r].frames->descriptors.rows();
      length = std::max(length, samples[r].frames->descriptors.cols());
    }
  if (total < 2)
    throw std::invalid_argument("fitPca: fewer than 2 frame descriptors with flow in the training set");
  Eigen::MatrixXf all(total, length);
  Eigen::Index at = 0;
  for (std::size_t r : rows)
    if (samples[r].frames && samples[r].frames->descriptors.rows() > 0)
    {
      all.middleRows(at, samples[r].frames->descriptors.rows()) = samples[r].frames->descriptors;
      at += samples[r].frames->descriptors.rows();
    }
  return Pca::fit(all, variance);
}

namespace
{
// The sequence descriptors of a model's training rows, and of their mirror images.
struct TrainingRows
{
  const std::vector<LabelledSample>& samples;
  const std::vector<std::size_t>& rows;
  std::vector<std::string> labels, persons;
  std::vector<bool> queries;  // per row: not a training copy

  TrainingRows(const std::vector<LabelledSample>& s, const std::vector<std::size_t>& r) : samples(s), rows(r)
  {
    for (std::size_t i : rows)
    {
      labels.push_back(samples[i].action);
      persons.push_back(samples[i].person);
      queries.push_back(!samples[i].copy);
    }
  }

  // What a cross-validation over these rows under @p model, @p flow and @p posture, with these
  // options, is asked (SelectionMemo): each row's person, action and frame descriptors (by address:
  // the same for every variant of one extraction), every recognition parameter and the options.
  std::string question(const ActionModel& model, FlowEncoding flow, PostureMode posture,
                       const std::vector<bool>& mirror_options, const std::vector<double>& c_options) const
  {
    RecognitionParams probe = model.params;
    probe.pyramid.flow = flow;
    probe.pyramid.posture = posture;
    std::ostringstream q;
    q << "rows";
    for (std::size_t r : rows)
      q << " " << samples[r].person << "/" << samples[r].action << "@" << static_cast<const void*>(samples[r].frames)
        << (samples[r].copy ? "c" : "");
    for (const ParamEntry& e : paramEntries(probe))
      q << " " << e.name << "=" << e.value;
    q << " mirror";
    for (bool m : mirror_options)
      q << " " << m;
    q << " c";
    q.precision(17);
    for (double c : c_options)
      q << " " << c;
    return q.str();
  }

  // Under @p model with the flow encoding @p flow and posture @p posture (mirrored rows only when asked).
  void describe(const ActionModel& model, FlowEncoding flow, PostureMode posture, bool with_mirrored,
                Eigen::MatrixXf& x, Eigen::MatrixXf& mirrored) const
  {
    ActionModel probe = model;
    probe.params.pyramid.flow = flow;
    probe.params.pyramid.posture = posture;
    x.resize(static_cast<Eigen::Index>(rows.size()), probe.sequenceLength());
    for (std::size_t i = 0; i < rows.size(); ++i)
      x.row(static_cast<Eigen::Index>(i)) = sequenceOf(samples[rows[i]], probe).transpose();
    mirrored.resize(with_mirrored ? x.rows() : 0, x.cols());
    for (std::size_t i = 0; with_mirrored && i < rows.size(); ++i)
      mirrored.row(static_cast<Eigen::Index>(i)) = mirroredSequenceOf(samples[rows[i]], probe).transpose();
  }
};

// posture_flow with the linear classifier: C, the mirrored copies, the flow encoding and posture,
// whichever are not fixed, chosen by cross-validation inside the training people (all that @p t
// holds) and written into @p pyramid; @p rows receives the rows under the choice (the originals,
// then their mirrored copies when mirroring was an option). Returns the temperature fitted on the
// chosen setting's held-out answers (0 with fewer than 2 people). Ties keep the earlier option:
// direction bins before sums, posture before none.
double chooseLinearSettings(const TrainingRows& t, const ActionModel& model, PyramidParams& pyramid,
                            std::unique_ptr<GramRows>& rows, SelectionMemo* memo)
{
  std::vector<bool> mirror_options;
  if (pyramid.mirror != MirrorMode::On)
    mirror_options.push_back(false);
  if (pyramid.mirror != MirrorMode::Off)
    mirror_options.push_back(true);
  const std::vector<double> c_options = pyramid.c > 0.0 ? std::vector<double>{ pyramid.c } : linearCandidates();
  // Decided before the loop, which writes pyramid.flow and pyramid.posture.
  std::vector<FlowEncoding> encodings;
  for (FlowEncoding e : { FlowEncoding::Bins, FlowEncoding::Sums })
    if (pyramid.flow == FlowEncoding::Choose || pyramid.flow == e)
      encodings.push_back(e);
  std::vector<PostureMode> postures;
  for (PostureMode p : { PostureMode::On, PostureMode::Off })
    if (pyramid.posture == PostureMode::Choose || pyramid.posture == p)
      postures.push_back(p);
  LinearChoice best;
  bool first = true;
  for (PostureMode p : postures)
    for (FlowEncoding e : encodings)
    {
      const std::string question = memo ? t.question(model, e, p, mirror_options, c_options) : std::string();
      std::unique_ptr<GramRows> g;
      std::optional<LinearChoice> choice = memo ? memo->find(question) : std::nullopt;
      if (!choice)
      {
        Eigen::MatrixXf xe, me;
        t.describe(model, e, p, mirror_options.back(), xe, me);
        g = std::make_unique<GramRows>(stacked(xe, me.size() ? &me : nullptr));
        choice = chooseOnRows(*g, me.size() > 0, t.labels, t.persons, mirror_options, c_options, 3, &t.queries);
        if (memo)
          memo->add(question, *choice);
      }
      if (first || choice->score > best.score + 1e-9)
      {
        first = false;
        best = *choice;
        pyramid.flow = e;
        pyramid.posture = p;
        rows = std::move(g);
      }
    }
  if (!rows)
  {
    // The choice was remembered: the final classifier's rows are described again.
    Eigen::MatrixXf xe, me;
    t.describe(model, pyramid.flow, pyramid.posture, mirror_options.back(), xe, me);
    rows = std::make_unique<GramRows>(stacked(xe, me.size() ? &me : nullptr));
  }
  pyramid.c = best.c;
  pyramid.mirror = best.mirror ? MirrorMode::On : MirrorMode::Off;
  return best.temperature;
}
}  // namespace

ActionModel trainModel(const std::vector<LabelledSample>& samples, const std::vector<std::size_t>& rows,
                       const RecognitionParams& params, const Pca* fitted, SelectionMemo* memo)
{
  if (rows.empty())
    throw std::invalid_argument("trainModel: no training samples");
  ActionModel model;
  model.params = params;
  if (params.recognizer == Recognizer::Paper && params.use_pca)
    model.pca = fitted ? *fitted : fitPca(samples, rows, params.pca_variance);
  const TrainingRows t(samples, rows);
  PyramidParams& pyramid = model.params.pyramid;
  const bool posture_flow = params.recognizer == Recognizer::PostureFlow;
  const bool linear = posture_flow && pyramid.classifier == PyramidClassifier::Linear;
  Eigen::MatrixXf x, mirrored;
  if (linear)
  {
    // The final classifier trains on the rows the choice was made on, sharing their Gram matrix.
    std::unique_ptr<GramRows> g;
    const double temperature = chooseLinearSettings(t, model, pyramid, g, memo);
    const Eigen::Index n = static_cast<Eigen::Index>(t.labels.size());
    const Eigen::Index used = pyramid.mirror == MirrorMode::On ? 2 * n : n;
    std::vector<Eigen::Index> all(static_cast<std::size_t>(used));
    for (Eigen::Index i = 0; i < used; ++i)
      all[static_cast<std::size_t>(i)] = i;
    model.descriptors = g->x().topRows(used);
    model.labels = model.persons = {};
    for (Eigen::Index i = 0; i < used; ++i)
    {
      model.labels.push_back(t.labels[static_cast<std::size_t>(i % n)]);
      model.persons.push_back(t.persons[static_cast<std::size_t>(i % n)]);
    }
    model.linear = LinearClassifier::train(*g, all, model.labels, { pyramid.c }).front().calibrated(temperature);
    return model;
  }
  if (!posture_flow)
    t.describe(model, FlowEncoding::Bins, PostureMode::On, false, x, mirrored);
  else
  {
    // 1-NN has nothing to fit: what is not fixed takes the fuller option.
    if (pyramid.flow == FlowEncoding::Choose)
      pyramid.flow = FlowEncoding::Bins;
    if (pyramid.posture == PostureMode::Choose)
      pyramid.posture = PostureMode::On;
    if (pyramid.mirror == MirrorMode::Choose)
      pyramid.mirror = MirrorMode::On;
    t.describe(model, pyramid.flow, pyramid.posture, pyramid.mirror == MirrorMode::On, x, mirrored);
  }
  model.descriptors = x;
  model.labels = t.labels;
  model.persons = t.persons;
  if (posture_flow && pyramid.mirror == MirrorMode::On)
  {
    model.descriptors.conservativeResize(2 * x.rows(), Eigen::NoChange);
    model.descriptors.bottomRows(x.rows()) = mirrored;
    model.labels.insert(model.labels.end(), t.labels.begin(), t.labels.end());
    model.persons.insert(model.persons.end(), t.persons.begin(), t.persons.end());
  }
  return model;
}

Confusion runFolds(const std::vector<LabelledSample>& samples, const std::vector<Fold>& folds,
                   const RecognitionParams& params, std::vector<double>* fold_accuracy, std::vector<Pca>* fold_pcas,
                   int jobs, std::vector<PyramidParams>* fold_choices, SelectionMemo* memo)
{
  std::vector<std::string> actions;
  for (const auto& s : samples)
    actions.push_back(s.action);
  Confusion all(uniqueSorted(actions));
  const bool reuse = params.use_pca && fold_pcas;
  if (reuse && fold_pcas->size() != folds.size())
  {
    fold_pcas->clear();
    for (const auto& fold : folds)
      fold_pcas->push_back(fold.test.empty() ? Pca() : fitPca(samples, fold.train, params.pca_variance));
  }
  for (const Fold& fold : folds)
    for (std::size_t t : fold.test)
    {
      if (samples[t].copy)
        throw std::invalid_argument("runFolds: fold '" + fold.name + "' tests a training copy of " +
                                    samples[t].person + "'s " + samples[t].action);
      for (std::size_t r : fold.train)
        if (samples[t].person == samples[r].person)
          throw std::invalid_argument("runFolds: fold '" + fold.name + "' trains on person " + samples[r].person +
                                      " whom it tests");
    }
  // Folds are independent: up to `jobs` of them train at once; their answers are merged in fold order.
  std::vector<std::vector<Classification>> predicted(folds.size());
  std::vector<PyramidParams> chosen(folds.size());
  forEachParallel(jobs, folds.size(), [&](std::size_t f) {
    const Fold& fold = folds[f];
    if (fold.test.empty())
      return;
    try
    {
      const ActionModel model = trainModel(samples, fold.train, params, reuse ? &(*fold_pcas)[f] : nullptr, memo);
      chosen[f] = model.params.pyramid;
      const SequenceClassifier classifier = model.classifier();
      for (std::size_t t : fold.test)
        predicted[f].push_back(classifier.classify(sequenceOf(samples[t], model)));
    }
    catch (const std::exception& e)
    {
      throw std::runtime_error("fold '" + fold.name + "': " + e.what());
    }
  });
  for (std::size_t f = 0; f < folds.size(); ++f)
  {
    if (folds[f].test.empty())
      continue;
    Confusion mine(all.labels);
    for (std::size_t i = 0; i < folds[f].test.size(); ++i)
    {
      const Classification& answer = predicted[f][i];
      all.add(samples[folds[f].test[i]].action, answer.label, answer.confidence);
      mine.add(samples[folds[f].test[i]].action, answer.label);
    }
    if (fold_accuracy)
      fold_accuracy->push_back(mine.accuracy());
    if (fold_choices)
      fold_choices->push_back(chosen[f]);
  }
  return all;
}

}  // namespace action_flow
