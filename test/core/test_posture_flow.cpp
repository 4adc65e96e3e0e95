// Known-answer tests of the default recognizer: the posture-and-flow frame descriptor, the part
// selection for ablations, the temporal pyramid, the linear classifier and its model file.
#include <action_flow/action_model.h>
#include <action_flow/posture_flow.h>
#include <action_flow/temporal_pyramid.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace action_flow;

namespace
{
// Centre of cell (ix, iy, iz) of a level with n parts per axis, for a 1.75 m person at the origin
// with identity axes: the grid is 2.0 x 2.3 x 1.8 m, x and z centred, y from the ground up.
Eigen::Vector3f centreOf(int ix, int iy, int iz, int n)
{
  return Eigen::Vector3f(-1.0f + 2.0f / n * (ix + 0.5f), 2.3f / n * (iy + 0.5f), -0.9f + 1.8f / n * (iz + 0.5f));
}

Cloud pointsAt(const std::vector<Eigen::Vector3f>& where)
{
  Cloud c;
  for (const auto& w : where)
  {
    PointT p;
    p.x = w.x();
    p.y = w.y();
    p.z = w.z();
    c.push_back(p);
  }
  return c;
}

// Index of the first value of cell (ix, iy, iz) at level l of the default layout.
int at(const PostureFlowDescriptor& d, int level, int ix, int iy, int iz)
{
  const int n = d.parts(level)[0];
  return d.offset(level) + kPostureFlowValuesPerCell * (ix + n * (iy + n * iz));
}
}  // namespace

TEST(PostureFlowDescriptor, LayoutIsOneTwoFourPartsPerAxis)
{
  const PostureFlowDescriptor d;
  EXPECT_EQ(d.parts(0)[0], 1);
  EXPECT_EQ(d.parts(1)[1], 2);
  EXPECT_EQ(d.parts(2)[2], 4);
  EXPECT_EQ(d.offset(1), 7);
  EXPECT_EQ(d.offset(2), 7 + 56);
  EXPECT_EQ(d.geometryOffset(), 7 * (1 + 8 + 64));
  EXPECT_EQ(d.size(), 7 * (1 + 8 + 64) + kGeometryValues);
}

TEST(PostureFlowDescriptor, GeometryBlockHasKnownCentroidExtremesAndMomentum)
{
  const PostureFlowDescriptor d;
  const PersonFrame person;  // 1.75 m: the grid is 2.0 x 2.3 x 1.8 m, so x/2, y/2.3, z/1.8
  // kExtremePoints points at each of five places: the right hand, the left hand, the head, in front
  // of the chest (+z, toward the camera) and behind it.
  const std::vector<Eigen::Vector3f> places = { { 0.8f, 1.0f, 0.0f }, { -0.8f, 1.0f, 0.0f }, { 0.0f, 2.0f, 0.0f },
                                                { 0.0f, 1.0f, 0.6f }, { 0.0f, 1.0f, -0.6f } };
  std::vector<Eigen::Vector3f> points;
  for (const auto& p : places)
    for (int i = 0; i < kExtremePoints; ++i)
      points.push_back(p);
  // The right hand rises at 1 m/s.
  const FlowVectors flow = { { places[0], { 0.0f, 1.0f, 0.0f } } };
  const Eigen::VectorXf v = d.compute(pointsAt(points), flow, person);
  const auto g = [&](int i) { return Eigen::Vector3f(v.segment<3>(d.geometryOffset() + 3 * i)); };
  const Eigen::Vector3f scale(2.0f, 2.3f, 1.8f);
  const Eigen::Vector3f centroid = Eigen::Vector3f(0.0f, 1.2f, 0.0f).cwiseQuotient(scale);
  EXPECT_LT((g(0) - centroid).norm(), 1e-6f);
  for (int e = 0; e < 5; ++e)  // +x, -x, +y, +z, -z
    EXPECT_LT((g(1 + e) - places[e].cwiseQuotient(scale)).norm(), 1e-6f) << "extreme " << e;
  const float n = static_cast<float>(points.size());
  const Eigen::Vector3f r = places[0].cwiseQuotient(scale) - centroid;  // (0.4, -0.2/2.3, 0)
  EXPECT_LT((g(6) - r / n).norm(), 1e-6f) << "speed-weighted offset of the motion";
  EXPECT_LT((g(7) - Eigen::Vector3f(0.0f, 0.0f, 0.4f / n)).norm(), 1e-6f) << "r x v: turning about +z";
  // No flow: no motion values, the rest unchanged.
  const Eigen::VectorXf still = d.compute(pointsAt(points), {}, person);
  EXPECT_EQ(still.tail<6>(), Eigen::VectorXf::Zero(6));
  EXPECT_EQ(still.segment<18>(d.geometryOffset()), v.segment<18>(d.geometryOffset()));
}

