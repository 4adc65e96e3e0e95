// What evaluate's reports say of a recognizer variant: its name and parameters, its confusion
// matrix as JSON and as CSV. Shared by the classification protocols (evaluate.cpp, crowd_protocol).
#pragma once

#include "../eval/evaluation.h"
#include <action_flow/action_model.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>

namespace action_flow
{
namespace tools
{
/** A recognizer evaluate knows: its name, its title in tables, its parameters. */
struct RecognizerVariant
{
  std::string name, title;
  RecognitionParams params;
  std::size_t extraction;  // which extracted descriptor set it reads
};

/** The confusion matrix, per-class precision, recall and support, and the reliability bins. */
nlohmann::json confusionJson(const Confusion& c);

/** The confusion matrix as CSV (rows: truth, columns: predicted). */
std::string confusionCsv(const Confusion& c);

}  // namespace tools
}  // namespace action_flow
