// The classifier's policy on hand-built frame descriptor streams: known segments give known labels
// and times, stillness gives none, tracks never mix.
#include <action_flow/posture_flow.h>
#include <action_flow/recognition_policy.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace action_flow;

namespace
{
constexpr double kFps = 30.0;

// A posture_flow frame descriptor: the whole body in the coarsest cell, and for the two actions a
// body part that comes and goes in one finest cell (its share of the points swings, as an arm's
// does) with flow of `speed` there, upward and downward in turn (wave) or toward the camera (kick).
Eigen::VectorXf frame(const std::string& what, int i, std::mt19937& rng, float speed = 0.15f)
{
  const PostureFlowDescriptor layout;
  Eigen::VectorXf d = Eigen::VectorXf::Zero(layout.size());
  std::normal_distribution<float> noise(0.0f, 0.003f);
  d[0] = 1.0f;
  d[layout.offset(1)] = 1.0f;
  const int wave_cell = layout.offset(2) + kPostureFlowValuesPerCell * 60;  // high up
  const int kick_cell = layout.offset(2) + kPostureFlowValuesPerCell * 3;   // low down
  d[wave_cell] = 0.1f;
  d[kick_cell] = 0.1f;
  if (what == "wave")
  {
    const int bin = (i / 8) % 2 == 0 ? 3 : 4;  // +y, then -y
    d[bin] = speed;
    d[wave_cell + bin] = speed;
    d[wave_cell] = 0.2f + 0.15f * std::sin(2.0f * 3.14159f * i / 15.0f);
  }
  else if (what == "kick")
  {
    d[5] = speed;
    d[kick_cell + 5] = speed;
    d[kick_cell] = 0.25f + 0.15f * std::sin(2.0f * 3.14159f * i / 20.0f);
  }
  else if (what == "shift")  // a step sideways between actions: flow along x, and up at the arms
  {
    const int mid_cell = layout.offset(2) + kPostureFlowValuesPerCell * 30;
    d[1] = speed;
    d[3] = speed;
    d[mid_cell + 1] = speed;
    d[wave_cell + 3] = speed;
    d[mid_cell] = 0.25f + 0.15f * std::sin(2.0f * 3.14159f * i / 25.0f);
  }
  for (int k = 0; k < d.size(); ++k)
    d[k] = std::max(0.0f, d[k] + (k < 7 && k > 0 ? std::abs(noise(rng)) : noise(rng) * 0.1f));
  return d;
}

// Trained on standing, wave and kick; with @p no_action also on steps sideways as the class no_action.
// @p means_only: the pyramid of means only, without maxima and Fourier magnitudes (an earlier default).
std::shared_ptr<ActionModel> trainedModel(bool no_action = false, bool means_only = false)
{
  auto m = std::make_shared<ActionModel>();
  m->params = defaultRecognitionParams();
  if (means_only)
  {
    m->params.pyramid.max_pooling = false;
    m->params.pyramid.fourier = 0;
  }
  m->params.pyramid.c = 1.0;
  m->params.pyramid.flow = FlowEncoding::Bins;
  m->params.pyramid.mirror = MirrorMode::Off;
  std::mt19937 rng(7);
  std::vector<Eigen::VectorXf> rows;
  std::vector<std::string> kinds = { "standing", "wave", "kick" };
  if (no_action)
    kinds.push_back("shift");
  for (const std::string& kind : kinds)
    for (int rep = 0; rep < 8; ++rep)
    {
      // Training samples have a little stillness before and after the action, as the datasets do.
      std::vector<Eigen::VectorXf> frames;
      std::vector<double> stamps;
      const int n = 75 + 5 * rep;
      for (int i = 0; i < n; ++i)
      {
        const bool lead = i < 12 || i >= n - 12;
        frames.push_back(frame(lead ? "standing" : kind, i, rng));
        stamps.push_back(i / kFps);
      }
      rows.push_back(m->sequence(frames, stamps));
      m->labels.push_back(kind == "shift" ? kNoActionLabel : kind);
      m->persons.push_back("p" + std::to_string(rep));
    }
  m->descriptors.resize(static_cast<Eigen::Index>(rows.size()), m->sequenceLength());
  for (std::size_t r = 0; r < rows.size(); ++r)
    m->descriptors.row(static_cast<Eigen::Index>(r)) = rows[r].transpose();
  m->linear = LinearClassifier::train(m->descriptors, m->labels, m->params.pyramid.c);
  return m;
}

const std::shared_ptr<ActionModel>& model()
{
  static const std::shared_ptr<ActionModel> m = trainedModel();
  return m;
}

struct Piece
{
  std::string what;
  double seconds;
};

struct Published
{
  LabelEvent event;
  double at;  // stamp of the frame that produced it
};

// Plays the pieces through the policy as track 1; returns every event with the stamp it came at.
std::vector<Published> play(RecognitionPolicy& policy, const std::vector<Piece>& pieces, std::uint32_t id = 1)
{
  std::mt19937 rng(99);
  std::vector<Published> out;
  double t = 0.0;
  int i = 0;
  for (const Piece& p : pieces)
    for (int k = 0; k < int(p.seconds * kFps); ++k, ++i)
    {
      t = i / kFps;
      for (const LabelEvent& e : policy.add(id, frame(p.what, i, rng), t))
        out.push_back({ e, t });
    }
  for (const LabelEvent& e : policy.end(id))
    out.push_back({ e, t });
  return out;
}

PolicyParams online()
{
  PolicyParams p;
  p.mode = PolicyParams::Mode::Online;
  return p;
}

}  // namespace

