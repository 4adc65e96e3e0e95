// Dataset index, protocols, experiments and the descriptor cache.
#include "../../src/eval/evaluation.h"
#include <action_flow/posture_flow.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

using namespace action_flow;

namespace
{
std::string dir()
{
  return ::testing::TempDir();
}

std::string writeIndex(const std::string& name, const std::string& text)
{
  const std::string path = dir() + name;
  std::ofstream(path) << text;
  return path;
}

// Expects readIndex to fail with a message holding "<file>:<line>" and @p what.
void expectIndexError(const std::string& text, int line, const std::string& what)
{
  const std::string path = writeIndex("bad_index.csv", text);
  try
  {
    readIndex(path, { "wave", "kick" });
    ADD_FAILURE() << "accepted a malformed index: " << what;
  }
  catch (const DatasetError& e)
  {
    const std::string msg = e.what();
    const std::string where = line > 0 ? path + ":" + std::to_string(line) : path;
    EXPECT_NE(msg.find(where), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

// Sample frames whose descriptors are the action's direction plus noise: separable by action.
SampleFrames framesFor(int action, unsigned seed, int n = 12)
{
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  SampleFrames f;
  f.descriptors.resize(n, 192);
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < 192; ++c)
      f.descriptors(r, c) = noise(rng);
    f.descriptors(r, 7 * action + r % 3) += 1.0f;
    f.stamps.push_back(r / 30.0);
  }
  return f;
}
}  // namespace

TEST(DatasetIndex, ReadsAValidIndexRelativeToItsFolder)
{
  std::ofstream(dir() + "a.bag") << "x";
  std::ofstream(dir() + "b.bag") << "x";
  // Columns found by name; one the reader does not use ("note") is ignored, "frames" is not needed.
  const auto e = readIndex(writeIndex("good.csv", "note,path,person,action,repetition\n"
                                                  "x,a.bag,p01,wave,1\n"
                                                  "\n"
                                                  "y,b.bag, p02 ,kick,2\n"),
                           { "wave", "kick" });
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[1].path, dir() + "b.bag");
  EXPECT_EQ(e[1].person, "p02");
  EXPECT_EQ(e[1].repetition, 2);
  EXPECT_EQ(e[1].line, 4);
}

TEST(DatasetIndex, MalformedIndexNamesTheLine)
{
  std::ofstream(dir() + "a.bag") << "x";
  const std::string head = "path,person,action,repetition,frames\n";
  expectIndexError(head + "a.bag,p01,wave,1,90\nmissing.bag,p01,kick,1,90\n", 3, "does not exist");
  expectIndexError(head + "a.bag,p01,dance,1,90\n", 2, "unknown action 'dance'");
  expectIndexError(head + "a.bag,p01,wave,1\n", 2, "expected 5 fields");
  expectIndexError(head + "a.bag,p01,wave,one,90\n", 2, "'repetition' must be a non-negative integer");
  expectIndexError(head + "a.bag,,wave,1,90\n", 2, "'person' is empty");
  expectIndexError(head + "a.bag,p01,wave,1,90\na.bag,p01,wave,1,90\n", 3, "duplicate sample");
  expectIndexError("path,person,action,frames\n", 1, "lacks column 'repetition'");
  expectIndexError("path,action,repetition\n", 1, "lacks column 'person'");
  expectIndexError(head, 0, "lists no samples");
  expectIndexError("", 0, "empty dataset index");
  EXPECT_THROW(readIndex(dir() + "no_such_index.csv"), DatasetError);
}

TEST(Protocols, LeaveOnePersonOutNeverTrainsOnTheTestPerson)
{
  const std::vector<std::string> persons = { "p1", "p2", "p3", "p1", "p2", "p3", "p1" };
  const auto folds = leaveOnePersonOut(persons);
  ASSERT_EQ(folds.size(), 3u);
  for (const auto& f : folds)
  {
    EXPECT_EQ(f.train.size() + f.test.size(), persons.size());
    ASSERT_FALSE(f.test.empty());
    const std::string tested = persons[f.test[0]];
    for (std::size_t t : f.test)
      EXPECT_EQ(persons[t], tested);
    for (std::size_t r : f.train)
      EXPECT_NE(persons[r], tested) << f.name;
  }
  EXPECT_EQ(folds[0].test, (std::vector<std::size_t>{ 0, 3, 6 }));
}

