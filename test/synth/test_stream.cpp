// Tests of the continuous streams of actions (dataset "stream"): the sets and the drawn actions,
// determinism, the ground-truth segments, and that they match the rendered motion (walks cross
// the view, sitting is low, idle is still, no jumps at transitions, the head in the image). And of
// the streams of real motion (dataset "msr_stream"): the dealing of a subject's MSR sequences, the
// segments, continuity at the joins, determinism, a continuous file with a segments file.
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <unistd.h>

using namespace action_flow::synth;

namespace
{
SampleSpec stream(const std::string& person, int number, int max_frames = 0, int actions = 8, std::uint64_t seed = 1)
{
  SampleSpec s;
  s.dataset = "stream";
  s.person = person;
  s.action = "stream";
  s.repetition = number;
  s.seed = seed;
  s.max_frames = max_frames;
  s.stream_actions = actions;
  return s;
}

Eigen::Vector3f pelvis(const Skeleton& s) { return 0.5f * (s[Joint::LeftHip] + s[Joint::RightHip]); }

bool sameJoints(const SampleRenderer& a, const SampleRenderer& b)
{
  if (a.frames() != b.frames())
    return false;
  for (int i = 0; i < a.frames(); ++i)
    for (int k = 0; k < kJointCount; ++k)
      if (a.worldSkeleton(i).joints[k] != b.worldSkeleton(i).joints[k])
        return false;
  return true;
}

bool sameSegments(const std::vector<StreamSegment>& a, const std::vector<StreamSegment>& b)
{
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const StreamSegment& x, const StreamSegment& y) {
           return x.action == y.action && x.first == y.first && x.last == y.last;
         });
}

// The streams the motion tests look at: 6 people x 2 streams of 8 actions (96 actions, several
// walks and sit_down / get_up pairs among them).
const std::vector<SampleSpec>& testStreams()
{
  static const std::vector<SampleSpec> specs = streamSamples(1, 6, 2);
  return specs;
}
}  // namespace

TEST(Stream, SetsNamesAndValidation)
{
  const auto specs = streamSamples(3, 2, 4, 6, 7);
  ASSERT_EQ(specs.size(), 8u);
  EXPECT_EQ(specs.front().name(), "p03_stream_1");
  EXPECT_EQ(specs[3].name(), "p03_stream_4");
  EXPECT_EQ(specs[4].name(), "p04_stream_1");
  EXPECT_EQ(specs.back().name(), "p04_stream_4");
  for (const auto& s : specs)
  {
    EXPECT_EQ(s.dataset, "stream");
    EXPECT_EQ(s.action, "stream");
    EXPECT_EQ(s.stream_actions, 6);
    EXPECT_EQ(s.seed, 7u);
  }
  EXPECT_EQ(streamSamples(99, 1, 1).front().person, "p99");
  EXPECT_THROW(streamSamples(0, 1, 1), std::invalid_argument);
  EXPECT_THROW(streamSamples(98, 3, 1), std::invalid_argument);
  EXPECT_THROW(streamSamples(1, 0, 1), std::invalid_argument);
  EXPECT_THROW(streamSamples(1, 1, 0), std::invalid_argument);
  EXPECT_THROW(streamSamples(1, 1, 1, 0), std::invalid_argument);
  EXPECT_THROW(streamSamples(1, 1, 1, 100), std::invalid_argument);
  EXPECT_THROW(streamActions(stream("s01", 1)), std::invalid_argument);
  EXPECT_THROW(streamActions(stream("p01", 0)), std::invalid_argument);
  SampleSpec wrong = stream("p01", 1);
  wrong.action = "wave";
  EXPECT_THROW(SampleRenderer{ wrong }, std::invalid_argument);
}