TEST(RecognitionPolicy, ModelRecognisesItsOwnTrainingKinds)
{
  // The fixture itself: whole sequences of each kind classify as that kind.
  PolicyParams p;
  RecognitionPolicy policy(model(), p);
  for (const std::string what : { "wave", "kick", "standing" })
  {
    const auto events = play(policy, { { what, 3.0 } });
    ASSERT_EQ(events.size(), 1u) << what;
    EXPECT_EQ(events[0].event.result.label, what);
  }
}

TEST(RecognitionPolicy, OnlineKnownSegmentsGiveKnownLabelsAndTimes)
{
  RecognitionPolicy policy(model(), online());
  ASSERT_TRUE(policy.usesMotion());
  const auto events = play(policy, { { "standing", 2.0 }, { "wave", 2.0 }, { "standing", 2.0 }, { "kick", 2.0 },
                                     { "standing", 2.0 } });
  ASSERT_EQ(events.size(), 4u);
  const PolicyParams& p = policy.params();
  const char* labels[] = { "wave", "kick" };
  for (int a = 0; a < 2; ++a)
  {
    const double start = 2.0 + 4.0 * a, end = start + 2.0;
    const Published& started = events[2 * a];
    const Published& ended = events[2 * a + 1];
    EXPECT_EQ(started.event.kind, LabelEvent::Kind::Started);
    EXPECT_EQ(started.event.result.label, labels[a]);
    // Published while the action is under way, not before it has lasted min_segment.
    EXPECT_GE(started.at, start + p.min_segment);
    EXPECT_LT(started.at, end);
    EXPECT_NEAR(started.event.start, start - p.pre_roll, 0.2);
    EXPECT_EQ(ended.event.kind, LabelEvent::Kind::Ended);
    EXPECT_TRUE(ended.event.closes_published);
    EXPECT_EQ(ended.event.result.label, labels[a]);
    EXPECT_NEAR(ended.event.end, end + p.post_roll, 0.2);
    EXPECT_NEAR(ended.at, end + p.rest_time, 0.25);  // closed once the body rested rest_time
  }
}

TEST(RecognitionPolicy, StillnessGivesNoLabel)
{
  RecognitionPolicy policy(model(), online());
  EXPECT_TRUE(play(policy, { { "standing", 12.0 } }).empty());
}

