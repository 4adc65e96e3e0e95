// Each parameter declared once (param_table.h): the text forms, the cache key, the model check,
// the --config yaml files and docs/parameters.md all follow that one declaration.
#include <gtest/gtest.h>

#include "../../src/offline/extraction.h"
#include "../../src/offline/param_files.h"

#include <action_flow/param_table.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

using namespace action_flow;
using namespace action_flow::tools;

namespace
{
const std::string kSource = ACTION_FLOW_SOURCE_DIR;

// Another valid text for an entry's type: what "changing the parameter" means in these tests.
std::string otherValue(const ParamEntry& e)
{
  if (e.type == "int")
    return std::to_string(std::stoi(e.value) + 1);
  if (e.type == "float")
    return paramText(std::stod(e.value) * 2.0 + 1.0);
  if (e.type == "bool")
    return e.value == "true" ? "false" : "true";
  if (e.type == "string")
    return e.value + "x";
  if (e.type == "list of strings")
    return "[x]";
  if (e.type == "[x, y, z]")
    return "[9, 9, 9]";
  if (e.type == "[a, b, c, d] or []")
    return e.value == "[]" ? "[0, 0, 1, 1]" : "[]";
  // an enum: "a|b|c"
  std::stringstream names(e.type);
  std::string n;
  while (std::getline(names, n, '|'))
    if (n != e.value)
      return n;
  ADD_FAILURE() << e.name << ": no other value for type " << e.type;
  return e.value;
}

std::string writeFile(const std::string& name, const std::string& text)
{
  const std::string path = ::testing::TempDir() + "action_flow_params_" + name;
  std::ofstream(path) << text;
  return path;
}

std::string readFile(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(ParamText, KnownAnswers)
{
  EXPECT_EQ(paramText(0.3f), "0.3");
  EXPECT_EQ(paramText(0.02f), "0.02");
  EXPECT_EQ(paramText(1.0 / 3.0), "0.3333333333333333");
  EXPECT_EQ(paramText(50), "50");
  EXPECT_EQ(paramText(true), "true");
  EXPECT_EQ(paramText(Recognizer::PostureFlow), "posture_flow");
  EXPECT_EQ(paramText(std::vector<std::string>{ "standing", "sit" }), "[standing, sit]");
  EXPECT_EQ(paramText(std::optional<Eigen::Vector4f>()), "[]");
  EXPECT_EQ(paramText(std::optional<Eigen::Vector4f>(Eigen::Vector4f(0, -1, 0, 1.1f))), "[0, -1, 0, 1.1]");

  int i = 0;
  parseParam("12", i);
  EXPECT_EQ(i, 12);
  EXPECT_THROW(parseParam("12.5", i), std::invalid_argument);
  EXPECT_THROW(parseParam("twelve", i), std::invalid_argument);
  float f = 0;
  parseParam(paramText(0.123456789f), f);
  EXPECT_EQ(f, 0.123456789f);  // the text reads back as the same float
  EXPECT_THROW(parseParam("nan", f), std::invalid_argument);
  bool b = false;
  parseParam("true", b);
  EXPECT_TRUE(b);
  EXPECT_THROW(parseParam("yes please", b), std::invalid_argument);
  Recognizer r = Recognizer::Paper;
  parseParam("posture_flow", r);
  EXPECT_EQ(r, Recognizer::PostureFlow);
  try
  {
    parseParam("posture", r);
    ADD_FAILURE() << "parsed an unknown recognizer";
  }
  catch (const std::invalid_argument& e)
  {
    EXPECT_STREQ(e.what(), "expected paper or posture_flow, got 'posture'");
  }
  std::optional<Eigen::Vector4f> plane;
  parseParam("[0, -1, 0, 1.5]", plane);
  ASSERT_TRUE(plane.has_value());
  EXPECT_EQ((*plane)[3], 1.5f);
  EXPECT_THROW(parseParam("[0, -1, 0]", plane), std::invalid_argument);
  parseParam("[]", plane);
  EXPECT_FALSE(plane.has_value());
  EXPECT_EQ(stableHash(""), "cbf29ce484222325");  // FNV-1a's offset basis: the same in every build
  EXPECT_EQ(stableHash("a"), "af63dc4c8601ec8c");
}

// Every parameter's text sets it back: set(entries(p)) reproduces p, and a changed text shows.
TEST(ParamTable, EveryParameterRoundTripsByName)
{
  RecognitionParams p = defaultRecognitionParams();
  for (const ParamEntry& e : paramEntries(p))
  {
    RecognitionParams q = p;
    ASSERT_TRUE(setParam(q, e.name, otherValue(e))) << e.name;
    const auto changed = paramEntries(q);
    int differing = 0;
    for (std::size_t i = 0; i < changed.size(); ++i)
      differing += changed[i].value != paramEntries(p)[i].value;
    EXPECT_EQ(differing, 1) << e.name << " -> " << otherValue(e);
  }
  EXPECT_FALSE(setParam(p, "flow/no_such_thing", "1"));
  EXPECT_THROW(setParam(p, "flow/k", "many"), std::invalid_argument);
}

// The cache key changes with every parameter that shapes a frame descriptor, recognizer's and
// tracker's alike, and with none of those the model decides (they leave the cached frames valid).
TEST(ParamTable, CacheKeyChangesWithEveryParameterThatShapesFrames)
{
  const RecognitionParams p = defaultRecognitionParams();
  const TrackerParams t;
  const std::string key = paramsFingerprint(p, t);
  int frames = 0, model = 0;
  for (const ParamEntry& e : paramEntries(p))
  {
    RecognitionParams q = p;
    setParam(q, e.name, otherValue(e));
    if (e.shapes == Shapes::Frames)
    {
      ++frames;
      EXPECT_NE(paramsFingerprint(q, t), key) << e.name << " shapes frames but leaves the cache key";
    }
    else
    {
      ++model;
      EXPECT_EQ(paramsFingerprint(q, t), key) << e.name << " is the model's but changes the cache key";
    }
  }
  for (const ParamEntry& e : paramEntries(t))
  {
    TrackerParams u = t;
    setParam(u, e.name, otherValue(e));
    EXPECT_NE(paramsFingerprint(p, u), key) << "tracker " << e.name << " leaves the cache key";
  }
  EXPECT_GE(frames, 16);
  EXPECT_GE(model, 10);
}

// A model refuses a runtime that differs in any parameter that shapes frames, naming it.
TEST(ParamTable, ModelCheckNamesEveryFrameParameter)
{
  const RecognitionParams p = defaultRecognitionParams();
  for (const ParamEntry& e : paramEntries(p))
  {
    RecognitionParams q = p;
    setParam(q, e.name, otherValue(e));
    const std::string diff = describeDifferences(p, q);
    if (e.shapes == Shapes::Frames)
      EXPECT_EQ(diff.rfind(e.name + ": model " + e.value + ", runtime ", 0), 0u) << diff;
    else
      EXPECT_EQ(diff, "") << e.name;
  }
}

// The shipped yaml files hold the declared defaults, so a model trained without --config fits the
// nodelets as launched, and every key in them is a declared parameter.
TEST(ParamFiles, ShippedConfigHoldsTheDeclaredDefaults)
{
  ToolParams loaded;
  applyParamFile(kSource + "/config/recognition.yaml", loaded);
  applyParamFile(kSource + "/config/tracker.yaml", loaded);
  const ToolParams defaults;
  const auto a = paramEntries(loaded.recognition), b = paramEntries(defaults.recognition);
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(a[i].value, b[i].value) << "config/recognition.yaml: " << a[i].name;
  const auto c = paramEntries(loaded.tracker), d = paramEntries(defaults.tracker);
  for (std::size_t i = 0; i < c.size(); ++i)
    EXPECT_EQ(c[i].value, d[i].value) << "config/tracker.yaml: " << c[i].name;
}

// config/online_model.yaml (train --config, the online model) changes only what the model file
// keeps (the pyramid's pooling): a model trained with it fits the nodelets as launched, whose
// frame descriptors follow config/recognition.yaml.
TEST(ParamFiles, OnlineModelConfigChangesOnlyTheModelsOwnParameters)
{
  ToolParams loaded;
  applyParamFile(kSource + "/config/online_model.yaml", loaded);
  const ToolParams defaults;
  const auto a = paramEntries(loaded.recognition), b = paramEntries(defaults.recognition);
  ASSERT_EQ(a.size(), b.size());
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].value != b[i].value)
    {
      ++changed;
      EXPECT_EQ(a[i].shapes, Shapes::Model) << a[i].name << " shapes the frame descriptors";
      EXPECT_EQ(a[i].name.rfind("pyramid/", 0), 0u) << a[i].name;
    }
  EXPECT_GT(changed, 0u) << "the file changes nothing: the online model would be the segmented one";
  EXPECT_EQ(describeDifferences(loaded.recognition, defaults.recognition), "");
  EXPECT_EQ(loaded.recognition.pyramid.problem(), "");
}