TEST(Protocols, CrossSubjectSplitsByPerson)
{
  const std::vector<std::string> persons = { "s01", "s02", "s03", "s10", "s01" };
  const Fold f = crossSubject(persons, { "s01", "s03" });
  EXPECT_EQ(f.train, (std::vector<std::size_t>{ 0, 2, 4 }));
  EXPECT_EQ(f.test, (std::vector<std::size_t>{ 1, 3 }));
}

TEST(Confusion, AccuracyPrecisionRecall)
{
  Confusion c({ "a", "b" });
  c.add("a", "a");
  c.add("a", "a");
  c.add("a", "b");
  c.add("b", "b");
  EXPECT_DOUBLE_EQ(c.accuracy(), 0.75);
  EXPECT_DOUBLE_EQ(c.recall()[0], 2.0 / 3);
  EXPECT_DOUBLE_EQ(c.precision()[1], 0.5);
  EXPECT_EQ(c.support(), (std::vector<int>{ 3, 1 }));
  EXPECT_THROW(c.add("a", "zzz"), std::invalid_argument);
}

TEST(Reliability, KnownAnswers)
{
  Reliability r;
  EXPECT_EQ(r.total(), 0);
  EXPECT_DOUBLE_EQ(r.expectedCalibrationError(), 0.0);
  EXPECT_DOUBLE_EQ(r.meanConfidence(), 0.0);
  // Three answers at 0.95 of which two right, one at 0.15 that was wrong: bins 9 and 1.
  r.add(0.95f, true);
  r.add(0.95f, true);
  r.add(0.95f, false);
  r.add(0.15f, false);
  EXPECT_EQ(r.total(), 4);
  EXPECT_EQ(r.count[9], 3);
  EXPECT_EQ(r.correct[9], 2);
  EXPECT_EQ(r.count[1], 1);
  EXPECT_NEAR(r.meanConfidence(), (3 * 0.95 + 0.15) / 4, 1e-6);
  // (|2 - 2.85| + |0 - 0.15|) / 4
  EXPECT_NEAR(r.expectedCalibrationError(), 0.25, 1e-6);
  // Confidence 1 falls in the last bin; outside [0, 1] (or NaN) is clamped.
  r.add(1.0f, true);
  r.add(-0.5f, false);
  r.add(std::numeric_limits<float>::quiet_NaN(), false);
  EXPECT_EQ(r.count[9], 4);
  EXPECT_EQ(r.count[0], 2);
  EXPECT_NEAR(r.confidence_sum[0], 0.0, 1e-12);
}

TEST(Reliability, ConfusionRecordsConfidenceOnlyWhenGiven)
{
  Confusion c({ "a", "b" });
  c.add("a", "a");
  c.add("a", "b", 0.8f);
  EXPECT_EQ(c.total(), 2);
  EXPECT_EQ(c.reliability.total(), 1);
  EXPECT_EQ(c.reliability.correct[8], 0);
  EXPECT_NEAR(c.reliability.expectedCalibrationError(), 0.8, 1e-6);
}