TEST(PostureFlowDescriptor, HandBuiltPersonGivesKnownPostureAndFlow)
{
  const PostureFlowDescriptor d;
  const PersonFrame person;  // origin 0, identity axes, 1.75 m
  // Three points in finest cell (0,0,0), one in (3,3,3); one outside and one NaN are ignored.
  const Cloud cloud = pointsAt({ centreOf(0, 0, 0, 4), centreOf(0, 0, 0, 4) + Eigen::Vector3f(0.01f, 0, 0),
                                 centreOf(0, 0, 0, 4) - Eigen::Vector3f(0, 0.01f, 0), centreOf(3, 3, 3, 4),
                                 Eigen::Vector3f(5, 0, 0), Eigen::Vector3f(NAN, 0, 0) });
  const FlowVectors flow = { { centreOf(0, 0, 0, 4), { 1.0f, -2.0f, 0.0f } },
                             { centreOf(3, 3, 3, 4), { 0.0f, 0.0f, 0.5f } },
                             { Eigen::Vector3f(5, 0, 0), { 9, 9, 9 } } };
  const Eigen::VectorXf v = d.compute(cloud, flow, person);
  ASSERT_EQ(v.size(), d.size());
  // Posture: shares of the 4 points inside; flow: per-direction sums divided by 4.
  Eigen::VectorXf expected = Eigen::VectorXf::Zero(d.size());
  const auto cell = [&](int index, float share, std::array<float, 6> bins) {
    expected[index] += share;
    for (int b = 0; b < 6; ++b)
      expected[index + 1 + b] += bins[b];
  };
  cell(at(d, 0, 0, 0, 0), 1.0f, { 0.25f, 0, 0, 0.5f, 0.125f, 0 });  // whole body
  cell(at(d, 1, 0, 0, 0), 0.75f, { 0.25f, 0, 0, 0.5f, 0, 0 });
  cell(at(d, 1, 1, 1, 1), 0.25f, { 0, 0, 0, 0, 0.125f, 0 });
  cell(at(d, 2, 0, 0, 0), 0.75f, { 0.25f, 0, 0, 0.5f, 0, 0 });
  cell(at(d, 2, 3, 3, 3), 0.25f, { 0, 0, 0, 0, 0.125f, 0 });
  for (int i = 0; i < d.geometryOffset(); ++i)  // the geometry block has a test of its own
    EXPECT_NEAR(v[i], expected[i], 1e-6f) << "value " << i;

  // The person's point count does not matter, only shares: doubling every point gives the same.
  Cloud twice = cloud;
  twice += cloud;
  FlowVectors flow_twice = flow;
  flow_twice.insert(flow_twice.end(), flow.begin(), flow.end());
  EXPECT_LT((d.compute(twice, flow_twice, person) - v).norm(), 1e-6f);

  // A cloud with nothing inside the grid gives all zeros; so does a frame without height.
  EXPECT_EQ(d.compute(pointsAt({ Eigen::Vector3f(5, 0, 0) }), flow, person).norm(), 0.0f);
  PersonFrame flat;
  flat.height = 0.0f;
  EXPECT_EQ(d.compute(cloud, flow, flat).norm(), 0.0f);
}