TEST(Stream, ActionsAreBalancedPairedAndNeverRepeated)
{
  const std::set<std::string> all(iasLabActions().begin(), iasLabActions().end());
  std::map<std::string, int> counts;
  int total = 0;
  for (const auto& spec : streamSamples(1, 10, 10))
  {
    const auto actions = streamActions(spec);
    ASSERT_EQ(int(actions.size()), spec.stream_actions) << spec.name();
    for (size_t k = 0; k < actions.size(); ++k)
    {
      const std::string& a = actions[k];
      ASSERT_TRUE(all.count(a)) << a;
      EXPECT_NE(a, "standing") << spec.name();
      if (k > 0)
      {
        EXPECT_NE(a, actions[k - 1]) << spec.name() << " action " << k;
      }
      if (a == "sit_down")
      {
        ASSERT_LT(k + 1, actions.size()) << spec.name() << ": sit_down last";
        EXPECT_EQ(actions[k + 1], "get_up") << spec.name();
      }
      if (a == "get_up")
      {
        ASSERT_GT(k, 0u) << spec.name();
        EXPECT_EQ(actions[k - 1], "sit_down") << spec.name();
      }
      ++counts[a];
      ++total;
    }
  }
  // Every action but standing, about equally often (800 actions, 57 each).
  ASSERT_EQ(counts.size(), 14u);
  for (const auto& [a, n] : counts)
  {
    EXPECT_GT(n, 0.85 * total / 14) << a;
    EXPECT_LT(n, 1.15 * total / 14) << a;
  }
  // A single action per stream: never the pair.
  for (int k = 1; k <= 20; ++k)
  {
    const auto one = streamActions(stream("p02", k, 0, 1));
    ASSERT_EQ(one.size(), 1u);
    EXPECT_NE(one[0], "sit_down");
    EXPECT_NE(one[0], "get_up");
  }
}

TEST(Stream, SameSpecSameStreamOthersDiffer)
{
  const SampleRenderer a(stream("p04", 2)), b(stream("p04", 2));
  EXPECT_TRUE(sameJoints(a, b));
  EXPECT_TRUE(sameSegments(a.segments(), b.segments()));
  EXPECT_EQ(a.label(), "stream");
  action_flow::Cloud ca, cb;
  std::vector<std::uint8_t> ma, mb;
  const int f = a.segments()[2].first;
  a.render(f, ca, &ma);
  b.render(f, cb, &mb);
  ASSERT_EQ(ca.size(), cb.size());
  EXPECT_EQ(std::memcmp(ca.points.data(), cb.points.data(), ca.size() * sizeof(action_flow::PointT)), 0);
  EXPECT_EQ(ma, mb);
  EXPECT_GT(std::count(ma.begin(), ma.end(), 1), 3000);
  // Another stream of the person, another person, another seed: other actions or other motion.
  for (const SampleSpec& other : { stream("p04", 3), stream("p05", 2), stream("p04", 2, 0, 8, 2) })
  {
    const SampleRenderer c(other);
    EXPECT_FALSE(sameJoints(a, c)) << other.name() << " " << other.seed;
    EXPECT_FALSE(sameSegments(a.segments(), c.segments())) << other.name() << " " << other.seed;
  }
}