TEST(Experiments, SeparableActionsAreAllRecognised)
{
  std::vector<SampleFrames> frames;
  std::vector<LabelledSample> samples;
  const char* actions[] = { "wave", "kick", "punch" };
  for (int p = 0; p < 4; ++p)
    for (int a = 0; a < 3; ++a)
      frames.push_back(framesFor(a, 100 * p + a));
  for (int p = 0; p < 4; ++p)
    for (int a = 0; a < 3; ++a)
      samples.push_back({ "p" + std::to_string(p), actions[a], &frames[3 * p + a] });
  std::vector<std::string> persons;
  for (const auto& s : samples)
    persons.push_back(s.person);
  RecognitionParams params;
  params.frames = 5;
  std::vector<double> per_fold;
  const Confusion c = runFolds(samples, leaveOnePersonOut(persons), params, &per_fold);
  EXPECT_EQ(c.total(), 12);
  EXPECT_DOUBLE_EQ(c.accuracy(), 1.0);
  EXPECT_EQ(per_fold.size(), 4u);
  // Every test answer came with its confidence, in [0, 1].
  EXPECT_EQ(c.reliability.total(), 12);
  EXPECT_GT(c.reliability.meanConfidence(), 0.0);
  EXPECT_LE(c.reliability.meanConfidence(), 1.0);

  params.use_pca = true;
  params.pca_variance = 0.9;
  std::vector<Pca> pcas;
  EXPECT_DOUBLE_EQ(runFolds(samples, leaveOnePersonOut(persons), params, nullptr, &pcas).accuracy(), 1.0);
  EXPECT_EQ(pcas.size(), 4u);
  const ActionModel m = trainModel(samples, { 0, 1, 2, 3 }, params);
  EXPECT_LT(m.pca.outputSize(), 192);
  EXPECT_EQ(m.descriptors.cols(), 5 * m.pca.outputSize());

  // A fold that trains on the person it tests is refused.
  Fold leaky = leaveOnePersonOut(persons)[0];
  leaky.train.push_back(leaky.test[0]);
  EXPECT_THROW(runFolds(samples, { leaky }, params), std::invalid_argument);

  // A fold that tests a training copy (it trains, it is never tested) is refused.
  std::vector<LabelledSample> with_copy = samples;
  with_copy.push_back({ "p0", "wave", &frames[0], true });
  Fold tests_copy = leaveOnePersonOut(persons)[0];
  tests_copy.test.push_back(with_copy.size() - 1);
  EXPECT_THROW(runFolds(with_copy, { tests_copy }, params), std::invalid_argument);
}

// Training copies train but are never the inner cross-validation's queries: here every person's
// copy lies apart from the actions and bears a label that no other person's copy predicts, so
// asked, it would be answered wrong; not asked, the held-out originals are all right.
TEST(Experiments, TrainingCopiesAreNeverHeldOutQueries)
{
  Eigen::MatrixXf x(18, 3);
  std::vector<std::string> labels, persons;
  std::vector<bool> queries;
  for (int p = 0; p < 6; ++p)
  {
    for (int a = 0; a < 2; ++a)
    {
      x.row(labels.size()) << (a == 0 ? 3.0f : -3.0f), 0.1f * p, 0.0f;
      labels.push_back(a == 0 ? "a" : "b");
      persons.push_back("p" + std::to_string(p));
      queries.push_back(true);
    }
    x.row(labels.size()) << 0.0f, 0.0f, 5.0f;  // the copy: the same place for everyone, labels alternating
    labels.push_back(p % 2 ? "a" : "b");
    persons.push_back("p" + std::to_string(p));
    queries.push_back(false);
  }
  const LinearChoice honest = chooseLinear(x, nullptr, labels, persons, { false }, { 1.0 }, 3, &queries);
  EXPECT_DOUBLE_EQ(honest.score, 1.0);
  const LinearChoice asked = chooseLinear(x, nullptr, labels, persons, { false }, { 1.0 }, 3);
  EXPECT_LT(asked.score, 1.0) << "asked, the copies would be answered wrong";
  const std::vector<bool> short_flags(3, true);
  EXPECT_THROW(chooseLinear(x, nullptr, labels, persons, { false }, { 1.0 }, 3, &short_flags), std::invalid_argument);
}

TEST(Experiments, SampleWithoutFlowIsAStillFrame)
{
  SampleFrames moving = framesFor(0, 1), still;
  const std::vector<LabelledSample> samples = { { "p1", "wave", &moving }, { "p2", "standing", &still } };
  RecognitionParams params;
  params.frames = 4;
  const ActionModel m = trainModel(samples, { 0, 1 }, params);
  EXPECT_EQ(m.descriptors.row(1).norm(), 0.0f);
  EXPECT_EQ(m.classifier().classify(sequenceOf({ "p3", "?", &still }, m)).label, "standing");
}

