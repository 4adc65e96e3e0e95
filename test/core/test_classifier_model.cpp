// Nearest-neighbour classification and the model file.
#include <action_flow/action_model.h>
#include <action_flow/posture_flow.h>

#include <gtest/gtest.h>
#include <boost/crc.hpp>
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>

using namespace action_flow;

namespace
{
struct TrainingSet
{
  Eigen::MatrixXf descriptors;
  std::vector<std::string> labels, persons;
};

TrainingSet randomSet(int rows, int dims, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.0f, 1.0f);
  TrainingSet t;
  t.descriptors.resize(rows, dims);
  for (int i = 0; i < t.descriptors.size(); ++i)
    t.descriptors(i) = n(rng);
  const char* actions[] = { "wave", "kick", "punch", "sit_down", "walk" };
  for (int r = 0; r < rows; ++r)
  {
    t.labels.push_back(actions[r % 5]);
    t.persons.push_back("person" + std::to_string(r / 5));
  }
  return t;
}

std::string tempPath(const std::string& name)
{
  return ::testing::TempDir() + "action_flow_" + name;
}

std::string readAll(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void writeAll(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), bytes.size());
}

ActionModel smallModel()
{
  const TrainingSet t = randomSet(20, 192 * 3, 5);
  ActionModel m;
  m.params.frames = 3;
  m.params.flow.k = 40;
  m.params.use_pca = true;
  m.pca = Pca::fit(t.descriptors.leftCols(192), 0.9);
  m.descriptors = Eigen::MatrixXf::Random(20, m.pca.outputSize() * 3);
  m.labels = t.labels;
  m.persons = t.persons;
  return m;
}

// Expects loading @p path to fail with a message naming the file and containing @p what.
void expectRejected(const std::string& path, const std::string& what)
{
  try
  {
    ActionModel::load(path);
    ADD_FAILURE() << "loaded a bad model file: " << what;
  }
  catch (const ModelError& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}
}  // namespace

TEST(ActionClassifier, ReturnsPlantedNearestNeighbour)
{
  const TrainingSet t = randomSet(100, 50, 1);
  const ActionClassifier nn(t.descriptors, t.labels);
  Eigen::VectorXf query = t.descriptors.row(37).transpose();
  query[3] += 0.05f;
  const Classification c = nn.classify(query);
  EXPECT_EQ(c.label, t.labels[37]);
  EXPECT_EQ(c.neighbour, 37u);
  EXPECT_NEAR(c.distance, 0.05f, 1e-3f);
  EXPECT_GT(c.margin, 1.0f) << "random 50-d points are ~10 apart; the planted one is 0.05 away";
  EXPECT_EQ(nn.classes().size(), 5u);
}

TEST(ActionClassifier, MajorityVoteWithK3)
{
  Eigen::MatrixXf d(4, 1);
  d << 0.0f, 0.2f, 0.25f, 0.3f;
  const std::vector<std::string> labels = { "a", "b", "b", "b" };
  Eigen::VectorXf q(1);
  q << 0.05f;
  EXPECT_EQ(ActionClassifier(d, labels, 1).classify(q).label, "a");
  const Classification three = ActionClassifier(d, labels, 3).classify(q);
  EXPECT_EQ(three.label, "b");
  EXPECT_NEAR(three.distance, 0.15f, 1e-6f);
  EXPECT_NEAR(three.margin, -0.1f, 1e-6f);
}