TEST(Stream, SegmentsAreOrderedAndSeparatedByIdle)
{
  for (const auto& spec : testStreams())
  {
    const SampleRenderer r(spec);
    const double fps = r.camera().fps;
    const auto& segs = r.segments();
    const auto actions = streamActions(spec);
    ASSERT_EQ(segs.size(), size_t(spec.stream_actions)) << spec.name();
    // About a minute.
    EXPECT_GT(r.frames(), 35 * fps) << spec.name();
    EXPECT_LT(r.frames(), 85 * fps) << spec.name();
    // Idle at the start and the end (at least the 1 s lead), between segments at least 0.5 s.
    EXPECT_GE(segs.front().first, int(fps)) << spec.name();
    EXPECT_LE(segs.back().last, r.frames() - 1 - int(fps)) << spec.name();
    for (size_t k = 0; k < segs.size(); ++k)
    {
      EXPECT_EQ(segs[k].action, actions[k]) << spec.name();
      EXPECT_NE(segs[k].action, "standing");
      EXPECT_GE(segs[k].first, 0);
      EXPECT_LT(segs[k].first, segs[k].last) << spec.name() << " " << k;
      EXPECT_LT(segs[k].last, r.frames());
      if (segs[k].action == "sit_down")
      {
        ASSERT_LT(k + 1, segs.size());
        EXPECT_EQ(segs[k + 1].action, "get_up");
      }
      if (k > 0)
      {
        EXPECT_GE(segs[k].first - segs[k - 1].last - 1, 0.5 * fps) << spec.name() << " between " << k - 1 << " and " << k;
      }
    }
    // actionAt agrees with the segments everywhere.
    size_t s = 0;
    for (int i = 0; i < r.frames(); ++i)
    {
      while (s < segs.size() && segs[s].last < i)
        ++s;
      const std::string expected = s < segs.size() && segs[s].first <= i ? segs[s].action : "";
      ASSERT_EQ(r.actionAt(i), expected) << spec.name() << " frame " << i;
    }
    EXPECT_THROW(r.actionAt(r.frames()), std::out_of_range);
    EXPECT_THROW(r.actionAt(-1), std::out_of_range);
  }
}

TEST(Stream, GroundTruthMatchesTheMotion)
{
  const Joint trunk[] = { Joint::Head, Joint::Neck, Joint::Torso, Joint::LeftHip, Joint::RightHip };
  int walks = 0, sits = 0;
  for (const auto& spec : testStreams())
  {
    const SampleRenderer r(spec);
    const auto& segs = r.segments();
    const float standing_z = pelvis(r.worldSkeleton(0)).z();
    const auto pelvisAt = [&](int i) { return pelvis(r.worldSkeleton(i)); };
    const auto shoulders = [&](int i) {
      return (r.worldSkeleton(i)[Joint::LeftShoulder] - r.worldSkeleton(i)[Joint::RightShoulder]).norm();
    };
    // Continuity: no joint jumps more than 0.15 m between frames in idle periods, transitions and
    // at the edges of the segments; the trunk nowhere (limbs move fast within some actions). Turns
    // rotate the body, they do not squash it: the shoulders keep their width.
    for (int i = 1; i < r.frames(); ++i)
    {
      const bool within = !r.actionAt(i).empty() && r.actionAt(i - 1) == r.actionAt(i);
      if (!within)
      {
        ASSERT_NEAR(shoulders(i), shoulders(0), 0.05f * shoulders(0)) << spec.name() << " frame " << i;
      }
      for (int k = 0; k < kJointCount; ++k)
      {
        const float jump = (r.worldSkeleton(i).joints[k] - r.worldSkeleton(i - 1).joints[k]).norm();
        const bool is_trunk = std::find(std::begin(trunk), std::end(trunk), Joint(k)) != std::end(trunk);
        if (!within || is_trunk)
        {
          ASSERT_LT(jump, 0.15f) << spec.name() << " frame " << i << " " << jointName(Joint(k)) << " in '" << r.actionAt(i)
                                 << "'";
        }
      }
    }
    // Outside the segments the actor stays where it is (a weight shift, a turn on the spot).
    int from = 0;
    for (size_t k = 0; k <= segs.size(); ++k)
    {
      const int to = k < segs.size() ? segs[k].first : r.frames() - 1;
      for (int i = from; i <= to; ++i)
        ASSERT_LT((pelvisAt(i) - pelvisAt(from)).head<2>().norm(), 0.12f) << spec.name() << " frame " << i;
      if (k < segs.size())
        from = segs[k].last;
    }
    for (const StreamSegment& s : segs)
    {
      const Eigen::Vector3f a = pelvisAt(s.first), b = pelvisAt(s.last);
      if (s.action == "walk")
      {
        // Across the view, toward the side with more room, ending in view.
        ++walks;
        EXPECT_GT(std::abs(b.y() - a.y()), 1.0f) << spec.name();
        EXPECT_LT(std::abs(b.x() - a.x()), 0.25f) << spec.name();
        EXPECT_LT(b.x(), a.x() + 0.03f) << spec.name() << ": walks never away from the camera (chairs stay behind)";
        EXPECT_LT(a.y() * (b.y() - a.y()), 0.0f) << spec.name() << ": walks toward the side with more room";
        EXPECT_LT(std::abs(b.y()), 1.3f) << spec.name();
        // The segment is the walk itself: moving within a few frames of either end.
        EXPECT_GT((pelvisAt(s.first + 6) - a).head<2>().norm(), 0.015f) << spec.name();
        EXPECT_GT((b - pelvisAt(s.last - 6)).head<2>().norm(), 0.015f) << spec.name();
        continue;
      }
      // Elsewhere the actor stays on the spot, 3-3.6 m away, facing the camera within 30 degrees.
      EXPECT_LT((b - a).head<2>().norm(), s.action == "sit_down" || s.action == "get_up" ? 0.5f : 0.15f)
          << spec.name() << " " << s.action;
      if (s.action != "get_up")
      {
        EXPECT_GT(a.x(), 2.95f) << spec.name();
        EXPECT_LT(a.x(), 3.65f) << spec.name();
        EXPECT_LT(std::abs(a.y()), 1.3f) << spec.name();
        const Eigen::Vector3f f = r.posedBody(s.first).forward;
        const float off = std::acos(std::clamp(f.head<2>().normalized().dot(-a.head<2>().normalized()), -1.0f, 1.0f));
        EXPECT_LT(off, 0.55f) << spec.name() << " " << s.action;
      }
      if (s.action == "sit_down")
      {
        ++sits;
        EXPECT_LT(b.z(), standing_z - 0.2f) << spec.name();
        EXPECT_GT(a.z(), standing_z - 0.05f) << spec.name();
      }
      if (s.action == "get_up")
      {
        EXPECT_LT(a.z(), standing_z - 0.2f) << spec.name();
        EXPECT_GT(b.z(), standing_z - 0.05f) << spec.name();
      }
    }
    // Seated from sit_down to get_up.
    for (size_t k = 0; k + 1 < segs.size(); ++k)
    {
      if (segs[k].action != "sit_down")
        continue;
      for (int i = segs[k].last; i <= segs[k + 1].first; ++i)
      {
        ASSERT_LT(pelvisAt(i).z(), standing_z - 0.2f) << spec.name() << " frame " << i;
      }
    }
  }
  EXPECT_GE(walks, 3);
  EXPECT_GE(sits, 3);
}