TEST(SampleCache, RoundTripsAndRejectsDamage)
{
  const std::string path = dir() + "sample.frames";
  const SampleFrames f = framesFor(2, 9, 7);
  saveSampleFrames(path, f);
  SampleFrames g;
  ASSERT_TRUE(loadSampleFrames(path, g));
  EXPECT_EQ(g.descriptors, f.descriptors);
  EXPECT_EQ(g.stamps, f.stamps);
  EXPECT_FALSE(loadSampleFrames(dir() + "absent.frames", g));
  std::ofstream(path, std::ios::app) << "junk";
  EXPECT_THROW(loadSampleFrames(path, g), DatasetError);
  std::remove(path.c_str());
}

TEST(SampleCache, KeepsAStreamsTracks)
{
  const std::string path = dir() + "stream.frames";
  SampleFrames f = framesFor(2, 9, 7);
  f.tracks.assign(f.stamps.size(), 3u);
  f.tracks.back() = 8u;
  saveSampleFrames(path, f);
  SampleFrames g;
  g.tracks = { 1u };
  ASSERT_TRUE(loadSampleFrames(path, g));
  EXPECT_EQ(g.tracks, f.tracks);
  EXPECT_EQ(g.descriptors, f.descriptors);
  f.tracks.pop_back();  // one id per row, or none
  EXPECT_THROW(saveSampleFrames(path, f), DatasetError);
  // A file of one performer has no tracks.
  saveSampleFrames(path, framesFor(2, 9, 7));
  ASSERT_TRUE(loadSampleFrames(path, g));
  EXPECT_TRUE(g.tracks.empty());
  // A truncated track section is damage.
  f.tracks.push_back(8u);
  saveSampleFrames(path, f);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 2);
  EXPECT_THROW(loadSampleFrames(path, g), DatasetError);
  std::remove(path.c_str());
}

namespace
{
// Posture-and-flow frames of one sample: action a puts the body's points and an upward motion in
// its own finest cell (x = 1, y = a: distinct from the others also when mirrored), plus noise.
SampleFrames postureFramesFor(int action, unsigned seed, int n = 12)
{
  const PostureFlowDescriptor layout;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(0.0f, 0.01f);
  SampleFrames f;
  f.descriptors.resize(n, layout.size());
  for (int r = 0; r < n; ++r)
  {
    for (int c = 0; c < layout.size(); ++c)
      f.descriptors(r, c) = noise(rng);
    const int cell = layout.offset(2) + kPostureFlowValuesPerCell * (1 + 4 * action);
    f.descriptors(r, cell) += 0.5f;
    f.descriptors(r, cell + 3) += r % 2 ? 1.0f : 0.2f;
    f.stamps.push_back(r / 30.0);
  }
  return f;
}

struct PostureSet
{
  std::vector<SampleFrames> frames;
  std::vector<LabelledSample> samples;
  std::vector<std::string> persons;
};

PostureSet postureSet(int people)
{
  PostureSet s;
  const char* actions[] = { "wave", "kick", "punch" };
  for (int p = 0; p < people; ++p)
    for (int a = 0; a < 3; ++a)
      s.frames.push_back(postureFramesFor(a, 100 * p + a));
  for (int p = 0; p < people; ++p)
    for (int a = 0; a < 3; ++a)
    {
      s.samples.push_back({ "p" + std::to_string(p), actions[a], &s.frames[3 * p + a] });
      s.persons.push_back(s.samples.back().person);
    }
  return s;
}
}  // namespace

