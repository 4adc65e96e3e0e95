// Crowd scenes of the virtual Kinect give the ground truth they promise: people ids per pixel where
// those people are, positions at 1-5 m facing every way, people entering, leaving and crossing,
// kept apart, with their own action segments.
#include <action_flow/synth/crowd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

using namespace action_flow;
using namespace action_flow::synth;

namespace
{
SampleSpec scene(int people, int number, double seconds = 60.0)
{
  return crowdSamples(people, number, seconds).back();
}

float bearing(const Eigen::Vector3f& p) { return std::atan2(p.y(), p.x()); }

/** Mean of a person's joints, world. */
Eigen::Vector3f centre(const Skeleton& s)
{
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  for (const auto& j : s.joints)
    c += j / float(kJointCount);
  return c;
}
}  // namespace

TEST(Crowd, SpecsAreCheckedAndNamed)
{
  EXPECT_THROW(crowdSamples(1, 1), std::invalid_argument);
  EXPECT_THROW(crowdSamples(6, 1), std::invalid_argument);
  EXPECT_THROW(crowdSamples(3, 0), std::invalid_argument);
  EXPECT_THROW(crowdSamples(3, 1, 1.0), std::invalid_argument);
  const auto specs = crowdSamples(3, 2);
  ASSERT_EQ(specs.size(), 2u);
  EXPECT_EQ(specs[1].name(), "crowd3_2");
  EXPECT_EQ(specs[1].person, "p04+p05+p06");
  SampleSpec not_crowd = specs[0];
  not_crowd.dataset = "ias";
  EXPECT_THROW(CrowdRenderer{ not_crowd }, std::invalid_argument);
  EXPECT_THROW(SampleRenderer{ specs[0] }, std::invalid_argument) << "a crowd is not a single-person sample";
}

TEST(Crowd, MaskIdsArePeopleWherePeopleAre)
{
  const CrowdRenderer crowd(scene(3, 1, 20.0));
  ASSERT_EQ(crowd.people().size(), 3u);
  const CameraModel& cam = crowd.camera();
  const Eigen::Isometry3f to_optical = cam.worldFromOptical().inverse();
  int checked = 0;
  FrameImages im;
  for (int i = 0; i < crowd.frames(); i += 97)
  {
    crowd.renderImages(i, im);
    const std::vector<CrowdTruth> truth = crowd.truth(i, im);
    std::set<int> present;
    for (const CrowdTruth& t : truth)
      present.insert(t.mask_id);
    for (std::uint8_t m : im.mask)
      ASSERT_TRUE(m == 0 || present.count(m)) << "frame " << i << ": mask id " << int(m) << " of nobody present";
    for (const CrowdTruth& t : truth)
    {
      if (!t.counted)
        continue;
      // The pixels of this id lie around the person's own image column, at the person's depth.
      const Eigen::Vector3f c = to_optical * t.position;
      const double u_person = cam.fx * c.x() / c.z() + cam.cx;
      double u_sum = 0, depth_sum = 0;
      int n = 0, with_depth = 0;
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u)
        {
          const size_t p = size_t(v) * size_t(cam.width) + size_t(u);
          if (im.mask[p] != t.mask_id)
            continue;
          u_sum += u;
          ++n;
          if (std::isfinite(im.depth[p]))
            depth_sum += im.depth[p], ++with_depth;
        }
      ASSERT_GT(n, 0);
      EXPECT_EQ(with_depth, t.visible_pixels);
      EXPECT_NEAR(u_sum / n, u_person, 0.35 * cam.fx / c.z()) << "frame " << i << " person " << int(t.mask_id);
      EXPECT_NEAR(depth_sum / with_depth, c.z(), 0.5) << "frame " << i << " person " << int(t.mask_id);
      EXPECT_GE(t.visible_area, kCrowdMinVisibleArea);
      EXPECT_TRUE(t.head_visible);
      ++checked;
    }
  }
  EXPECT_GE(checked, 6) << "too few counted people to check";
}