TEST(Stream, HeadStaysInTheImage)
{
  int frames = 0, out = 0;
  for (const auto& spec : streamSamples(1, 12, 2, 8, 3))
  {
    const SampleRenderer r(spec);
    const auto& cam = r.camera();
    for (int i = 0; i < r.frames(); ++i)
    {
      const Eigen::Vector3f p = r.skeleton(i)[Joint::Head];
      const double u = cam.fx * p.x() / p.z() + cam.cx, v = cam.fy * p.y() / p.z() + cam.cy;
      out += u > 10 && u < cam.width - 11 && v > 10 && v < cam.height - 11 ? 0 : 1;
      ++frames;
    }
  }
  EXPECT_GT(frames, 24 * 1000);
  EXPECT_LE(out, frames / 1000) << out << " of " << frames << " frames with the head outside the image";
}

TEST(Stream, MaxFramesClipsTheSegments)
{
  const SampleRenderer full(stream("p07", 1));
  const auto& all = full.segments();
  ASSERT_GE(all.size(), 3u);
  const int cut = (all[1].first + all[1].last) / 2;
  const SampleRenderer part(stream("p07", 1, cut + 1));
  ASSERT_EQ(part.frames(), cut + 1);
  ASSERT_EQ(part.segments().size(), 2u);
  EXPECT_EQ(part.segments()[0].last, all[0].last);
  EXPECT_EQ(part.segments()[1].first, all[1].first);
  EXPECT_EQ(part.segments()[1].last, cut);
  EXPECT_EQ(part.actionAt(cut), all[1].action);
  for (int i = 0; i < part.frames(); i += 7)
    EXPECT_EQ(part.worldSkeleton(i).joints[0], full.worldSkeleton(i).joints[0]);
  // Cut before the first action: no segment.
  EXPECT_TRUE(SampleRenderer(stream("p07", 1, all[0].first)).segments().empty());
}