TEST(Experiments, DefaultRecognizerRecognisesSeparableActions)
{
  const PostureSet s = postureSet(4);
  const RecognitionParams params = defaultRecognitionParams();
  std::vector<double> per_fold;
  const Confusion c = runFolds(s.samples, leaveOnePersonOut(s.persons), params, &per_fold, nullptr, 2);
  EXPECT_EQ(c.total(), 12);
  EXPECT_DOUBLE_EQ(c.accuracy(), 1.0);
  EXPECT_EQ(per_fold.size(), 4u);
  // Every test answer came with its confidence, in [0, 1].
  EXPECT_EQ(c.reliability.total(), 12);
  EXPECT_GT(c.reliability.meanConfidence(), 0.0);
  EXPECT_LE(c.reliability.meanConfidence(), 1.0);

  const ActionModel m = trainModel(s.samples, { 0, 1, 2, 3, 4, 5 }, params);
  EXPECT_NE(m.params.pyramid.mirror, MirrorMode::Choose) << "the choice is recorded in the model";
  EXPECT_EQ(m.descriptors.rows(), m.params.pyramid.mirror == MirrorMode::On ? 12 : 6);
  EXPECT_FALSE(m.linear.empty());
  EXPECT_GT(m.params.pyramid.c, 0.0) << "the chosen C is recorded in the model";
  RecognitionParams mirrored = params;
  mirrored.pyramid.mirror = MirrorMode::On;
  EXPECT_EQ(trainModel(s.samples, { 0, 1, 2, 3, 4, 5 }, mirrored).descriptors.rows(), 12) << "6 samples, each mirrored too";
  RecognitionParams nn = params;
  nn.pyramid.classifier = PyramidClassifier::Nearest;
  nn.pyramid.mirror = MirrorMode::Off;
  EXPECT_DOUBLE_EQ(runFolds(s.samples, leaveOnePersonOut(s.persons), nn).accuracy(), 1.0);
  EXPECT_TRUE(trainModel(s.samples, { 0, 1, 2 }, nn).linear.empty());
}

TEST(Experiments, ModelSelectionNeverSeesATestPerson)
{
  PostureSet s = postureSet(5);
  const Fold fold = leaveOnePersonOut(s.persons)[0];  // tests p0
  RecognitionParams params = defaultRecognitionParams();
  params.pyramid.posture = PostureMode::Choose;  // every setting that can be chosen is
  const ActionModel before = trainModel(s.samples, fold.train, params);
  // Whatever the test person did, the chosen C and the weights stay the same.
  for (std::size_t t : fold.test)
    s.frames[t].descriptors = s.frames[t].descriptors.reverse() * 7.0f;
  const ActionModel after = trainModel(s.samples, fold.train, params);
  EXPECT_EQ(before.params.pyramid.c, after.params.pyramid.c);
  EXPECT_EQ(before.params.pyramid.mirror, after.params.pyramid.mirror);
  EXPECT_EQ(before.params.pyramid.posture, after.params.pyramid.posture);
  EXPECT_EQ(before.params.pyramid.flow, after.params.pyramid.flow);
  EXPECT_EQ(before.linear.weights(), after.linear.weights());
  EXPECT_EQ(before.linear.temperature(), after.linear.temperature());
  EXPECT_GT(before.linear.temperature(), 0.0) << "the probabilities are calibrated";
  for (const auto& p : before.persons)
    EXPECT_NE(p, "p0");
  // The candidates are tried: C is one of them.
  EXPECT_NE(std::find(linearCandidates().begin(), linearCandidates().end(), before.params.pyramid.c),
            linearCandidates().end());
}

namespace
{
// Frames of one sample whose action shows in one finest cell, either as the share of the body's
// points there (@p in_posture) or as upward flow there; with @p person_pose, every cell also holds
// a large share of its own for this person doing this action (a build or habit that tells the
// training people apart but says nothing about a new one).
SampleFrames oneCueFrames(int action, bool in_posture, bool person_pose, unsigned seed)
{
  const PostureFlowDescriptor layout;
  std::mt19937 rng(seed), pose_rng(seed / 10);  // seed / 10: one pose per person and action
  std::uniform_real_distribution<float> noise(0.0f, 0.02f), pose(0.0f, 2.0f);
  std::vector<float> shares(static_cast<std::size_t>(layout.cells(2)));
  for (float& s : shares)
    s = pose(pose_rng);
  SampleFrames f;
  f.descriptors.resize(8, layout.size());
  for (int r = 0; r < 8; ++r)
  {
    for (int c = 0; c < layout.size(); ++c)
      f.descriptors(r, c) = noise(rng);
    for (int c = 0; person_pose && c < layout.cells(2); ++c)
      f.descriptors(r, layout.offset(2) + kPostureFlowValuesPerCell * c) += shares[static_cast<std::size_t>(c)];
    const int cell = layout.offset(2) + kPostureFlowValuesPerCell * (1 + 4 * action);
    f.descriptors(r, cell + (in_posture ? 0 : 3)) += 0.3f;
    f.stamps.push_back(r / 30.0);
  }
  return f;
}
}  // namespace