TEST(RecognitionPolicy, IdleLabelsAreNeverPublished)
{
  // Without the motion gate, stillness reaches the classifier, which says "standing": an idle label.
  PolicyParams p = online();
  p.motion_segments = false;
  RecognitionPolicy policy(model(), p);
  EXPECT_FALSE(policy.usesMotion());
  EXPECT_TRUE(play(policy, { { "standing", 8.0 } }).empty());
  p.idle_labels.clear();
  RecognitionPolicy no_idle(model(), p);
  const auto events = play(no_idle, { { "standing", 8.0 } });
  ASSERT_EQ(events.size(), 2u);  // published once, when stable, not again while it stays the same
  EXPECT_EQ(events[0].event.result.label, "standing");
  EXPECT_EQ(events[1].event.kind, LabelEvent::Kind::Ended);  // closed when the track ends
  EXPECT_TRUE(events[1].event.closes_published);
}

TEST(RecognitionPolicy, TransitionsLearntAsNoActionAreNeverPublished)
{
  // A closed-set model has only actions to answer with, so a step sideways becomes one of them.
  const std::vector<Piece> stream = { { "standing", 1.0 }, { "shift", 2.0 }, { "standing", 2.0 }, { "kick", 2.0 },
                                      { "standing", 2.0 } };
  const auto labelsOf = [&](const std::shared_ptr<ActionModel>& m) {
    RecognitionPolicy policy(m, online());
    std::vector<std::pair<std::string, double>> out;  // each new label and its start
    for (const Published& p : play(policy, stream))
      if (!p.event.closes_published)
        out.emplace_back(p.event.result.label, p.event.start);
    return out;
  };
  // The control: a closed-set model of means only labels the step as an action. (With the pyramid's
  // maxima this hand-built step happens not to be labelled at all, so it would not show the threat.)
  const auto closed = labelsOf(trainedModel(false, true));
  ASSERT_EQ(closed.size(), 2u);
  EXPECT_NE(closed[0].first, "kick");
  EXPECT_EQ(closed[1].first, "kick");
  // A model that learnt such steps as no_action says so, and no_action is idle by default: with
  // either pyramid, only the kick is published.
  for (bool means_only : { true, false })
  {
    const auto open = labelsOf(trainedModel(true, means_only));
    ASSERT_EQ(open.size(), 1u) << "means_only " << means_only;
    EXPECT_EQ(open[0].first, "kick");
    EXPECT_NEAR(open[0].second, 5.0, 0.6);
  }
  // The default closed-set model still finds the kick.
  const auto closed_max = labelsOf(model());
  ASSERT_FALSE(closed_max.empty());
  EXPECT_EQ(closed_max.back().first, "kick");
}

TEST(RecognitionPolicy, TrimmingTakesTheSurestPartOfASegment)
{
  // A kick run straight into a step sideways is one motion segment; cut at its ends, its surest part
  // is the kick, and the label's span ends where the kick does.
  PolicyParams p = online();
  p.publish_early = false;
  const std::vector<Piece> stream = { { "standing", 1.0 }, { "kick", 2.5 }, { "shift", 1.0 }, { "standing", 2.0 } };
  const auto labelled = [&](double trim) {
    p.trim = trim;
    RecognitionPolicy policy(model(), p);
    std::vector<LabelEvent> out;
    for (const Published& e : play(policy, stream))
      out.push_back(e.event);
    return out;
  };
  const auto whole = labelled(0.0);
  const auto trimmed = labelled(1.0);
  ASSERT_EQ(whole.size(), 1u);
  ASSERT_EQ(trimmed.size(), 1u);
  EXPECT_EQ(trimmed[0].result.label, "kick");
  EXPECT_GT(whole[0].end, 4.2);  // the whole segment runs to the end of the step
  EXPECT_LT(trimmed[0].end, whole[0].end - 0.4);
  EXPECT_GE(trimmed[0].result.confidence, whole[0].result.confidence);
  EXPECT_GE(trimmed[0].end - trimmed[0].start, p.min_segment);
}

