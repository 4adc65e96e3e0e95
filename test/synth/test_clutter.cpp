// The clutter dataset: every scene is what its kind promises (a wall close behind or beside the
// person, the object near them, the person cut by the image border, nobody among the furniture),
// cameras in the stated range, and the ground truth (mask, 3D position) agrees with the render.
#include <action_flow/synth/clutter.h>
#include <action_flow/synth/synth.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

using namespace action_flow;
using namespace action_flow::synth;

namespace
{
constexpr double kDeg = M_PI / 180.0;

// Nearest horizontal distance from the person's torso to the boxes of objects of this kind.
float nearestObject(const ClutterLayout& l, const std::string& kind, int frame)
{
  const Eigen::Vector2f torso = l.joints[size_t(frame)][Joint::Torso].head<2>();
  float best = 1e9f;
  for (const ClutterObject& o : l.objects)
    if (o.kind == kind)
      for (const Box& b : o.boxes)
      {
        // Distance to the box's footprint (in its own frame).
        const Eigen::Vector2f d = Eigen::Rotation2Df(-b.yaw) * (torso - b.center.head<2>());
        const Eigen::Vector2f out = (d.cwiseAbs() - b.half.head<2>()).cwiseMax(0.0f);
        best = std::min(best, out.norm());
      }
  return best;
}
}  // namespace

TEST(Clutter, SamplesCoverEveryKindAndNameThemUniquely)
{
  const auto specs = clutterSamples(4, 1);
  ASSERT_EQ(specs.size(), 4 * clutterKinds().size());
  std::set<std::string> names;
  std::map<std::string, int> per_kind;
  int bending = 0;
  for (const auto& s : specs)
  {
    names.insert(s.name());
    ++per_kind[s.scene];
    EXPECT_EQ(s.dataset, "clutter");
    EXPECT_EQ(s.scene == "furniture", s.person == "none") << s.name();
    bending += s.action == "pick_up";
  }
  EXPECT_EQ(names.size(), specs.size());
  EXPECT_EQ(names.count("wall_01"), 1u);
  for (const auto& k : clutterKinds())
    EXPECT_EQ(per_kind[k], 4) << k;
  EXPECT_GT(bending, 0) << "no scene of a bending person";
  EXPECT_THROW(clutterSamples(0), std::invalid_argument);
  SampleSpec bad = specs[0];
  bad.scene = "kitchen";
  EXPECT_THROW(clutterLayout(bad), std::invalid_argument);
}

TEST(Clutter, EveryKindIsWhatItPromises)
{
  for (const SampleSpec& spec : clutterSamples(6, 3))
  {
    SCOPED_TRACE(spec.name());
    const ClutterLayout l = clutterLayout(spec);
    EXPECT_GE(l.camera.height_above_floor, 0.5 - 1e-9);
    EXPECT_LE(l.camera.height_above_floor, 1.8 + 1e-9);
    EXPECT_GE(l.camera.tilt, -10 * kDeg - 1e-6);
    EXPECT_LE(l.camera.tilt, 20 * kDeg + 1e-6);
    EXPECT_EQ(l.person, spec.scene != "furniture");
    if (!l.person)
    {
      EXPECT_GE(l.objects.size(), 3u);
      continue;
    }
    ASSERT_EQ(int(l.joints.size()), l.frames);
    ASSERT_GT(l.frames, 20);
    const Eigen::Vector3f torso = l.joints[0][Joint::Torso];
    if (spec.scene == "wall" || spec.scene == "door")
    {
      // 0.2-1 m from where the person stands; the torso sways a few centimetres about it.
      EXPECT_GE(distanceToWall(l.room, torso), 0.15f);
      EXPECT_LE(distanceToWall(l.room, torso), 1.05f);
    }
    if (spec.scene == "chair" || spec.scene == "table" || spec.scene == "shelf")
    {
      EXPECT_LT(nearestObject(l, spec.scene, 0), 0.9f);
    }
    if (spec.scene == "door")  // beside them in the wall behind, or its open leaf
    {
      EXPECT_LT(nearestObject(l, spec.scene, 0), 1.3f);
    }
    bool cut = false, head_always = true, whole_always = true;
    for (int f = 0; f < l.frames; ++f)
    {
      const JointsInView v = jointsInView(l.camera, l.joints[size_t(f)], 0.0f);
      cut = cut || v.inside < kJointCount;
      head_always = head_always && v.head_inside;
      whole_always = whole_always && v.inside == kJointCount;
    }
    if (spec.scene == "border")
    {
      EXPECT_TRUE(cut) << "the person is never cut by the image border";
      EXPECT_TRUE(head_always);
    }
    else
      EXPECT_TRUE(whole_always) << "the person leaves the image";
  }
}

