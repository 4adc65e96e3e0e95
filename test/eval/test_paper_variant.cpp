// The paper's recognizer (variant `paper`: SUMFLOW + PCA, F = 30, 1-NN) is kept unchanged beside
// the default: on a small fixed set of hand-built moving people its frame descriptors, PCA basis and
// answers must stay those recorded when it was set aside as the reference (this file's numbers).
// A change to the flow estimation, the grid, the frame selection, the PCA or the 1-NN shows here.
#include "../../src/eval/evaluation.h"
#include <action_flow/person_pipeline.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace action_flow;

namespace
{
const char* const kActions[] = { "wave", "kick", "clap" };
constexpr int kPeople = 4, kFrames = 45;

/** Uniform in [0, 1) from the standard's fixed mt19937 sequence (the same on every platform). */
float uniform(std::mt19937& rng)
{
  return float(rng() >> 8) * (1.0f / 16777216.0f);
}

/**
 * A box-built person (legs, torso, head, arms; one colour per part, so the flow's colour match
 * means something) doing @p action at frame @p k: the right arm waves, the right leg kicks, or both
 * arms swing in and out; @p person sets the amplitude, speed, phase and size.
 */
Cloud personAt(int action, int person, int k)
{
  std::mt19937 rng(1000u * unsigned(person) + 7u * unsigned(k) + unsigned(action));
  const float scale = 0.9f + 0.05f * float(person);
  const float amplitude = 0.7f + 0.15f * float(person), speed = 1.0f + 0.1f * float(person % 3);
  const float phase = 0.4f * float(person);
  const float a = amplitude * std::sin(2.0f * float(M_PI) * 0.9f * speed * float(k) / 30.0f + phase);
  Cloud cloud;
  const auto box = [&](Eigen::Vector3f lo, Eigen::Vector3f hi, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                       const Eigen::Vector3f& pivot, int axis, float angle) {
    const Eigen::Matrix3f rot = Eigen::AngleAxisf(angle, Eigen::Vector3f::Unit(axis)).toRotationMatrix();
    for (float x = lo.x(); x <= hi.x(); x += 0.03f)
      for (float y = lo.y(); y <= hi.y(); y += 0.03f)
        for (float z = lo.z(); z <= hi.z(); z += 0.06f)
        {
          const Eigen::Vector3f p = scale * (pivot + rot * (Eigen::Vector3f(x, y, z) - pivot));
          PointT q;
          q.x = p.x() + 0.004f * (uniform(rng) - 0.5f);
          q.y = p.y() + 0.004f * (uniform(rng) - 0.5f);
          q.z = p.z() + 0.004f * (uniform(rng) - 0.5f);
          // A colour pattern along each part (stripes 6 cm apart), so that the colour match finds the
          // same place again, as on clothes.
          const std::uint8_t stripe = static_cast<std::uint8_t>(60.0f * (0.5f + 0.5f * std::sin(100.0f * (x + y + z))));
          q.r = std::uint8_t(r / 2 + stripe), q.g = std::uint8_t(g / 2 + stripe / 2), q.b = std::uint8_t(b / 2);
          cloud.push_back(q);
        }
  };
  const Eigen::Vector3f zero = Eigen::Vector3f::Zero();
  const Eigen::Vector3f right_hip(0.1f, 0.85f, 0.0f), right_shoulder(0.22f, 1.4f, 0.0f), left_shoulder(-0.22f, 1.4f, 0.0f);
  box({ -0.18f, 0.0f, -0.06f }, { -0.04f, 0.85f, 0.06f }, 40, 40, 160, zero, 0, 0.0f);  // left leg
  box({ 0.04f, 0.0f, -0.06f }, { 0.18f, 0.85f, 0.06f }, 40, 160, 40, right_hip, 0, action == 1 ? -0.8f * a : 0.0f);
  box({ -0.2f, 0.85f, -0.1f }, { 0.2f, 1.45f, 0.1f }, 160, 40, 40, zero, 0, 0.0f);     // torso
  box({ -0.09f, 1.5f, -0.09f }, { 0.09f, 1.75f, 0.09f }, 200, 160, 120, zero, 0, 0.0f); // head
  const float right = action == 0 ? 1.2f + 0.9f * a : action == 2 ? 0.9f + 0.6f * a : 0.1f;
  const float left = action == 2 ? -(0.9f + 0.6f * a) : -0.1f;
  box({ 0.22f, 0.85f, -0.05f }, { 0.3f, 1.42f, 0.05f }, 200, 200, 40, right_shoulder, 2, right);  // right arm
  box({ -0.3f, 0.85f, -0.05f }, { -0.22f, 1.42f, 0.05f }, 40, 200, 200, left_shoulder, 2, left); // left arm
  // Seen from 2.5 m: the camera's optical frame (y down, z ahead).
  for (PointT& q : cloud.points)
    q.y = 1.0f - q.y, q.z += 2.5f;
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  return cloud;
}

RecognitionParams paperParams()
{
  RecognitionParams p;  // Recognizer::Paper, SUMFLOW, F = 30
  p.use_pca = true;
  return p;
}
}  // namespace