TEST(PostureFlowDescriptor, MirroredEqualsTheMirroredPerson)
{
  const PostureFlowDescriptor d;
  const PersonFrame person;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> x(-0.95f, 0.95f), y(0.05f, 2.2f), z(-0.85f, 0.85f), v(-2.0f, 2.0f);
  std::vector<Eigen::Vector3f> points, mirrored_points;
  FlowVectors flow, mirrored_flow;
  for (int i = 0; i < 200; ++i)
  {
    const Eigen::Vector3f p(x(rng), y(rng), z(rng)), vel(v(rng), v(rng), v(rng));
    points.push_back(p);
    mirrored_points.push_back(Eigen::Vector3f(-p.x(), p.y(), p.z()));
    flow.push_back({ p, vel });
    mirrored_flow.push_back({ mirrored_points.back(), Eigen::Vector3f(-vel.x(), vel.y(), vel.z()) });
  }
  const Eigen::VectorXf a = d.compute(pointsAt(points), flow, person);
  const Eigen::VectorXf b = d.compute(pointsAt(mirrored_points), mirrored_flow, person);
  EXPECT_GT(a.norm(), 0.1f);
  EXPECT_GT((a - b).norm(), 0.01f) << "the test person must not be symmetric already";
  EXPECT_LT((d.mirrored(a) - b).norm(), 1e-5f);
  EXPECT_LT((d.mirrored(d.mirrored(a)) - a).norm(), 1e-7f);
  EXPECT_THROW(d.mirrored(Eigen::VectorXf::Zero(3)), std::invalid_argument);
}

TEST(TemporalPyramid, SelectsTheParts)
{
  const PostureFlowDescriptor layout;
  Eigen::VectorXf full = Eigen::VectorXf::Zero(layout.size());
  full.segment<7>(at(layout, 0, 0, 0, 0)) << 1, 2, 3, 4, 5, 6, 7;
  full.segment<7>(at(layout, 2, 1, 0, 0)) << 0.5f, 1, 0, 0, 3, 0, 0;
  PyramidParams all;
  EXPECT_THROW(selectFrameFeatures(full, layout, all), std::invalid_argument) << "the encoding is not chosen yet";
  all.flow = FlowEncoding::Bins;
  all.posture = PostureMode::Choose;
  EXPECT_THROW(selectFrameFeatures(full, layout, all), std::invalid_argument) << "posture is not chosen yet";
  all.posture = PostureMode::On;
  EXPECT_EQ(selectFrameFeatures(full, layout, all).size(), 511 + kGeometryValues);
  full.tail<kGeometryValues>().setConstant(0.25f);
  EXPECT_EQ(selectFrameFeatures(full, layout, all).tail<kGeometryValues>(),
            all.geometry_weight * full.tail<kGeometryValues>());
  all.geometry = false;
  EXPECT_EQ(selectFrameFeatures(full, layout, all).size(), 511);
  EXPECT_EQ(selectFrameFeatures(full, layout, all).head<7>(), full.head<7>());
  PyramidParams no_posture = all;
  no_posture.posture = PostureMode::Off;
  EXPECT_EQ(selectFrameFeatures(full, layout, no_posture).size(), 6 * 73);
  no_posture.geometry = true;
  EXPECT_EQ(selectFrameFeatures(full, layout, no_posture).size(), 6 * 73 + kGeometryValues);
  no_posture.geometry = false;
  EXPECT_EQ(selectFrameFeatures(full, layout, no_posture)[0], 2.0f);
  PyramidParams sums;
  sums.flow = FlowEncoding::Sums;
  sums.geometry = false;
  const Eigen::VectorXf s = selectFrameFeatures(full, layout, sums);
  ASSERT_EQ(s.size(), 4 * 73);
  EXPECT_EQ(s.head<4>(), Eigen::Vector4f(1, -1, -1, -1));  // +x - -x, +y - -y, +z - -z
  PyramidParams fine = all;  // geometry off
  fine.coarse_to_fine = false;
  const Eigen::VectorXf f = selectFrameFeatures(full, layout, fine);
  ASSERT_EQ(f.size(), 7 * 64);
  EXPECT_EQ(f.segment<7>(7), full.segment<7>(at(layout, 2, 1, 0, 0)));
  EXPECT_THROW(selectFrameFeatures(Eigen::VectorXf::Zero(10), layout, all), std::invalid_argument);
}

