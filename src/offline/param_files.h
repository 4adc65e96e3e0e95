// The parameters of the offline tools from the same yaml files the nodelets load (config/), and
// their table for the docs: both from the one declaration of each parameter (param_table.h).
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/people_tracker.h>
#include <action_flow/recognition_policy.h>

#include <string>

namespace action_flow
{
namespace tools
{
/** The parameter structs a tool runs with. */
struct ToolParams
{
  RecognitionParams recognition = defaultRecognitionParams();
  TrackerParams tracker;
  PolicyParams policy;
};

/**
 * Applies every key of the yaml file @p path (nested maps joined with '/', as rosparam loads them:
 * flow: {k: 50} is flow/k) to whichever of @p p's structs declares it.
 * @throws std::runtime_error "<path>: <key>: <what was wrong>" for an unreadable or malformed file,
 *         a key no struct declares, or a value that does not parse
 */
void applyParamFile(const std::string& path, ToolParams& p);

/** Markdown tables of every parameter (name, type, default, what it shapes, doc): docs/parameters.md. */
std::string paramsMarkdown();

}  // namespace tools
}  // namespace action_flow