TEST(RecognitionPolicy, SlidingWindowPublishesEachChangeOnce)
{
  PolicyParams p = online();
  p.motion_segments = false;
  RecognitionPolicy policy(model(), p);
  const auto events = play(policy, { { "wave", 5.0 }, { "kick", 5.0 } });
  ASSERT_EQ(events.size(), 4u);
  EXPECT_EQ(events[0].event.kind, LabelEvent::Kind::Started);
  EXPECT_EQ(events[0].event.result.label, "wave");
  EXPECT_GE(events[0].at, p.min_coverage * p.window);
  // When kick takes over, wave is closed at the last window that showed it, then kick starts.
  EXPECT_EQ(events[1].event.kind, LabelEvent::Kind::Ended);
  EXPECT_EQ(events[1].event.result.label, "wave");
  EXPECT_GT(events[1].event.end, 5.0);
  EXPECT_LT(events[1].event.end, 5.0 + p.window);
  EXPECT_EQ(events[2].event.kind, LabelEvent::Kind::Started);
  EXPECT_EQ(events[2].event.result.label, "kick");
  EXPECT_GT(events[2].at, 5.0);
  EXPECT_EQ(events[3].event.kind, LabelEvent::Kind::Ended);
  EXPECT_EQ(events[3].event.result.label, "kick");
}

TEST(RecognitionPolicy, RejectionThresholdSilencesUnsureLabels)
{
  PolicyParams p = online();
  RecognitionPolicy sure(model(), p);
  const auto events = play(sure, { { "standing", 1.0 }, { "wave", 2.0 }, { "standing", 2.0 } });
  ASSERT_FALSE(events.empty());
  const float confidence = events[0].event.result.confidence;
  ASSERT_LT(confidence, 1.0f);
  p.min_confidence = std::min(1.0, confidence + 0.05);
  RecognitionPolicy strict(model(), p);
  // Each classification of the segment is less sure than the threshold: nothing at all.
  const auto none = play(strict, { { "standing", 1.0 }, { "wave", 2.0 }, { "standing", 2.0 } });
  for (const auto& e : none)
    EXPECT_GE(e.event.result.confidence, p.min_confidence);
}

TEST(RecognitionPolicy, WithoutEarlyLabelsTheWholeSegmentIsLabelledWhenItEnds)
{
  PolicyParams p = online();
  p.publish_early = false;
  RecognitionPolicy policy(model(), p);
  const auto events = play(policy, { { "standing", 1.0 }, { "kick", 2.0 }, { "standing", 2.0 } });
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].event.kind, LabelEvent::Kind::Ended);
  EXPECT_FALSE(events[0].event.closes_published);
  EXPECT_EQ(events[0].event.result.label, "kick");
  EXPECT_NEAR(events[0].event.start, 1.0 - p.pre_roll, 0.2);
  EXPECT_NEAR(events[0].event.end, 3.0 + p.post_roll, 0.2);
}

TEST(RecognitionPolicy, ShortTwitchesAreIgnored)
{
  PolicyParams p = online();
  RecognitionPolicy policy(model(), p);
  EXPECT_TRUE(play(policy, { { "standing", 1.0 }, { "wave", 0.3 }, { "standing", 2.0 } }).empty());
}

TEST(RecognitionPolicy, TrackEndingMidActionClosesItsSegment)
{
  RecognitionPolicy policy(model(), online());
  const auto events = play(policy, { { "standing", 1.0 }, { "kick", 2.5 } });
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].event.kind, LabelEvent::Kind::Ended);
  EXPECT_EQ(events[1].event.result.label, "kick");
  EXPECT_EQ(policy.tracks(), 0u);
}

