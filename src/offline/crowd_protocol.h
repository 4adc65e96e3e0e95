// evaluate --protocol crowd: recognition of several people at once. The same actors' actions in
// crowd scenes of the virtual Kinect, recognised once with everyone in view and once with each
// person rendered alone (the same motion, place and facing), so what several people cost is the
// difference.
#pragma once

#include "sample_sources.h"
#include "variant_report.h"

#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
class Args;
class Options;

/** Adds the crowd protocol's options (--crowd-people, --crowd-seconds; --scenes and --gate are shared). */
void addCrowdOptions(Options& o);

/**
 * "2,3": people counts of crowd scenes, each 2..5. @throws UsageError naming @p option otherwise.
 */
std::vector<int> crowdPeopleList(const std::string& text, const std::string& option);

/**
 * Trains each of @p variants on all of @p samples (the segmented samples of the training people),
 * then recognises every action of the people of --scenes crowd scenes per --crowd-people count
 * (actors who are none of the training people), with everyone in view and with each person alone,
 * and writes OUTPUT/crowd.json, OUTPUT/segments.csv, the confusion matrices and (unless --no-plots)
 * OUTPUT/crowd.png. @p extractions are the descriptor sets the variants read (extraction indices).
 */
int runCrowdProtocol(const Args& args, const std::vector<SampleRef>& samples,
                     const std::vector<RecognitionParams>& extractions, const std::vector<RecognizerVariant>& variants,
                     const std::string& dir);

}  // namespace tools
}  // namespace action_flow