TEST(TemporalPyramid, MeansOfWholeHalvesAndQuarters)
{
  std::vector<Eigen::VectorXf> frames;
  for (float v : { 1.0f, 2.0f, 3.0f, 4.0f })
    frames.push_back(Eigen::VectorXf::Constant(1, v));
  const std::vector<double> stamps = { 10.0, 11.0, 12.0, 13.0 };
  const Eigen::VectorXf p = temporalPyramid(frames, stamps, 3);
  ASSERT_EQ(p.size(), 7);
  const float expected[] = { 2.5f, 1.5f, 3.5f, 1, 2, 3, 4 };  // then sign(v) sqrt(|v|)
  for (int i = 0; i < 7; ++i)
    EXPECT_NEAR(p[i], std::sqrt(expected[i]), 1e-6f) << "part " << i;
  const Eigen::VectorXf plain = temporalPyramid(frames, stamps, 3, false);  // means only (coordinates)
  for (int i = 0; i < 7; ++i)
    EXPECT_NEAR(plain[i], expected[i], 1e-6f) << "part " << i;

  // Performed twice as fast (half the time span, same poses): the same descriptor.
  const std::vector<double> fast = { 10.0, 10.5, 11.0, 11.5 };
  EXPECT_LT((temporalPyramid(frames, fast, 3) - p).norm(), 1e-6f);
  // A single frame fills every part; negative values keep their sign.
  const Eigen::VectorXf one = temporalPyramid({ Eigen::VectorXf::Constant(1, -4.0f) }, { 0.0 }, 2);
  EXPECT_EQ(one, Eigen::Vector3f(-2, -2, -2));
  EXPECT_THROW(temporalPyramid({}, {}, 3), std::invalid_argument);
  EXPECT_THROW(temporalPyramid(frames, { 3, 2, 1, 0 }, 3), std::invalid_argument);
  EXPECT_THROW(temporalPyramid(frames, stamps, 0), std::invalid_argument);
}

TEST(TemporalPyramid, MaximaBesideTheMeans)
{
  // Two values a frame: a rise 1, 4, 9, 16 and a dip 0, -1, -9, 0.
  std::vector<Eigen::VectorXf> frames;
  const float rise[] = { 1, 4, 9, 16 }, dip[] = { 0, -1, -9, 0 };
  for (int i = 0; i < 4; ++i)
    frames.push_back(Eigen::Vector2f(rise[i], dip[i]));
  const std::vector<double> stamps = { 0.0, 0.1, 0.2, 0.3 };
  const Eigen::VectorXf p = temporalPyramid(frames, stamps, 2, false, Pooling{ true, 0 });
  // Per part (whole, first half, second half): the two means, then the two maxima.
  const float expected[] = { 7.5f, -2.5f, 16, 0,  2.5f, -0.5f, 4, 0,  12.5f, -4.5f, 16, 0 };
  ASSERT_EQ(p.size(), 12);
  for (int i = 0; i < 12; ++i)
    EXPECT_NEAR(p[i], expected[i], 1e-6f) << "value " << i;
  // Power-normalised as the means are; the means are those of the default Pooling, means only.
  const Eigen::VectorXf root = temporalPyramid(frames, stamps, 2, true, Pooling{ true, 0 });
  for (int i = 0; i < 12; ++i)
    EXPECT_NEAR(root[i], std::copysign(std::sqrt(std::abs(expected[i])), expected[i]), 1e-6f) << "value " << i;
  const Eigen::VectorXf means = temporalPyramid(frames, stamps, 2, false);
  ASSERT_EQ(means.size(), 6);
  EXPECT_EQ(means.segment<2>(0), p.segment<2>(0));
  EXPECT_EQ(means.segment<2>(4), p.segment<2>(8));
  // A part no frame falls in takes the frame nearest its middle, for its maximum too.
  const Eigen::VectorXf sparse = temporalPyramid({ frames[0], frames[3] }, { 0.0, 1.0 }, 3, false, Pooling{ true, 0 });
  ASSERT_EQ(sparse.size(), 28);
  EXPECT_EQ(sparse.segment<4>(12), Eigen::Vector4f(1, 0, 1, 0));  // the first quarter: frame 0 only
  EXPECT_EQ(sparse.segment<4>(20), Eigen::Vector4f(16, 0, 16, 0));  // the third: empty, frame 3 is nearest
}