TEST(RecognitionPolicy, SegmentedTracksNeverMix)
{
  RecognitionPolicy policy(model(), PolicyParams());
  std::mt19937 rng(3);
  for (int i = 0; i < 90; ++i)
  {
    EXPECT_TRUE(policy.add(1, frame(i < 15 || i >= 75 ? "standing" : "wave", i, rng), i / kFps).empty());
    EXPECT_TRUE(policy.add(2, frame(i < 15 || i >= 75 ? "standing" : "kick", i, rng), i / kFps).empty());
  }
  EXPECT_EQ(policy.frames(1), 90u);
  const auto one = policy.end(1);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0].kind, LabelEvent::Kind::Segmented);
  EXPECT_EQ(one[0].result.label, "wave");
  EXPECT_EQ(one[0].frames, 90u);
  EXPECT_DOUBLE_EQ(one[0].end, 89 / kFps);
  const auto two = policy.endAll();
  ASSERT_EQ(two.size(), 1u);
  EXPECT_EQ(two[0].track, 2u);
  EXPECT_EQ(two[0].result.label, "kick");
  EXPECT_EQ(policy.tracks(), 0u);
}

TEST(RecognitionPolicy, RestartAndTooShortSequences)
{
  PolicyParams p;
  p.min_frames = 10;
  RecognitionPolicy policy(model(), p);
  std::mt19937 rng(5);
  for (int i = 0; i < 30; ++i)
    policy.add(4, frame("wave", i, rng), i / kFps);
  policy.restart(4);
  EXPECT_EQ(policy.frames(4), 0u);
  for (int i = 0; i < 9; ++i)
    policy.add(4, frame("wave", i, rng), 1.0 + i / kFps);
  EXPECT_TRUE(policy.end(4).empty());  // 9 < min_frames
  EXPECT_TRUE(policy.end(77).empty());  // unknown track
}

TEST(RecognitionPolicy, RefusesBadInput)
{
  EXPECT_THROW(RecognitionPolicy(nullptr, PolicyParams()), std::invalid_argument);
  PolicyParams bad;
  bad.motion_off = 0.1;
  bad.motion_on = 0.05;
  EXPECT_THROW(RecognitionPolicy(model(), bad), std::invalid_argument);
  bad = PolicyParams();
  bad.stable_count = 0;
  EXPECT_THROW(RecognitionPolicy(model(), bad), std::invalid_argument);
  bad = PolicyParams();
  bad.trim = -0.5;
  EXPECT_THROW(RecognitionPolicy(model(), bad), std::invalid_argument);
  RecognitionPolicy policy(model(), PolicyParams());
  EXPECT_THROW(policy.add(1, Eigen::VectorXf::Zero(12), 0.0), std::invalid_argument);
  EXPECT_THROW(policyModeFromString("sometimes"), std::invalid_argument);
  EXPECT_EQ(policyModeFromString("online"), PolicyParams::Mode::Online);
}

TEST(PostureFlowDescriptor, PostureChangeIsTheFinestSharesL1Distance)
{
  const PostureFlowDescriptor layout;
  Eigen::VectorXf a = Eigen::VectorXf::Zero(layout.size()), b = a;
  a[layout.offset(2)] = 0.6f;  // finest cell 0
  a[layout.offset(2) + kPostureFlowValuesPerCell * 5] = 0.4f;
  b[layout.offset(2)] = 0.5f;
  b[layout.offset(2) + kPostureFlowValuesPerCell * 9] = 0.5f;
  b[layout.offset(2) + 1] = 3.0f;  // flow: not shape
  b[layout.offset(1)] = 0.9f;      // a coarser level: not counted twice
  EXPECT_FLOAT_EQ(layout.postureChange(a, b), 0.1f + 0.4f + 0.5f);
  EXPECT_FLOAT_EQ(layout.postureChange(b, b), 0.0f);
  EXPECT_THROW(layout.postureChange(a, Eigen::VectorXf::Zero(3)), std::invalid_argument);
}