// The pruned search must give exactly what a scan of every row gives, whether the bound prunes
// well (variance concentrated in few columns, as after PCA) or hardly (equal variances).
TEST(ActionClassifier, PrunedSearchAnswersAsTheFullScan)
{
  for (const bool decaying : { true, false })
    for (const int k : { 1, 3 })
    {
      TrainingSet t = randomSet(300, 400, 7);
      std::mt19937 rng(8);
      std::normal_distribution<float> n(0.0f, 1.0f);
      // Columns in a shuffled order of decreasing spread: the classifier must find the order itself.
      std::vector<int> spread_rank(400);
      std::iota(spread_rank.begin(), spread_rank.end(), 0);
      std::shuffle(spread_rank.begin(), spread_rank.end(), rng);
      for (int j = 0; j < 400; ++j)
        if (decaying)
          t.descriptors.col(j) *= 10.0f / (1.0f + spread_rank[j]);
      const ActionClassifier nn(t.descriptors, t.labels, k);
      std::size_t completed = 0;
      for (int q = 0; q < 100; ++q)
      {
        // Near a training row (a clear winner) or between two (close calls).
        Eigen::VectorXf query = q % 2 ? Eigen::VectorXf(t.descriptors.row(q).transpose())
                                      : Eigen::VectorXf(0.5f * (t.descriptors.row(q) + t.descriptors.row(q + 1)).transpose());
        for (int j = 0; j < 400; ++j)
          query[j] += 0.3f * n(rng) * (decaying ? 10.0f / (1.0f + spread_rank[j]) : 1.0f);
        const Classification fast = nn.classify(query);
        completed += ActionClassifier::lastCompletedRows();
        const Classification full = nn.classifyBruteForce(query);
        ASSERT_EQ(fast.label, full.label) << "query " << q << ", k " << k;
        EXPECT_EQ(fast.neighbour, full.neighbour);
        EXPECT_EQ(fast.distance, full.distance);
        EXPECT_EQ(fast.margin, full.margin);
      }
      if (decaying && k == 1)
        EXPECT_LT(completed, 100u * 300u / 4) << "the bound should spare most rows when the variance is concentrated";
    }
}

TEST(ActionClassifier, RejectsBadInput)
{
  const TrainingSet t = randomSet(10, 4, 2);
  EXPECT_THROW(ActionClassifier(Eigen::MatrixXf(0, 4), {}), std::invalid_argument);
  EXPECT_THROW(ActionClassifier(t.descriptors, { "a" }), std::invalid_argument);
  const ActionClassifier nn(t.descriptors, t.labels);
  EXPECT_THROW(nn.classify(Eigen::VectorXf::Zero(5)), std::invalid_argument);
  EXPECT_THROW(nn.classify(Eigen::VectorXf::Constant(4, NAN)), std::invalid_argument);
}

TEST(ActionModel, RoundTripsExactly)
{
  const ActionModel m = smallModel();
  const std::string path = tempPath("roundtrip.model");
  m.save(path);
  const ActionModel l = ActionModel::load(path);
  EXPECT_EQ(describeDifferences(l.params, m.params), "");
  EXPECT_EQ(l.params.use_pca, true);
  EXPECT_EQ(l.params.pca_variance, m.params.pca_variance);
  EXPECT_EQ(l.params.neighbours, m.params.neighbours);
  EXPECT_EQ(l.descriptors, m.descriptors);
  EXPECT_EQ(l.pca.basis(), m.pca.basis());
  EXPECT_EQ(l.pca.mean(), m.pca.mean());
  EXPECT_EQ(l.pca.variances(), m.pca.variances());
  EXPECT_EQ(l.labels, m.labels);
  EXPECT_EQ(l.persons, m.persons);
  EXPECT_EQ(readAll(path + ".tmp"), "") << "no temporary file left behind";
  std::remove(path.c_str());
}

TEST(ActionModel, RejectsEachKindOfBadFile)
{
  const std::string path = tempPath("bad.model");
  smallModel().save(path);
  const std::string good = readAll(path);

  expectRejected(tempPath("does_not_exist.model"), "does not exist");

  writeAll(path, good.substr(0, good.size() / 2));
  expectRejected(path, "truncated");

  std::string corrupt = good;
  corrupt[good.size() - 100] ^= 0x5a;
  writeAll(path, corrupt);
  expectRejected(path, "checksum");

  std::string old = good;
  old[8] = 0;  // version field follows the 8-byte magic
  old[9] = 0;
  writeAll(path, old);
  expectRejected(path, "format version 0");

  writeAll(path, "wave,kick\n1,2,3\n");
  expectRejected(path, "not an action_flow model");

  writeAll(path, "");
  expectRejected(path, "truncated");
  std::remove(path.c_str());
}

TEST(ActionModel, RejectsParametersThatDifferFromTheRuntime)
{
  const ActionModel m = smallModel();
  RecognitionParams runtime = m.params;
  EXPECT_NO_THROW(m.checkCompatible(runtime, "m.model"));
  runtime.neighbours = 3;  // the vote does not shape descriptors
  EXPECT_NO_THROW(m.checkCompatible(runtime, "m.model"));
  runtime.flow.k = 50;
  runtime.grid.aggregation = FlowAggregation::Mean;
  try
  {
    m.checkCompatible(runtime, "m.model");
    ADD_FAILURE() << "accepted a model made with other parameters";
  }
  catch (const ModelError& e)
  {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'m.model'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("flow/k: model 40, runtime 50"), std::string::npos) << msg;
    EXPECT_NE(msg.find("descriptor: model sumflow, runtime meanflow"), std::string::npos) << msg;
  }
}