TEST(TemporalPyramid, FourierMagnitudesOfKnownWaves)
{
  // Eight frames of two values: cos(2 pi 2 j / 8) + 1, two cycles of amplitude 1 around 1, and
  // 3 sin(2 pi j / 8), one cycle of amplitude 3.
  std::vector<Eigen::VectorXf> frames;
  std::vector<double> stamps;
  for (int j = 0; j < 8; ++j)
  {
    frames.push_back(Eigen::Vector2f(std::cos(2 * M_PI * 2 * j / 8) + 1, 3 * std::sin(2 * M_PI * j / 8)));
    stamps.push_back(0.1 * j);
  }
  const Eigen::VectorXf p = temporalPyramid(frames, stamps, 1, false, Pooling{ false, 3 });
  // The mean, then |X_k| / n for k = 1, 2, 3: a real wave of amplitude a gives a / 2 at its k.
  const float expected[] = { 1, 0, 0, 1.5f, 0.5f, 0, 0, 0 };
  ASSERT_EQ(p.size(), 8);
  for (int i = 0; i < 8; ++i)
    EXPECT_NEAR(p[i], expected[i], 1e-5f) << "value " << i;
  // The magnitudes do not change when the motion shifts in time (here by three frames, cyclically).
  std::vector<Eigen::VectorXf> shifted(8);
  for (int j = 0; j < 8; ++j)
    shifted[j] = frames[(j + 3) % 8];
  EXPECT_TRUE(temporalPyramid(shifted, stamps, 1, false, Pooling{ false, 3 }).isApprox(p, 1e-5f));
  // With the maxima: mean, maximum, then the magnitudes; and per part of a two-level pyramid.
  const Eigen::VectorXf both = temporalPyramid(frames, stamps, 2, false, Pooling{ true, 1 });
  ASSERT_EQ(both.size(), 3 * 3 * 2);
  EXPECT_NEAR(both[2], 2.0f, 1e-5f);  // the first value's maximum over the whole
  EXPECT_NEAR(both[5], 1.5f, 1e-5f);  // the second value's k = 1 magnitude over the whole
  // A part of one frame does not swing: its magnitudes are 0, for every k.
  const Eigen::VectorXf single = temporalPyramid({ frames[1] }, { 0.0 }, 1, false, Pooling{ false, 4 });
  EXPECT_EQ(single.tail(8), Eigen::VectorXf::Zero(8));
  EXPECT_THROW(temporalPyramid(frames, stamps, 1, false, Pooling{ false, -1 }), std::invalid_argument);
  EXPECT_THROW(temporalPyramid(frames, stamps, 1, false, Pooling{ false, kMaxFourier + 1 }), std::invalid_argument);
}

namespace
{
// Two clouds of points around (+1, 0...) and (-1, 0...) in 5 dimensions, plus a third class at the origin.
void threeClasses(Eigen::MatrixXf& x, std::vector<std::string>& labels, std::vector<std::string>& persons, int n)
{
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.2f);
  x.resize(3 * n, 5);
  for (int i = 0; i < 3 * n; ++i)
  {
    const int c = i % 3;
    for (int j = 0; j < 5; ++j)
      x(i, j) = noise(rng) + (j == 0 ? (c == 0 ? 1.0f : c == 1 ? -1.0f : 0.0f) : j == 1 ? (c == 2 ? 1.0f : 0.0f) : 0.0f);
    labels.push_back(c == 0 ? "right" : c == 1 ? "left" : "up");
    persons.push_back("p" + std::to_string(i % 4));
  }
}
}  // namespace