TEST(Clutter, RenderedTruthAgreesWithTheLayout)
{
  const auto specs = clutterSamples(1, 1);
  for (const SampleSpec& spec : specs)
  {
    SCOPED_TRACE(spec.name());
    SampleSpec s = spec;
    s.max_frames = 3;
    const SampleRenderer sample(s);
    const ClutterLayout l = clutterLayout(s);
    EXPECT_EQ(sample.bodies(), l.person ? 1 : 0);
    EXPECT_DOUBLE_EQ(sample.camera().height_above_floor, l.camera.height_above_floor);
    Cloud cloud;
    std::vector<std::uint8_t> mask;
    sample.render(1, cloud, &mask);
    ASSERT_EQ(mask.size(), cloud.size());
    int person = 0;
    Eigen::Vector3f mean = Eigen::Vector3f::Zero();
    const Eigen::Isometry3f world = sample.camera().worldFromOptical();
    for (std::size_t i = 0; i < mask.size(); ++i)
      if (mask[i] == 1 && std::isfinite(cloud[i].z))
      {
        ++person;
        mean += world * cloud[i].getVector3fMap();
      }
    if (!l.person)
    {
      EXPECT_EQ(person, 0);
      continue;
    }
    ASSERT_GT(person, 300);
    mean /= float(person);
    // The mask's points lie around the person's 3D position (the torso joint), and on the person.
    EXPECT_LT((mean.head<2>() - sample.worldSkeleton(1)[Joint::Torso].head<2>()).norm(), 0.35f);
    EXPECT_EQ(objectAt(l, 1, sample.worldSkeleton(1)[Joint::Head]), "person");
  }
}

TEST(Clutter, ObjectAtNamesWhatAPointLiesOn)
{
  SampleSpec spec = clutterSamples(1, 1)[1];  // chair_01
  ASSERT_EQ(spec.scene, "chair");
  const ClutterLayout l = clutterLayout(spec);
  const ClutterObject* chair = nullptr;
  for (const auto& o : l.objects)
    if (o.kind == "chair")
      chair = &o;
  ASSERT_NE(chair, nullptr);
  EXPECT_EQ(objectAt(l, -1, chair->boxes[0].center), "chair");
  EXPECT_EQ(objectAt(l, -1, Eigen::Vector3f(l.room.back_wall, 0.0f, 1.5f)), "wall");
  EXPECT_EQ(objectAt(l, -1, Eigen::Vector3f(0.8f, 0.0f, 0.0f)), "floor");
  EXPECT_EQ(objectAt(l, -1, Eigen::Vector3f(0.8f, 0.0f, 2.0f)), "other");
}

TEST(Clutter, SameSpecSameScene)
{
  const SampleSpec spec = clutterSamples(2, 5)[3];
  const ClutterLayout a = clutterLayout(spec), b = clutterLayout(spec);
  EXPECT_EQ(a.camera.tilt, b.camera.tilt);
  ASSERT_EQ(a.room.boxes.size(), b.room.boxes.size());
  for (std::size_t k = 0; k < a.room.boxes.size(); ++k)
    EXPECT_EQ(a.room.boxes[k].center, b.room.boxes[k].center);
  ASSERT_EQ(a.joints.size(), b.joints.size());
  EXPECT_EQ(a.joints.back()[Joint::Head], b.joints.back()[Joint::Head]);
}