TEST(Stream, IasSampleIsOneSegment)
{
  SampleSpec s;
  s.person = "p02";
  s.action = "kick";
  const SampleRenderer full(s);
  ASSERT_EQ(full.segments().size(), 1u);
  EXPECT_EQ(full.segments()[0].action, "kick");
  EXPECT_EQ(full.segments()[0].first, 0);
  EXPECT_EQ(full.segments()[0].last, full.frames() - 1);
  EXPECT_EQ(full.actionAt(full.frames() / 2), "kick");
  s.max_frames = 5;
  const SampleRenderer part(s);
  ASSERT_EQ(part.segments().size(), 1u);
  EXPECT_EQ(part.segments()[0].last, 4);
}

// ---- Streams of real motion (dataset "msr_stream") ----

namespace
{
std::string msrFolder() { return std::string(ACTION_FLOW_SHARED_DATA) + "/msr_action3d_skeletons"; }

#define SKIP_WITHOUT_MSR()                                                                                               \
  if (!std::filesystem::exists(msrFolder()))                                                                             \
  GTEST_SKIP() << "MSR skeletons not found at " << msrFolder()

std::string key(const SampleSpec& s) { return s.name(); }
}  // namespace

TEST(MsrStream, SetsAndDealing)
{
  SKIP_WITHOUT_MSR();
  const auto specs = msrStreamSamples(msrFolder(), { "s01", "s02" }, 2, 8, 3);
  ASSERT_EQ(specs.size(), 4u);
  EXPECT_EQ(specs[0].name(), "s01_msr_stream_1");
  EXPECT_EQ(specs[3].name(), "s02_msr_stream_2");
  for (const auto& s : specs)
  {
    EXPECT_EQ(s.dataset, "msr_stream");
    EXPECT_EQ(s.action, "stream");
    EXPECT_EQ(s.skeleton_file, msrFolder());
    EXPECT_EQ(s.stream_actions, 8);
    EXPECT_EQ(s.seed, 3u);
  }
  // Five streams of four: the first round of the deal, one take of each of the 20 actions (s01 has
  // all 20 in the cvpr12 list); over all the subject's streams no sequence twice, all of them the
  // subject's own (s04: 37 sequences of 13 actions).
  std::set<std::string> actions, used;
  for (const auto& spec : msrStreamSamples(msrFolder(), { "s01" }, 5, 4))
    for (const auto& seq : msrStreamSequences(spec))
    {
      EXPECT_EQ(seq.person, "s01");
      EXPECT_EQ(seq.dataset, "msr");
      EXPECT_TRUE(used.insert(key(seq)).second) << key(seq) << " used twice";
      actions.insert(seq.action);
    }
  EXPECT_EQ(actions.size(), 20u);
  size_t all = 0;
  for (const auto& s : msrSamples(msrFolder()))
    all += s.person == "s04";
  const int per_stream = 6, streams = int(all) / per_stream;
  used.clear();
  for (const auto& spec : msrStreamSamples(msrFolder(), { "s04" }, streams, per_stream))
  {
    const auto seqs = msrStreamSequences(spec);
    for (size_t k = 0; k < seqs.size(); ++k)
    {
      EXPECT_TRUE(used.insert(key(seqs[k])).second) << key(seqs[k]) << " used twice";
      if (k > 0)
      {
        EXPECT_NE(seqs[k].action, seqs[k - 1].action) << spec.name();
      }
    }
  }
  EXPECT_EQ(used.size(), size_t(streams * per_stream));
  // Deterministic in the seed; another seed deals otherwise; a pool restricts the actions.
  const auto a = msrStreamSequences(specs[0]), b = msrStreamSequences(msrStreamSamples(msrFolder(), { "s01" }, 1, 8, 3)[0]);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k)
    EXPECT_EQ(key(a[k]), key(b[k]));
  const auto c = msrStreamSequences(msrStreamSamples(msrFolder(), { "s01" }, 1, 8, 4)[0]);
  EXPECT_FALSE(std::equal(a.begin(), a.end(), c.begin(), [](const SampleSpec& x, const SampleSpec& y) { return key(x) == key(y); }));
  const std::vector<std::string> pool = { "bend", "hand_clap", "hammer" };
  for (const auto& seq : msrStreamSequences(msrStreamSamples(msrFolder(), { "s05" }, 1, 6, 1, pool)[0]))
    EXPECT_NE(std::find(pool.begin(), pool.end(), seq.action), pool.end()) << seq.action;
  EXPECT_THROW(msrStreamSamples(msrFolder(), { "s05" }, 2, 6, 1, pool), std::invalid_argument);  // 9 sequences
  EXPECT_THROW(msrStreamSamples(msrFolder(), { "s01" }, 1, 8, 1, { "jump" }), std::invalid_argument);
  EXPECT_THROW(msrStreamSamples(msrFolder(), { "p01" }, 1, 8), std::invalid_argument);
  EXPECT_THROW(msrStreamSamples(msrFolder(), { "s01" }, 0, 8), std::invalid_argument);
  EXPECT_THROW(msrStreamSamples(msrFolder(), { "s01" }, 1, 100), std::invalid_argument);
}

