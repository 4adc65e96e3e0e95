#include "param_files.h"

#include <yaml-cpp/yaml.h>

#include <map>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
namespace tools
{
namespace
{
// The file's scalars and lists as param_table.h text, by their '/'-joined key.
void flatten(const YAML::Node& node, const std::string& prefix, std::map<std::string, std::string>& out)
{
  if (node.IsMap())
  {
    for (const auto& kv : node)
      flatten(kv.second, prefix + (prefix.empty() ? "" : "/") + kv.first.as<std::string>(), out);
    return;
  }
  if (node.IsSequence())
  {
    std::string text = "[";
    for (std::size_t i = 0; i < node.size(); ++i)
    {
      if (!node[i].IsScalar())
        throw std::invalid_argument(prefix + ": a list of plain values is expected");
      text += (i ? ", " : "") + node[i].as<std::string>();
    }
    out[prefix] = text + "]";
    return;
  }
  out[prefix] = node.IsNull() ? "" : node.as<std::string>();
}

std::string shapesName(Shapes s)
{
  return s == Shapes::Frames ? "frame descriptors" : s == Shapes::Model ? "the model" : "runtime";
}

template <class P>
void table(std::ostringstream& md, const char* title, const char* intro, const P& defaults)
{
  md << "## " << title << "\n\n" << intro << "\n\n| name | type | default | shapes | what it does |\n|---|---|---|---|---|\n";
  for (const ParamEntry& e : paramEntries(defaults))
  {
    std::string type = e.type;
    for (std::size_t i = 0; (i = type.find('|', i)) != std::string::npos; i += 2)
      type.replace(i, 1, "\\|");
    md << "| `" << e.name << "` | " << type << " | `" << (e.value.empty() ? "\"\"" : e.value) << "` | "
       << shapesName(e.shapes) << " | " << e.doc << " |\n";
  }
  md << "\n";
}
}  // namespace

void applyParamFile(const std::string& path, ToolParams& p)
{
  std::map<std::string, std::string> values;
  try
  {
    const YAML::Node root = YAML::LoadFile(path);
    if (!root.IsNull() && !root.IsMap())
      throw std::invalid_argument("expected a map of parameters");
    flatten(root, "", values);
  }
  catch (const YAML::BadFile&)
  {
    throw std::runtime_error(path + ": cannot read the file (missing or unreadable)");
  }
  catch (const std::exception& e)  // YAML::Exception and the checks above
  {
    throw std::runtime_error(path + ": " + e.what());
  }
  for (const auto& kv : values)
  {
    try
    {
      if (!setParam(p.recognition, kv.first, kv.second) && !setParam(p.tracker, kv.first, kv.second) &&
          !setParam(p.policy, kv.first, kv.second))
        throw std::invalid_argument(kv.first + ": not a recognition, tracker or policy parameter "
                                               "(docs/parameters.md lists them)");
    }
    catch (const std::invalid_argument& e)
    {
      throw std::runtime_error(path + ": " + e.what());
    }
  }
}

std::string paramsMarkdown()
{
  std::ostringstream md;
  md << "# Parameters\n\n"
        "Every parameter of the method, as declared once in the code (each struct's `visit()`; "
        "`include/action_flow/param_table.h`). This page is made from that declaration by "
        "`rosrun action_flow train --list-params`, and a test keeps it so. The nodelets read the "
        "parameters under these names from their private namespaces (`config/*.yaml`); `train` and "
        "`evaluate` read the same files with `--config`. *shapes* says what a parameter changes: "
        "*frame descriptors* (part of the descriptor cache's key; the classifier refuses a model "
        "made with another value), *the model* (trained into the model file, which then rules), or "
        "*runtime* (what the classifier does with the labels).\n\n";
  table(md, "Recognition (flow, descriptor and classifier nodelets; `config/recognition.yaml`)",
        "`RecognitionParams`; the defaults are those of the default recognizer, posture_flow.",
        defaultRecognitionParams());
  table(md, "People tracker (tracker nodelet; `config/tracker.yaml`)", "`TrackerParams`.", TrackerParams());
  table(md, "Classifier policy (classifier nodelet; `config/classifier.yaml`)",
        "`PolicyParams`. `config/classifier.yaml` sets the online values that `evaluate --protocol online` "
        "chose; the nodelet also reads `model`, `end_of_input_timeout`, `arrow_scale` and `max_arrows` "
        "(docs/nodelets.md).",
        PolicyParams());
  return md.str();
}

}  // namespace tools
}  // namespace action_flow