TEST(ParamFiles, ValuesAndErrorsNameTheFileAndKey)
{
  ToolParams p;
  applyParamFile(writeFile("good.yaml", "recognizer: paper\nflow:\n  k: 30\n  max_gap: 0.5\n"
                                        "ground: [0, -1, 0, 1.2]\nidle_labels: [standing, sit]\n"),
                 p);
  EXPECT_EQ(p.recognition.recognizer, Recognizer::Paper);
  EXPECT_EQ(p.recognition.flow.k, 30);
  EXPECT_EQ(p.recognition.flow.max_gap, 0.5);
  ASSERT_TRUE(p.tracker.ground.has_value());
  EXPECT_EQ((*p.tracker.ground)[3], 1.2f);
  EXPECT_EQ(p.policy.idle_labels, (std::vector<std::string>{ "standing", "sit" }));

  const auto expectError = [](const std::string& path, const std::string& what) {
    ToolParams q;
    try
    {
      applyParamFile(path, q);
      ADD_FAILURE() << "accepted " << path;
    }
    catch (const std::runtime_error& e)
    {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expectError(writeFile("typo.yaml", "flow:\n  kk: 30\n"), "flow/kk: not a recognition, tracker or policy parameter");
  expectError(writeFile("bad.yaml", "flow:\n  k: lots\n"), "flow/k: expected a finite number, got 'lots'");
  expectError(writeFile("broken.yaml", "flow: [k: 1\n"), "");
  expectError(writeFile("list.yaml", "- 1\n- 2\n"), "expected a map of parameters");
  expectError(::testing::TempDir() + "action_flow_params_missing.yaml", "cannot read the file");
}

// docs/parameters.md is what the declaration says (regenerate: train --list-params > docs/parameters.md).
TEST(ParamFiles, DocsTableIsTheDeclaration)
{
  EXPECT_EQ(readFile(kSource + "/docs/parameters.md"), paramsMarkdown())
      << "docs/parameters.md is stale: rosrun action_flow train --list-params > docs/parameters.md";
}