TEST(LinearClassifier, LearnsSeparableClassesWithProbabilities)
{
  Eigen::MatrixXf x;
  std::vector<std::string> labels, persons;
  threeClasses(x, labels, persons, 40);
  const LinearClassifier c = LinearClassifier::train(x, labels, 1.0);
  EXPECT_EQ(c.classes(), (std::vector<std::string>{ "left", "right", "up" }));
  int right = 0;
  for (int i = 0; i < x.rows(); ++i)
    right += c.classify(x.row(i).transpose()).label == labels[i];
  EXPECT_GE(right, x.rows() - 2);
  Eigen::VectorXf q(5);
  q << 1.5f, 0, 0, 0, 0;
  const Classification r = c.classify(q);
  EXPECT_EQ(r.label, "right");
  EXPECT_GT(r.confidence, 0.8f);
  EXPECT_NEAR(c.probabilities(q).sum(), 1.0f, 1e-5f);
  Eigen::VectorXf p = c.probabilities(q);
  std::sort(p.data(), p.data() + p.size());
  EXPECT_NEAR(r.margin, p[2] - p[1], 1e-6f);
  // Halfway between two classes the classifier is unsure.
  q << 0.5f, 0.5f, 0, 0, 0;
  EXPECT_LT(c.classify(q).confidence, r.confidence);

  // Two labels (liblinear stores one weight vector then) work the same way.
  const LinearClassifier two = LinearClassifier::train(x.topRows(2), { "right", "left" }, 1.0);
  EXPECT_EQ(two.classify(x.row(0).transpose()).label, "right");
  EXPECT_EQ(two.classify(x.row(1).transpose()).label, "left");

  EXPECT_THROW(LinearClassifier::train(x, labels, 0.0), std::invalid_argument);
  EXPECT_THROW(LinearClassifier::train(x.topRows(3), { "a", "a", "a" }, 1.0), std::invalid_argument);
  EXPECT_THROW(c.classify(Eigen::VectorXf::Zero(4)), std::invalid_argument);
}

namespace
{
// @p rows random rows of @p cols values, row i of class i % @p classes with its class's column
// raised by 2.5; rows from @p wide_from on spread 3 times wider and shifted by 5.
void classRows(int rows, int cols, int classes, int wide_from, unsigned seed, Eigen::MatrixXf& x,
               std::vector<std::string>& labels)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  x.resize(rows, cols);
  labels.clear();
  for (int i = 0; i < rows; ++i)
  {
    const bool wide = i >= wide_from;
    for (int j = 0; j < cols; ++j)
      x(i, j) = (wide ? 3.0f : 1.0f) * noise(rng) + (j == i % classes ? 2.5f : 0.0f) + (wide ? 5.0f : 0.0f);
    labels.push_back("class" + std::to_string(i % classes));
  }
}
}  // namespace

TEST(LinearClassifier, SolvingInTheRowsSpanGivesTheFullSolution)
{
  // 30 rows of 200 columns: the span has 30 dimensions.
  Eigen::MatrixXf x;
  std::vector<std::string> labels;
  classRows(30, 200, 3, 30, 5, x, labels);
  const LinearClassifier span = LinearClassifier::train(x, labels, 0.1, true);
  const LinearClassifier full = LinearClassifier::train(x, labels, 0.1, false);
  EXPECT_LT((span.weights() - full.weights()).norm(), 0.02f * full.weights().norm());
  EXPECT_LT((span.bias() - full.bias()).norm(), 0.02f * (1.0f + full.bias().norm()));
  for (int i = 0; i < 30; ++i)
    EXPECT_LT((span.probabilities(x.row(i).transpose()) - full.probabilities(x.row(i).transpose())).norm(), 0.01f);
}