TEST(Crowd, PeopleComeAndGoCrossAndFaceEveryWay)
{
  int entering = 0, leaving = 0, crossings = 0;
  std::set<int> quadrants;
  float nearest = 1e9f, farthest = 0, closest = 1e9f;
  for (int number = 1; number <= 3; ++number)
  {
    const CrowdRenderer crowd(scene(3, number));
    EXPECT_GE(crowd.leastClearance(), 0.6f) << "people walk through each other in scene " << number;
    const double slope = crowd.camera().cx / crowd.camera().fx;
    for (size_t k = 0; k < crowd.people().size(); ++k)
    {
      const CrowdPerson& p = crowd.people()[k];
      if (p.enters)
      {
        ++entering;
        EXPECT_GT(p.first_frame, 0);
        const Eigen::Vector3f start = centre(crowd.worldSkeleton(k, p.first_frame));
        EXPECT_GT(std::abs(start.y()), start.x() * slope) << "a person walking in starts outside the view";
      }
      if (p.leaves && p.last_frame < crowd.frames() - 1)
      {
        ++leaving;
        const Eigen::Vector3f end = centre(crowd.worldSkeleton(k, p.last_frame));
        EXPECT_GT(std::abs(end.y()), end.x() * slope) << "a person walking out ends outside the view";
      }
    }
    std::vector<int> side(9, 0);
    for (int i = 0; i < crowd.frames(); i += 3)
      for (size_t a = 0; a < crowd.people().size(); ++a)
      {
        if (!crowd.present(a, i))
          continue;
        const Eigen::Vector3f pa = centre(crowd.worldSkeleton(a, i));
        closest = std::min(closest, pa.x());
        if (std::abs(bearing(pa)) < 0.5f)
        {
          nearest = std::min(nearest, pa.x());
          farthest = std::max(farthest, pa.x());
        }
        for (size_t b = a + 1; b < crowd.people().size(); ++b)
          if (crowd.present(b, i) && std::abs(bearing(pa)) < 0.5f)
          {
            const Eigen::Vector3f pb = centre(crowd.worldSkeleton(b, i));
            const int s = bearing(pa) > bearing(pb) ? 1 : -1;
            int& last = side[a * 3 + b];
            crossings += last != 0 && last != s ? 1 : 0;
            last = s;
          }
      }
    FrameImages im;
    for (int i = 0; i < crowd.frames(); i += 150)
    {
      crowd.renderImages(i, im);
      for (const CrowdTruth& t : crowd.truth(i, im))
        quadrants.insert(int(std::floor((t.yaw + 3.14159265f) / (3.14159265f / 2))) % 4);
    }
  }
  EXPECT_GE(entering, 1);
  EXPECT_GE(leaving, 1);
  EXPECT_GE(crossings, 3) << "people should pass each other in the image";
  EXPECT_EQ(quadrants.size(), 4u) << "people face every way";
  EXPECT_LT(nearest, 1.8f);
  EXPECT_GE(closest, 0.9f) << "nobody comes nearer to the camera than the nearest spots (1 m)";
  EXPECT_GT(farthest, 4.2f);
}

TEST(Crowd, EveryoneHasTheirOwnActionSegments)
{
  const CrowdRenderer crowd(scene(4, 2));
  std::set<std::string> actions;
  const auto& ias = iasLabActions();
  for (const CrowdPerson& p : crowd.people())
  {
    ASSERT_FALSE(p.segments.empty()) << p.actor;
    int previous_last = -1;
    bool walks = false;
    for (const StreamSegment& s : p.segments)
    {
      EXPECT_GT(s.first, previous_last) << p.actor << ": segments ordered, not overlapping";
      EXPECT_LE(s.first, s.last);
      EXPECT_GE(s.first, p.first_frame);
      EXPECT_LE(s.last, p.last_frame);
      EXPECT_NE(std::find(ias.begin(), ias.end(), s.action), ias.end()) << s.action;
      EXPECT_NE(s.action, "sit_down") << "no chairs in a crowd";
      previous_last = s.last;
      walks = walks || s.action == "walk";
      actions.insert(s.action);
    }
    EXPECT_TRUE(walks) << p.actor << " never walks across";
  }
  EXPECT_GE(actions.size(), 8u) << "the people perform different actions";
}

TEST(Crowd, SameSpecSameFrames)
{
  const SampleSpec spec = scene(2, 5, 4.0);
  const CrowdRenderer a(spec), b(spec);
  ASSERT_EQ(a.frames(), 120);
  FrameImages ia, ib;
  a.renderImages(77, ia);
  b.renderImages(77, ib);
  EXPECT_EQ(ia.mask, ib.mask);
  EXPECT_EQ(ia.rgb, ib.rgb);
  EXPECT_THROW(a.renderImages(120, ia), std::out_of_range);
}

TEST(Crowd, OnePersonAloneIsTheSameSceneWithoutTheOthers)
{
  const CrowdRenderer crowd(scene(3, 1, 20.0));
  FrameImages everyone, alone;
  int compared = 0;
  for (int i = 0; i < crowd.frames(); i += 131)
  {
    crowd.renderImages(i, everyone);
    for (const CrowdTruth& t : crowd.truth(i, everyone))
    {
      if (!t.counted)
        continue;
      crowd.renderImages(i, alone, t.mask_id);
      int own_everyone = 0, own_alone = 0, unmasked_equal = 0, unmasked = 0;
      for (size_t p = 0; p < alone.mask.size(); ++p)
      {
        ASSERT_TRUE(alone.mask[p] == 0 || alone.mask[p] == t.mask_id) << "frame " << i << ": another person drawn";
        own_everyone += everyone.mask[p] == t.mask_id;
        own_alone += alone.mask[p] == t.mask_id;
        if (everyone.mask[p] == 0 && alone.mask[p] == 0)
        {
          ++unmasked;
          const bool both_nan = std::isnan(everyone.depth[p]) && std::isnan(alone.depth[p]);
          unmasked_equal += both_nan || everyone.depth[p] == alone.depth[p];
        }
      }
      // Alone, nobody hides them: at least what was seen of them with the others, and the room
      // around is the same room (the same noise, the same pixels; shadows of the others aside).
      EXPECT_GE(own_alone, own_everyone) << "frame " << i << " person " << int(t.mask_id);
      EXPECT_GT(own_alone, 0);
      EXPECT_GT(double(unmasked_equal), 0.9 * unmasked) << "frame " << i;
      ++compared;
    }
  }
  EXPECT_GE(compared, 3);
  EXPECT_THROW(crowd.renderImages(0, alone, 9), std::invalid_argument) << "nobody has mask id 9";
}
