// Frame selection, sequence descriptors and PCA.
#include <action_flow/pca.h>
#include <action_flow/sequence_descriptor.h>

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <random>

using namespace action_flow;
using Indices = std::vector<std::size_t>;

namespace
{
std::vector<double> uniform(std::size_t n, double dt = 1.0 / 30)
{
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i)
    t[i] = 100.0 + i * dt;
  return t;
}
}  // namespace

TEST(SelectFrames, EqualToF)
{
  Indices expected(30);
  for (std::size_t i = 0; i < 30; ++i)
    expected[i] = i;
  EXPECT_EQ(selectFrames(uniform(30), 30), expected);
}

TEST(SelectFrames, LongerThanF)
{
  EXPECT_EQ(selectFrames(uniform(10), 4), (Indices{ 0, 3, 6, 9 }));
  EXPECT_EQ(selectFrames(uniform(100), 1), (Indices{ 49 }));
}

TEST(SelectFrames, ShorterThanFRepeatsNearestFrames)
{
  EXPECT_EQ(selectFrames(uniform(3), 5), (Indices{ 0, 0, 1, 1, 2 }));
  EXPECT_EQ(selectFrames(uniform(1), 3), (Indices{ 0, 0, 0 }));
}

TEST(SelectFrames, EvenInTimeNotInIndex)
{
  // A stall in the middle: evenly spaced in time picks 0, 3, 4 where even indices would be 0, 2, 4.
  EXPECT_EQ(selectFrames({ 0.0, 0.1, 0.2, 5.0, 10.0 }, 3), (Indices{ 0, 3, 4 }));
}

TEST(SelectFrames, RejectsBadSequences)
{
  EXPECT_THROW(selectFrames({}, 3), std::invalid_argument);
  EXPECT_THROW(selectFrames({ 1.0, 0.5 }, 3), std::invalid_argument);
  EXPECT_THROW(selectFrames(uniform(5), 0), std::invalid_argument);
}

TEST(SequenceDescriptor, ConcatenatesSelectedFrames)
{
  std::vector<Eigen::VectorXf> frames;
  for (int i = 0; i < 10; ++i)
    frames.push_back(Eigen::VectorXf::Constant(2, static_cast<float>(i)));
  const Eigen::VectorXf s = SequenceDescriptor(4).compute(frames, uniform(10));
  Eigen::VectorXf expected(8);
  expected << 0, 0, 3, 3, 6, 6, 9, 9;
  EXPECT_EQ(s, expected);
  EXPECT_THROW(SequenceDescriptor(4).compute(frames, uniform(9)), std::invalid_argument);
}

// Samples on a known 2-D subspace of R^12 plus tiny noise: PCA keeps 2 components spanning it.
TEST(Pca, RecoversKnownLowRankBasis)
{
  std::mt19937 rng(7);
  std::normal_distribution<float> n(0.0f, 1.0f);
  Eigen::MatrixXf random(12, 2);
  for (int i = 0; i < random.size(); ++i)
    random(i) = n(rng);
  const Eigen::MatrixXf basis = Eigen::HouseholderQR<Eigen::MatrixXf>(random).householderQ() *
                                Eigen::MatrixXf::Identity(12, 2);
  Eigen::VectorXf mean = Eigen::VectorXf::LinSpaced(12, -1, 1);
  Eigen::MatrixXf samples(200, 12);
  for (int r = 0; r < 200; ++r)
  {
    const Eigen::Vector2f z(3.0f * n(rng), 1.0f * n(rng));
    Eigen::VectorXf noise(12);
    for (int i = 0; i < 12; ++i)
      noise[i] = 1e-3f * n(rng);
    samples.row(r) = (mean + basis * z + noise).transpose();
  }
  const Pca pca = Pca::fit(samples, 0.99);
  ASSERT_EQ(pca.outputSize(), 2);
  EXPECT_GE(pca.explained(), 0.99);
  // Each kept direction lies in the planted subspace.
  for (int c = 0; c < 2; ++c)
    EXPECT_NEAR((basis.transpose() * pca.basis().col(c)).norm(), 1.0f, 1e-3f);
  EXPECT_GT(pca.variances()[0], pca.variances()[1]);
  // Projection keeps the distances within the subspace.
  const Eigen::VectorXf a = samples.row(0).transpose(), b = samples.row(1).transpose();
  EXPECT_NEAR((pca.project(a) - pca.project(b)).norm(), (a - b).norm(), 1e-2f);
}

TEST(Pca, KeepsAtLeastTheAskedVariance)
{
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 1.0f);
  Eigen::MatrixXf samples(300, 20);
  for (int r = 0; r < 300; ++r)
    for (int c = 0; c < 20; ++c)
      samples(r, c) = n(rng) / (1.0f + c);  // decaying spectrum
  for (double keep : { 0.5, 0.9, 0.99 })
  {
    const Pca pca = Pca::fit(samples, keep);
    EXPECT_GE(pca.explained(), keep);
    // One component fewer would not have been enough.
    const double total = (samples.rowwise() - samples.colwise().mean()).squaredNorm() / 299.0;
    const double fewer = pca.variances().head(pca.outputSize() - 1).cast<double>().sum();
    EXPECT_LT(fewer / total, keep + 1e-6);
  }
  EXPECT_THROW(Pca::fit(samples.topRows(1), 0.99), std::invalid_argument);
  EXPECT_THROW(Pca::fit(samples, 0.0), std::invalid_argument);
  const Eigen::VectorXf v = Eigen::VectorXf::LinSpaced(3, 1, 3);
  EXPECT_EQ(Pca().project(v), v) << "an empty basis leaves descriptors unchanged";
  EXPECT_THROW(Pca::fit(samples, 0.9).project(v), std::invalid_argument);
}