// Model selection trains on many subsets of one set of rows through their Gram matrix: a subset
// must give the classifier its rows alone give (its own mean and spread, not the whole set's), and
// the held-out scores must be that classifier's scores.
TEST(LinearClassifier, ASubsetOfGramRowsTrainsAsItsRowsAlone)
{
  // The later rows shifted and spread wider: a subset has another mean and spread than the whole.
  Eigen::MatrixXf x;
  std::vector<std::string> labels;
  classRows(40, 150, 4, 20, 7, x, labels);
  const GramRows g(x);
  std::vector<Eigen::Index> rows, queries;
  std::vector<std::string> row_labels;
  for (Eigen::Index i = 0; i < 40; ++i)
    if (i % 5 == 0)
      queries.push_back(i);
    else
    {
      rows.push_back(i);
      row_labels.push_back(labels[static_cast<std::size_t>(i)]);
    }
  const std::vector<double> cs = { 0.01, 1.0 };
  const std::vector<LinearClassifier> alone = LinearClassifier::train(x(rows, Eigen::all), row_labels, cs, false);
  const std::vector<LinearClassifier> shared = LinearClassifier::train(g, rows, row_labels, cs);
  std::vector<std::string> classes;
  const std::vector<Eigen::MatrixXf> held_out = LinearClassifier::heldOutScores(g, rows, row_labels, queries, cs, classes);
  ASSERT_EQ(shared.size(), 2u);
  ASSERT_EQ(held_out.size(), 2u);
  EXPECT_EQ(classes, alone[0].classes());
  for (std::size_t c = 0; c < cs.size(); ++c)
  {
    EXPECT_LT((shared[c].mean() - alone[c].mean()).norm(), 1e-4f * alone[c].mean().norm());
    EXPECT_NEAR(shared[c].scale()[0], alone[c].scale()[0], 1e-4f * alone[c].scale()[0]);
    EXPECT_LT((shared[c].weights() - alone[c].weights()).norm(), 0.02f * alone[c].weights().norm());
    ASSERT_EQ(held_out[c].rows(), static_cast<Eigen::Index>(queries.size()));
    for (std::size_t q = 0; q < queries.size(); ++q)
    {
      const Eigen::VectorXf query = x.row(queries[q]).transpose();
      EXPECT_LT((held_out[c].row(static_cast<Eigen::Index>(q)).transpose() - shared[c].scores(query)).norm(),
                1e-3f * (1.0f + shared[c].scores(query).norm()));
      EXPECT_LT((shared[c].scores(query) - alone[c].scores(query)).norm(), 0.05f * (1.0f + alone[c].scores(query).norm()));
    }
  }
  EXPECT_THROW(LinearClassifier::train(g, { 0, 40 }, { "a", "b" }, cs), std::invalid_argument);
  EXPECT_THROW(LinearClassifier::heldOutScores(g, rows, row_labels, { -1 }, cs, classes), std::invalid_argument);
}

