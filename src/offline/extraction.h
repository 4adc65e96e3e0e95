// Frame descriptors of many samples: cached per sample and variant, computed in parallel with
// progress, stoppable with Ctrl-C without leaving a damaged cache file.
#pragma once

#include "sample_sources.h"

#include "../eval/evaluation.h"
#include <action_flow/people_tracker.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
namespace tools
{
/** A name for the parameters that shape frame descriptors, for cache paths. */
std::string paramsFingerprint(const RecognitionParams& p, const TrackerParams& t);

/**
 * Frame descriptors of every sample for every variant: result[variant][sample]. Reads
 * <cache_dir>/<fingerprint>/<sample key>.frames when present and valid, otherwise runs the
 * tracker and pipelines (all variants of a sample in one pass) and writes the cache.
 * Prints progress on stderr. @throws std::runtime_error("interrupted") after Ctrl-C.
 */
std::vector<std::vector<SampleFrames>> extractAll(const std::vector<SampleRef>& samples,
                                                  const std::vector<RecognitionParams>& variants,
                                                  const TrackerParams& tracker, const std::string& cache_dir, int jobs);

/**
 * Refuses samples in which no person was tracked long enough for one frame descriptor (nothing to
 * learn from but zeros): @throws DatasetError naming the first such sample and how many there are,
 * unless @p allow_empty, when they stay as still frames.
 */
void refuseEmptySamples(const std::vector<SampleRef>& samples, const std::vector<SampleFrames>& frames,
                        bool allow_empty);

/** Installs a SIGINT/SIGTERM handler that asks extractAll to stop after the samples in flight. */
void installInterruptHandler();

/**
 * Creates the tools' output folder @p dir and its parents, before any long work.
 * @throws UsageError naming --output and @p dir when it cannot be made or written to
 */
void makeOutputDir(const std::string& dir);

/** Parses the common command-line value "a,b,c". */
std::vector<std::string> splitList(const std::string& s);

}  // namespace tools
}  // namespace action_flow