// Posture is kept where it tells the actions apart and dropped where it tells only the training
// people apart: the cross-validation inside the training people decides, and the model records it.
TEST(Experiments, PostureIsChosenByCrossValidationInsideTheTrainingPeople)
{
  for (const bool posture_tells : { true, false })
  {
    std::vector<SampleFrames> frames;
    std::vector<LabelledSample> samples;
    const char* actions[] = { "wave", "kick", "punch" };
    for (int p = 0; p < 6; ++p)
      for (int a = 0; a < 3; ++a)
        for (int rep = 0; rep < 2; ++rep)
          frames.push_back(oneCueFrames(a, posture_tells, !posture_tells, 10u * (100u * p + 10u * a) + rep));
    std::vector<std::size_t> rows;
    for (int p = 0, i = 0; p < 6; ++p)
      for (int a = 0; a < 3; ++a)
        for (int rep = 0; rep < 2; ++rep, ++i)
        {
          samples.push_back({ "p" + std::to_string(p), actions[a], &frames[static_cast<std::size_t>(i)] });
          rows.push_back(static_cast<std::size_t>(i));
        }
    RecognitionParams choose = defaultRecognitionParams();
    choose.pyramid.posture = PostureMode::Choose;
    const ActionModel m = trainModel(samples, rows, choose);
    EXPECT_EQ(m.params.pyramid.posture, posture_tells ? PostureMode::On : PostureMode::Off)
        << (posture_tells ? "the actions show only in the posture" : "the posture tells only the people apart");
    EXPECT_EQ(trainModel(samples, rows, defaultRecognitionParams()).params.pyramid.posture, PostureMode::On)
        << "the default keeps posture";
  }
}

// Variants that ask the same model-selection questions on the same folds share the answers
// (SelectionMemo, as evaluate's variants do): the variant that chooses posture asks what posture on
// and posture off asked, runs no cross-validation of its own, and ends as it does without the memo.
TEST(Experiments, ChoosingPostureReusesTheAnswersOfPostureOnAndOff)
{
  std::vector<SampleFrames> frames;
  std::vector<LabelledSample> samples;
  std::vector<std::string> persons;
  const char* actions[] = { "wave", "kick", "punch" };
  for (int p = 0; p < 5; ++p)
    for (int a = 0; a < 3; ++a)
      for (int rep = 0; rep < 2; ++rep)
        frames.push_back(oneCueFrames(a, false, true, 10u * (100u * p + 10u * a) + rep));
  for (int p = 0, i = 0; p < 5; ++p)
    for (int a = 0; a < 3; ++a)
      for (int rep = 0; rep < 2; ++rep, ++i)
      {
        samples.push_back({ "p" + std::to_string(p), actions[a], &frames[static_cast<std::size_t>(i)] });
        persons.push_back(samples.back().person);
      }
  const std::vector<Fold> folds = leaveOnePersonOut(persons);
  RecognitionParams on = defaultRecognitionParams(), off = on, choose = on;
  off.pyramid.posture = PostureMode::Off;
  choose.pyramid.posture = PostureMode::Choose;
  std::vector<PyramidParams> plain_choices, memo_choices;
  const Confusion plain = runFolds(samples, folds, choose, nullptr, nullptr, 2, &plain_choices);

  SelectionMemo memo;
  runFolds(samples, folds, on, nullptr, nullptr, 2, nullptr, &memo);
  runFolds(samples, folds, off, nullptr, nullptr, 2, nullptr, &memo);
  EXPECT_EQ(memo.hits(), 0) << "posture on and off ask different questions";
  const Confusion memoised = runFolds(samples, folds, choose, nullptr, nullptr, 2, &memo_choices, &memo);
  // Per fold, posture on and off under each flow encoding the default chooses between (bins, sums).
  ASSERT_EQ(choose.pyramid.flow, FlowEncoding::Choose);
  EXPECT_EQ(memo.hits(), 4 * static_cast<int>(folds.size())) << "each fold's questions were answered before";
  EXPECT_EQ(memoised.counts, plain.counts);
  EXPECT_EQ(memoised.reliability.meanConfidence(), plain.reliability.meanConfidence());
  ASSERT_EQ(memo_choices.size(), plain_choices.size());
  int off_chosen = 0;
  for (std::size_t f = 0; f < plain_choices.size(); ++f)
  {
    EXPECT_EQ(memo_choices[f].c, plain_choices[f].c);
    EXPECT_EQ(memo_choices[f].mirror, plain_choices[f].mirror);
    EXPECT_EQ(memo_choices[f].posture, plain_choices[f].posture);
    off_chosen += plain_choices[f].posture == PostureMode::Off;
  }
  EXPECT_GT(off_chosen, 0) << "the remembered choice is not the last one asked: the final rows are described again";
  // The final classifier itself, with and without the memo.
  const ActionModel a = trainModel(samples, folds[0].train, choose), b = trainModel(samples, folds[0].train, choose, nullptr, &memo);
  EXPECT_EQ(a.linear.weights(), b.linear.weights());
  EXPECT_EQ(a.linear.temperature(), b.linear.temperature());
  EXPECT_EQ(a.params.pyramid.posture, b.params.pyramid.posture);
  // Other rows are another question.
  const int hits = memo.hits();
  std::vector<std::size_t> fewer(folds[0].train.begin() + 6, folds[0].train.end());
  trainModel(samples, fewer, choose, nullptr, &memo);
  EXPECT_EQ(memo.hits(), hits);
}