TEST(MsrStream, SegmentsAreTheSequencesSeparatedByIdle)
{
  SKIP_WITHOUT_MSR();
  const Joint trunk[] = { Joint::Head, Joint::Neck, Joint::Torso, Joint::LeftHip, Joint::RightHip };
  for (const auto& spec : msrStreamSamples(msrFolder(), { "s02", "s07" }, 2, 8))
  {
    const SampleRenderer r(spec);
    const double fps = r.camera().fps;
    const auto seqs = msrStreamSequences(spec);
    const auto& segs = r.segments();
    EXPECT_EQ(r.label(), "stream");
    ASSERT_EQ(segs.size(), seqs.size()) << spec.name();
    EXPECT_GE(segs.front().first, int(fps)) << spec.name();
    EXPECT_LE(segs.back().last, r.frames() - 1 - int(fps)) << spec.name();
    const Eigen::Vector3f spot = pelvis(r.worldSkeleton(segs.front().first));
    for (size_t k = 0; k < segs.size(); ++k)
    {
      // The whole sequence, at 30 fps, its own motion, re-centred on the spot the subject stands on.
      EXPECT_EQ(segs[k].action, seqs[k].action);
      const SampleRenderer m(seqs[k]);
      EXPECT_NEAR(segs[k].last - segs[k].first + 1, m.frames(), 1) << spec.name() << " " << key(seqs[k]);
      const Eigen::Vector3f start = pelvis(r.worldSkeleton(segs[k].first));
      EXPECT_LT((start - spot).head<2>().norm(), 1e-4f) << spec.name() << " " << k;
      for (int i = 0; i < m.frames() && segs[k].first + i <= segs[k].last; i += 3)
        for (int j = 0; j < kJointCount; ++j)
        {
          const Eigen::Vector3f got = r.worldSkeleton(segs[k].first + i).joints[j] - start;
          const Eigen::Vector3f want = m.worldSkeleton(i).joints[j] - pelvis(m.worldSkeleton(0));
          ASSERT_LT((got - want).norm(), 1e-4f) << spec.name() << " " << key(seqs[k]) << " frame " << i;
        }
      if (k > 0)
      {
        EXPECT_GE(segs[k].first - segs[k - 1].last - 1, 0.5 * fps) << spec.name() << " between " << k - 1 << " and " << k;
        EXPECT_LE(segs[k].first - segs[k - 1].last - 1, 3.0 * fps + 1) << spec.name();
      }
    }
    // actionAt agrees with the segments everywhere.
    size_t s = 0;
    for (int i = 0; i < r.frames(); ++i)
    {
      while (s < segs.size() && segs[s].last < i)
        ++s;
      const std::string expected = s < segs.size() && segs[s].first <= i ? segs[s].action : "";
      ASSERT_EQ(r.actionAt(i), expected) << spec.name() << " frame " << i;
    }
    // Continuous across the joins: idle periods, transitions and the edges of the segments (inside
    // a sequence the recording is as it is).
    for (int i = 1; i < r.frames(); ++i)
    {
      if (!r.actionAt(i).empty() && r.actionAt(i - 1) == r.actionAt(i))
        continue;
      for (Joint j : trunk)
      {
        ASSERT_LT((r.worldSkeleton(i)[j] - r.worldSkeleton(i - 1)[j]).norm(), 0.15f)
            << spec.name() << " frame " << i << " " << jointName(j);
      }
    }
  }
}

