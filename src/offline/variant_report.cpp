// What evaluate's reports say of a recognizer variant (variant_report.h).
#include "variant_report.h"

namespace action_flow
{
namespace tools
{
using json = nlohmann::json;

json confusionJson(const Confusion& c)
{
  json per_class = json::object();
  const auto p = c.precision(), r = c.recall();
  const auto s = c.support();
  for (std::size_t i = 0; i < c.labels.size(); ++i)
    per_class[c.labels[i]] = { { "precision", p[i] }, { "recall", r[i] }, { "support", s[i] } };
  const Reliability& rel = c.reliability;
  json bins = json::array();
  for (int b = 0; b < Reliability::kBins; ++b)
    bins.push_back({ { "count", rel.count[b] },
                     { "correct", rel.correct[b] },
                     { "confidence", rel.count[b] ? rel.confidence_sum[b] / rel.count[b] : 0.0 } });
  return { { "labels", c.labels },
           { "matrix", c.counts },
           { "per_class", per_class },
           { "reliability",
             { { "answers", rel.total() },
               { "mean_confidence", rel.meanConfidence() },
               { "expected_calibration_error", rel.expectedCalibrationError() },
               { "bins", bins } } } };
}

std::string confusionCsv(const Confusion& c)
{
  std::string out = "truth\\predicted";
  for (const auto& l : c.labels)
    out += "," + l;
  out += "\n";
  for (std::size_t i = 0; i < c.labels.size(); ++i)
  {
    out += c.labels[i];
    for (int n : c.counts[i])
      out += "," + std::to_string(n);
    out += "\n";
  }
  return out;
}

}  // namespace tools
}  // namespace action_flow