// Five overlapping classes (about 60% separable): the temperature fitted by chooseLinear on the
// training people's held-out answers makes the confidence on new people match how often it is
// right, far better than the uncalibrated probabilities do.
TEST(Experiments, CalibratedConfidenceMatchesAccuracyOnNewPeople)
{
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  const auto draw = [&](int n, const std::string& person_prefix, Eigen::MatrixXf& x, std::vector<std::string>& labels,
                        std::vector<std::string>& persons) {
    x.resize(n, 8);
    for (int i = 0; i < n; ++i)
    {
      const int c = i % 5;
      for (int j = 0; j < 8; ++j)
        x(i, j) = noise(rng) + (j == c ? 1.6f : 0.0f);
      labels.push_back("a" + std::to_string(c));
      persons.push_back(person_prefix + std::to_string(i % 6));
    }
  };
  Eigen::MatrixXf train, test;
  std::vector<std::string> train_labels, train_persons, test_labels, test_persons;
  draw(600, "p", train, train_labels, train_persons);
  draw(3000, "q", test, test_labels, test_persons);
  const LinearChoice choice = chooseLinear(train, nullptr, train_labels, train_persons, { false }, { 0.1 });
  ASSERT_GT(choice.temperature, 0.0);
  const LinearClassifier raw = LinearClassifier::train(train, train_labels, choice.c);
  const LinearClassifier calibrated = raw.calibrated(choice.temperature);
  Reliability before, after;
  for (Eigen::Index i = 0; i < test.rows(); ++i)
  {
    const Classification a = raw.classify(test.row(i).transpose()), b = calibrated.classify(test.row(i).transpose());
    EXPECT_EQ(a.label, b.label);
    before.add(a.confidence, a.label == test_labels[i]);
    after.add(b.confidence, b.label == test_labels[i]);
  }
  EXPECT_LT(after.expectedCalibrationError(), 0.05);
  EXPECT_GT(before.expectedCalibrationError(), 2.0 * after.expectedCalibrationError());
  // With mirrored copies among the options (here: the same rows), the chosen setting is calibrated too.
  const LinearChoice with_mirror = chooseLinear(train, &train, train_labels, train_persons, { true }, { 0.1 });
  EXPECT_TRUE(with_mirror.mirror);
  EXPECT_GT(with_mirror.temperature, 0.0);
  EXPECT_NEAR(with_mirror.score, choice.score, 0.05) << "copies of the same rows change little: the mirrored "
                                                         "option must be scored with the copies' true labels";
  // One person: nothing to fit on.
  EXPECT_EQ(chooseLinear(train, nullptr, train_labels, std::vector<std::string>(600, "p"), { false }, { 0.1 }).temperature, 0.0);
}