TEST(MsrStream, SameSpecSameOutputOthersDiffer)
{
  SKIP_WITHOUT_MSR();
  const auto specs = msrStreamSamples(msrFolder(), { "s03" }, 2, 5);
  const SampleRenderer a(specs[0]), b(specs[0]), c(specs[1]);
  EXPECT_TRUE(sameJoints(a, b));
  EXPECT_TRUE(sameSegments(a.segments(), b.segments()));
  EXPECT_FALSE(sameJoints(a, c));
  action_flow::Cloud ca, cb;
  std::vector<std::uint8_t> ma, mb;
  const int f = a.segments()[1].first + 5;
  a.render(f, ca, &ma);
  b.render(f, cb, &mb);
  ASSERT_EQ(ca.size(), cb.size());
  EXPECT_EQ(std::memcmp(ca.points.data(), cb.points.data(), ca.size() * sizeof(action_flow::PointT)), 0);
  EXPECT_EQ(ma, mb);
  EXPECT_GT(std::count(ma.begin(), ma.end(), 1), 3000);
}

namespace
{
/**
 * A continuous recording in the MSR text format: a person standing 2.5 m from the camera who raises
 * the right arm (the second joint of each pair) over frames 10-19 and 30-39 of 50; frame 25 untracked.
 */
void writeTinyMsrFile(const std::string& path)
{
  // Joints 1..20 standing (x right as in the files, y up, z away).
  const float pose[20][3] = { { -0.18f, 0.45f, 2.5f },  { 0.18f, 0.45f, 2.5f },  { 0, 0.5f, 2.5f },
                              { 0, 0.2f, 2.5f },        { -0.1f, 0, 2.5f },      { 0.1f, 0, 2.5f },
                              { 0, 0, 2.5f },           { -0.22f, 0.18f, 2.5f }, { 0.22f, 0.18f, 2.5f },
                              { -0.24f, -0.05f, 2.5f }, { 0.24f, -0.05f, 2.5f }, { -0.25f, -0.12f, 2.5f },
                              { 0.25f, -0.12f, 2.5f },  { -0.1f, -0.45f, 2.5f }, { 0.1f, -0.45f, 2.5f },
                              { -0.1f, -0.85f, 2.5f },  { 0.1f, -0.85f, 2.5f },  { -0.1f, -0.9f, 2.45f },
                              { 0.1f, -0.9f, 2.45f },   { 0, 0.68f, 2.5f } };
  std::ofstream out(path);
  for (int f = 0; f < 50; ++f)
    for (int j = 0; j < 20; ++j)
    {
      const bool raising = (f >= 10 && f < 20) || (f >= 30 && f < 40);
      const float lift = raising && (j == 10 || j == 12) ? 0.9f * std::sin(3.14159f * ((f % 10) + 0.5f) / 10) : 0.0f;
      if (f == 25)
        out << "0 0 0 0\n";
      else
        out << pose[j][0] << " " << pose[j][1] + lift << " " << pose[j][2] << " 1\n";
    }
}

std::filesystem::path tempFolder()
{
  const auto dir = std::filesystem::temp_directory_path() / ("action_flow_msr_stream_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

void writeText(const std::filesystem::path& path, const std::string& text) { std::ofstream(path) << text; }
}  // namespace

TEST(MsrStream, ContinuousFileRendersWithItsSegmentsFile)
{
  const auto dir = tempFolder();
  writeTinyMsrFile((dir / "recording.txt").string());
  writeText(dir / "segments.csv", "action,first_frame,last_frame\nhigh_arm_wave,9,20\nhand_clap,29,40\n");
  SampleSpec spec;
  spec.dataset = "msr_stream";
  spec.person = "s03";
  spec.action = "stream";
  spec.skeleton_file = (dir / "recording.txt").string();
  spec.segments_file = (dir / "segments.csv").string();
  const SampleRenderer r(spec);
  EXPECT_EQ(spec.name(), "recording");
  EXPECT_EQ(r.label(), "stream");
  ASSERT_EQ(r.frames(), 2 * 50 - 1);
  EXPECT_TRUE(sameSegments(r.segments(), { { "high_arm_wave", 18, 40 }, { "hand_clap", 58, 80 } }));
  EXPECT_EQ(r.actionAt(17), "");
  EXPECT_EQ(r.actionAt(18), "high_arm_wave");
  EXPECT_EQ(r.actionAt(40), "high_arm_wave");
  EXPECT_EQ(r.actionAt(41), "");
  EXPECT_EQ(r.actionAt(70), "hand_clap");
  EXPECT_EQ(r.actionAt(98), "");
  // The file's motion: the right hand rises in the raises (frame 15 of the file is 30 here), and
  // the untracked frame is interpolated.
  const auto handOverHip = [&](int i) { return r.worldSkeleton(i)[Joint::RightHand].z() - r.worldSkeleton(i)[Joint::RightHip].z(); };
  EXPECT_GT(handOverHip(30) - handOverHip(0), 0.8f);
  EXPECT_NEAR(handOverHip(50), handOverHip(0), 0.01f);
  EXPECT_NEAR(pelvis(r.worldSkeleton(50)).x(), pelvis(r.worldSkeleton(0)).x(), 1e-4f);
  action_flow::Cloud cloud;
  std::vector<std::uint8_t> mask;
  r.render(30, cloud, &mask);
  EXPECT_GT(std::count(mask.begin(), mask.end(), 1), 3000);
  // max_frames clips that truth too.
  spec.max_frames = 60;
  EXPECT_TRUE(sameSegments(SampleRenderer(spec).segments(), { { "high_arm_wave", 18, 40 }, { "hand_clap", 58, 59 } }));
  spec.max_frames = 0;

  // Malformed segments files name the file and line.
  for (const std::string& bad : { std::string("wave,10,5\n"), std::string("wave,0,50\n"), std::string("a,0,9\nb,9,12\n"),
                                  std::string("wave,x,4\n"), std::string("wave,1\n"), std::string(",1,2\n") })
  {
    writeText(dir / "bad.csv", bad);
    spec.segments_file = (dir / "bad.csv").string();
    try
    {
      SampleRenderer{ spec };
      ADD_FAILURE() << "accepted '" << bad << "'";
    }
    catch (const std::runtime_error& e)
    {
      EXPECT_NE(std::string(e.what()).find("bad.csv:"), std::string::npos) << e.what();
    }
  }
  spec.segments_file = (dir / "missing.csv").string();
  EXPECT_THROW(SampleRenderer{ spec }, std::runtime_error);
  std::filesystem::remove_all(dir);
}