TEST(ActionModel, RefusesToSaveInconsistentModel)
{
  ActionModel m = smallModel();
  m.labels.pop_back();
  EXPECT_THROW(m.save(tempPath("inconsistent.model")), ModelError);
}

TEST(ActionModel, OnlyARegularFileIsReadAsAModel)
{
  const std::string dir = ::testing::TempDir() + "action_flow_model_dir";
  ::mkdir(dir.c_str(), 0755);
  expectRejected(dir, "is a directory");
  const std::string fifo = ::testing::TempDir() + "action_flow_model_fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  expectRejected(fifo, "not a regular file");  // and returns at once: nothing opens the FIFO
  std::remove(fifo.c_str());
}

// Makes a file of an older format @p version from the current one at @p path: its payload with
// @p erase(payload) applied, under a header of that version with the payload's size and checksum.
template <class Erase>
void rewriteAsVersion(const std::string& path, std::uint32_t version, Erase erase)
{
  const std::string now = readAll(path);
  const std::size_t head = 8 + 4 + 8 + 4;
  std::string payload = now.substr(head);
  erase(payload);
  boost::crc_32_type crc;
  crc.process_bytes(payload.data(), payload.size());
  const std::uint32_t checksum = crc.checksum();
  const std::uint64_t size = payload.size();
  std::string old = now.substr(0, 8);
  old.append(reinterpret_cast<const char*>(&version), 4);
  old.append(reinterpret_cast<const char*>(&size), 8);
  old.append(reinterpret_cast<const char*>(&checksum), 4);
  writeAll(path, old + payload);
}

// Where parameter @p name lies in a model's payload. The parameters come first: a count, then
// (name, value) strings, each a 64-bit length and its bytes.
struct PayloadParam
{
  std::size_t entry;         // its name's length field
  std::size_t value_at;      // its value's length field
  std::uint64_t value_length;
  std::size_t size() const { return value_at - entry + 8 + value_length; }
};
PayloadParam findParam(const std::string& payload, const std::string& name)
{
  const auto at = payload.find(name);
  if (at == std::string::npos || at < 8)
    throw std::runtime_error("no parameter " + name + " in the payload");
  PayloadParam e{ at - 8, at + name.size(), 0 };
  std::memcpy(&e.value_length, payload.data() + e.value_at, 8);
  return e;
}

// Files of the formats before version 4 (parameters as fixed binary fields) are refused with a
// message that says to retrain, not misread.
TEST(ActionModel, OlderFormatVersionsAreRefusedWithRetrain)
{
  const ActionModel m = smallModel();
  const std::string path = tempPath("v3.model");
  m.save(path);
  for (std::uint32_t version : { 1u, 2u, 3u })
  {
    rewriteAsVersion(path, version, [](std::string&) {});
    try
    {
      ActionModel::load(path);
      ADD_FAILURE() << "version " << version << " loaded";
    }
    catch (const ModelError& e)
    {
      EXPECT_NE(std::string(e.what()).find("format version " + std::to_string(version)), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("retrain"), std::string::npos) << e.what();
    }
  }
  std::remove(path.c_str());
}

// A version 4 file (the release before the linear classifier's temperature) still loads, as it
// was; a version 5 file without its temperature is refused as truncated.
TEST(ActionModel, Version4FilesLoadUncalibrated)
{
  const ActionModel m = smallModel();
  const std::string path = tempPath("v4.model");
  m.save(path);
  rewriteAsVersion(path, 4, [](std::string& payload) { payload.resize(payload.size() - sizeof(double)); });
  const ActionModel back = ActionModel::load(path);
  EXPECT_EQ(back.descriptors, m.descriptors);
  EXPECT_EQ(back.labels, m.labels);
  EXPECT_EQ(back.linear.temperature(), 0.0);
  rewriteAsVersion(path, ActionModel::kFormatVersion, [](std::string&) {});
  EXPECT_THROW(ActionModel::load(path), ModelError);
  std::remove(path.c_str());
}