TEST(PaperVariant, GivesTheRecordedDescriptorsAndAnswersOnAFixedSet)
{
  const RecognitionParams params = paperParams();
  ASSERT_EQ(params.recognizer, Recognizer::Paper);
  ASSERT_EQ(params.grid.aggregation, FlowAggregation::Sum);
  ASSERT_EQ(params.frames, 30);

  std::vector<SampleFrames> frames;
  for (int person = 0; person < kPeople; ++person)
    for (int action = 0; action < 3; ++action)
    {
      PersonPipeline pipeline(params);
      PersonFrame where;
      where.origin = Eigen::Vector3f(0.0f, 1.0f, 2.5f);
      where.axes.col(1) = Eigen::Vector3f(0.0f, -1.0f, 0.0f);  // up is the optical frame's -y
      where.axes.col(2) = Eigen::Vector3f(0.0f, 0.0f, -1.0f);  // depth toward the camera
      where.height = 1.75f;
      for (int k = 0; k < kFrames; ++k)
        pipeline.add(personAt(action, person, k), k / 30.0, where);
      SampleFrames f;
      f.descriptors.resize(Eigen::Index(pipeline.descriptors().size()), Eigen::Index(frameDescriptorLength(params)));
      for (std::size_t r = 0; r < pipeline.descriptors().size(); ++r)
        f.descriptors.row(Eigen::Index(r)) = pipeline.descriptors()[r].transpose();
      f.stamps = pipeline.stamps();
      frames.push_back(f);
    }
  std::vector<LabelledSample> samples;
  std::vector<std::string> persons;
  for (int person = 0; person < kPeople; ++person)
    for (int action = 0; action < 3; ++action)
    {
      samples.push_back({ "p" + std::to_string(person), kActions[action], &frames[std::size_t(3 * person + action)] });
      persons.push_back(samples.back().person);
    }

  // The frame descriptors (flow, then the 4x4x4 SUMFLOW grid), by a checksum of two samples.
  const auto checksum = [](const SampleFrames& f) { return double(f.descriptors.cwiseAbs().sum()); };
  EXPECT_EQ(frames[0].descriptors.rows(), kFrames - 1);
  EXPECT_EQ(frames[0].descriptors.cols(), 192);
  EXPECT_NEAR(checksum(frames[0]), 75.4668, 1e-3) << "wave of p0";
  EXPECT_NEAR(checksum(frames[4]), 71.5929, 1e-3) << "kick of p1";

  // PCA on the first fold's training people, then leave-one-person-out with 1-NN.
  const std::vector<Fold> folds = leaveOnePersonOut(persons);
  const Pca pca = fitPca(samples, folds[0].train, params.pca_variance);
  EXPECT_EQ(pca.outputSize(), 25);
  const ActionModel model = trainModel(samples, folds[0].train, params);
  EXPECT_NEAR(double(sequenceOf(samples[0], model).cwiseAbs().sum()), 53.7059, 1e-3);

  std::vector<double> per_fold;
  const Confusion c = runFolds(samples, folds, params, &per_fold);
    // Rows and columns: clap, kick, wave; one wave (p0's) is taken for a clap.
  ASSERT_EQ(c.labels, (std::vector<std::string>{ "clap", "kick", "wave" }));
  EXPECT_EQ(c.counts, (std::vector<std::vector<int>>{ { 4, 0, 0 }, { 0, 4, 0 }, { 1, 0, 3 } }));
  EXPECT_EQ(per_fold, (std::vector<double>{ 2.0 / 3.0, 1, 1, 1 }));
}