// A hand-made classifier whose scores are the query itself: known probabilities.
TEST(LinearClassifier, CalibratedProbabilitiesAreTheSoftmaxOfScoresOverTheTemperature)
{
  const LinearClassifier raw({ "a", "b", "c" }, Eigen::MatrixXf::Identity(3, 3), Eigen::VectorXf::Zero(3),
                             Eigen::VectorXf::Zero(3), Eigen::VectorXf::Ones(3));
  Eigen::VectorXf q(3);
  q << 2.0f, 0.0f, 0.0f;
  EXPECT_LT((raw.scores(q) - q).norm(), 1e-6f);
  // Uncalibrated: the logistic probabilities divided by their sum.
  const double s2 = 1.0 / (1.0 + std::exp(-2.0));
  EXPECT_NEAR(raw.probabilities(q)[0], s2 / (s2 + 1.0), 1e-6);
  EXPECT_EQ(raw.temperature(), 0.0);
  // T = 2: softmax(1, 0, 0).
  const LinearClassifier hot = raw.calibrated(2.0);
  EXPECT_EQ(hot.temperature(), 2.0);
  EXPECT_NEAR(hot.probabilities(q)[0], std::exp(1.0) / (std::exp(1.0) + 2.0), 1e-6);
  EXPECT_NEAR(hot.probabilities(q)[1], 1.0 / (std::exp(1.0) + 2.0), 1e-6);
  EXPECT_NEAR(hot.classify(q).confidence, std::exp(1.0) / (std::exp(1.0) + 2.0), 1e-6);
  // A lower temperature is surer, never of another label; huge scores do not overflow.
  EXPECT_GT(raw.calibrated(0.5).classify(q).confidence, hot.classify(q).confidence);
  EXPECT_EQ(raw.calibrated(0.5).classify(q).label, "a");
  q << 0.0f, 5000.0f, 4990.0f;
  EXPECT_NEAR(raw.calibrated(0.05).probabilities(q)[1], 1.0f, 1e-6f);
  EXPECT_TRUE(raw.calibrated(0.05).probabilities(q).allFinite());
  EXPECT_THROW(raw.calibrated(-1.0), std::invalid_argument);
  EXPECT_THROW(raw.calibrated(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

// Labels drawn from softmax(scores / 2.5) give back a temperature of 2.5; labels that always go to
// the top score give the surest temperature, labels unrelated to the scores the flattest.
TEST(LinearClassifier, FitTemperatureRecoversTheTemperatureThatDrewTheLabels)
{
  std::mt19937 rng(11);
  std::normal_distribution<float> score(0.0f, 3.0f);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int n = 20000, k = 4;
  Eigen::MatrixXf s(n, k);
  std::vector<int> drawn, top, unrelated;
  for (int i = 0; i < n; ++i)
  {
    for (int j = 0; j < k; ++j)
      s(i, j) = score(rng);
    const Eigen::ArrayXd p = (s.row(i).cast<double>().array() / 2.5).exp();
    double r = u(rng) * p.sum();
    int pick = 0;
    while (pick < k - 1 && (r -= p[pick]) > 0.0)
      ++pick;
    drawn.push_back(pick);
    Eigen::Index best = 0;
    s.row(i).maxCoeff(&best);
    top.push_back(static_cast<int>(best));
    unrelated.push_back(i % k);
  }
  EXPECT_NEAR(fitTemperature(s, drawn), 2.5, 0.1);
  EXPECT_NEAR(fitTemperature(s, top), kMinTemperature, 1e-3);
  EXPECT_GT(fitTemperature(s, unrelated), 0.9 * kMaxTemperature);
  EXPECT_THROW(fitTemperature(s, { 0, 1 }), std::invalid_argument);
  EXPECT_THROW(fitTemperature(s.topRows(1), { 4 }), std::invalid_argument);
  EXPECT_THROW(fitTemperature(Eigen::MatrixXf(0, 4), {}), std::invalid_argument);
}

TEST(PostureFlowModel, RoundTripsWithTheLinearClassifier)
{
  Eigen::MatrixXf x;
  std::vector<std::string> labels, persons;
  threeClasses(x, labels, persons, 10);
  ActionModel m;
  m.params = defaultRecognitionParams();
  m.params.pyramid.c = 0.5;
  m.params.pyramid.flow = FlowEncoding::Bins;
  m.params.pyramid.mirror = MirrorMode::Off;
  const Eigen::Index length = m.sequenceLength();
  // 7 parts, each its means, maxima and 6 Fourier magnitudes
  EXPECT_EQ(length, (511 + kGeometryValues) * 7 * (2 + 6));
  m.descriptors = Eigen::MatrixXf::Zero(x.rows(), length);
  m.descriptors.leftCols(5) = x;
  m.labels = labels;
  m.persons = persons;
  m.linear = LinearClassifier::train(m.descriptors, labels, 0.5).calibrated(1.7);
  const std::string path = ::testing::TempDir() + "posture_flow.model";
  m.save(path);
  const ActionModel back = ActionModel::load(path);
  EXPECT_EQ(back.params.recognizer, Recognizer::PostureFlow);
  EXPECT_EQ(back.params.pyramid.c, 0.5);
  EXPECT_EQ(back.params.pyramid.geometry, m.params.pyramid.geometry);
  EXPECT_EQ(back.params.pyramid.geometry_weight, m.params.pyramid.geometry_weight);
  EXPECT_EQ(back.linear.weights(), m.linear.weights());
  EXPECT_EQ(back.linear.classes(), m.linear.classes());
  EXPECT_EQ(back.linear.temperature(), 1.7);
  for (int i = 0; i < x.rows(); ++i)
  {
    const Classification a = m.classifier().classify(m.descriptors.row(i).transpose());
    const Classification b = back.classifier().classify(back.descriptors.row(i).transpose());
    EXPECT_EQ(a.label, b.label);
    EXPECT_EQ(a.confidence, b.confidence);
  }
  // The runtime must compute the same frame descriptors: a paper runtime is refused.
  EXPECT_THROW(back.checkCompatible(RecognitionParams(), path), ModelError);
  EXPECT_NO_THROW(back.checkCompatible(defaultRecognitionParams(), path));

  // A model whose classifier does not fit its sequences is refused at load, naming the fault.
  ActionModel bad = m;
  bad.params.pyramid.temporal_levels = 2;  // sequences would be 535 x 3 long
  bad.descriptors = Eigen::MatrixXf::Zero(x.rows(), bad.sequenceLength());
  bad.save(path);
  try
  {
    ActionModel::load(path);
    ADD_FAILURE() << "a linear classifier of the wrong length was accepted";
  }
  catch (const ModelError& e)
  {
    EXPECT_NE(std::string(e.what()).find("linear classifier of input length"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}