// Files from before a part of the pyramid do not name its parameter: they load with that part off,
// so their weights meet the sequence descriptors they were trained on. A version 5 file predates the
// maxima (pyramid/max_pooling) and the Fourier magnitudes (pyramid/fourier), a version 6 file the
// Fourier magnitudes; a current file without the names gets today's defaults.
TEST(ActionModel, OlderFilesLoadWithThePyramidTheyWereTrainedOn)
{
  ActionModel m = smallModel();
  ASSERT_TRUE(m.params.pyramid.max_pooling);
  ASSERT_GT(m.params.pyramid.fourier, 0);
  const std::string path = tempPath("older_pyramid.model");
  const auto strip = [](const std::vector<std::string>& names) {
    return [names](std::string& payload) {
      for (const std::string& name : names)
      {
        const PayloadParam p = findParam(payload, name);
        payload.erase(p.entry, p.size());
        std::uint64_t count = 0;
        std::memcpy(&count, payload.data(), 8);
        --count;
        std::memcpy(&payload[0], &count, 8);
      }
    };
  };
  m.save(path);
  rewriteAsVersion(path, 5, strip({ "pyramid/max_pooling", "pyramid/fourier" }));
  ActionModel back = ActionModel::load(path);
  EXPECT_FALSE(back.params.pyramid.max_pooling);
  EXPECT_EQ(back.params.pyramid.fourier, 0);
  m.save(path);
  rewriteAsVersion(path, 6, strip({ "pyramid/fourier" }));
  back = ActionModel::load(path);
  EXPECT_TRUE(back.params.pyramid.max_pooling);
  EXPECT_EQ(back.params.pyramid.fourier, 0);
  m.save(path);
  rewriteAsVersion(path, ActionModel::kFormatVersion, strip({ "pyramid/max_pooling", "pyramid/fourier" }));
  back = ActionModel::load(path);
  EXPECT_TRUE(back.params.pyramid.max_pooling);
  EXPECT_EQ(back.params.pyramid.fourier, PyramidParams().fourier);
  std::remove(path.c_str());
}

// A parameter the file names with a value out of range (a damaged or hand-edited file) is refused by
// name, as the tools refuse it from a --config file, before any descriptor is sized by it.
TEST(ActionModel, PyramidParameterOutOfRangeIsRefusedByName)
{
  const ActionModel m = smallModel();
  const std::string path = tempPath("fourier_range.model");
  m.save(path);
  rewriteAsVersion(path, ActionModel::kFormatVersion, [](std::string& payload) {
    const PayloadParam p = findParam(payload, "pyramid/fourier");
    const std::string value = "-3";
    const std::uint64_t new_length = value.size();
    payload.replace(p.value_at, 8 + p.value_length, std::string(reinterpret_cast<const char*>(&new_length), 8) + value);
  });
  try
  {
    ActionModel::load(path);
    ADD_FAILURE() << "a model with pyramid/fourier -3 loaded";
  }
  catch (const ModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("pyramid/fourier -3 outside 0..16"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
  PyramidParams p;
  EXPECT_EQ(p.problem(), "");
  p.fourier = kMaxFourier + 1;
  EXPECT_NE(p.problem().find("pyramid/fourier"), std::string::npos);
  p = PyramidParams();
  p.temporal_levels = 0;
  EXPECT_NE(p.problem().find("pyramid/temporal_levels"), std::string::npos);
  p = PyramidParams();
  p.geometry_weight = -1.0f;
  EXPECT_NE(p.problem().find("pyramid/geometry_weight"), std::string::npos);
}

// A parameter the build does not know (a file from a newer build) is refused, naming it.
TEST(ActionModel, UnknownParameterInTheFileIsRefusedByName)
{
  const ActionModel m = smallModel();
  const std::string path = tempPath("unknown_param.model");
  m.save(path);
  rewriteAsVersion(path, ActionModel::kFormatVersion, [](std::string& payload) {
    const std::string name = "flow/k";
    const auto at = payload.find(name);
    ASSERT_NE(at, std::string::npos);
    payload.replace(at, name.size(), "flow/q");
  });
  expectRejected(path, "unknown parameter 'flow/q'");
  std::remove(path.c_str());
}
