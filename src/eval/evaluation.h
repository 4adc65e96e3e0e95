/**
 * @file evaluation.h
 * @brief What training and evaluation need besides the method itself: the dataset index, the
 *        protocols' train/test splits, the per-sample frame descriptor cache, and accuracy
 *        figures. ROS-free.
 */
#pragma once

#include <action_flow/action_model.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief A dataset index or cache file is malformed; the message names the file and line. */
class DatasetError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** @brief One line of a dataset index (CSV with a header naming at least path, person, action and repetition; other columns are ignored). */
struct IndexEntry
{
  std::string path;    ///< the sample's bag, resolved against the index's folder
  std::string person;
  std::string action;
  int repetition = 0;
  int line = 0;        ///< line in the index file, for messages
};

/**
 * @brief Reads a dataset index.
 * @param known_actions when not empty, an action outside it is an error
 * @throws DatasetError naming the file and line: missing or unreadable index, missing header
 *         column, empty index, wrong field count, empty or non-numeric field, unknown action,
 *         missing sample file, or a duplicate sample
 */
std::vector<IndexEntry> readIndex(const std::string& path, const std::vector<std::string>& known_actions = {});

/** @brief A train/test split: indices into the sample list. */
struct Fold
{
  std::string name;  ///< e.g. "test person p03"
  std::vector<std::size_t> train, test;
};

/** @brief One fold per person: that person's samples are the test set, everyone else's the training set. */
std::vector<Fold> leaveOnePersonOut(const std::vector<std::string>& persons);

/**
 * @brief One fold: samples of @p train_persons train, all others test (MSR Action3D's
 *        cross-subject protocol trains on subjects 1,3,5,7,9).
 */
Fold crossSubject(const std::vector<std::string>& persons, const std::vector<std::string>& train_persons);

/** @brief Frame descriptors of one sample (one row per frame with flow) and their stamps. */
struct SampleFrames
{
  Eigen::MatrixXf descriptors;
  std::vector<double> stamps;
  /** The track of each row, when the rows are every track's (a stream); empty: one performer. */
  std::vector<std::uint32_t> tracks;
};

/** @brief Writes @p frames to @p path atomically (temporary name, then rename); the tracks, if any, after the rows. */
void saveSampleFrames(const std::string& path, const SampleFrames& frames);
/** @brief Reads a cache file; returns false if it is absent, @throws DatasetError if it is damaged. */
bool loadSampleFrames(const std::string& path, SampleFrames& frames);

/**
 * @brief How well a classifier's confidence says how often it is right (a reliability diagram): its
 *        answers dealt into kBins equal bins of confidence, each with its mean confidence and the
 *        share of it that was right. A calibrated confidence has the two equal in every bin.
 */
struct Reliability
{
  static constexpr int kBins = 10;
  std::vector<int> count = std::vector<int>(kBins, 0);
  std::vector<int> correct = std::vector<int>(kBins, 0);
  std::vector<double> confidence_sum = std::vector<double>(kBins, 0.0);

  /** @brief One answer; a confidence outside [0, 1] is clamped into it. */
  void add(float confidence, bool right);
  int total() const;
  /** @brief Mean confidence of the answers (0 without any). */
  double meanConfidence() const;
  /**
   * @brief The expected calibration error: over the bins, weighted by their answers, the mean
   *        |share right - mean confidence| (0 without any answers).
   */
  double expectedCalibrationError() const;
};

/** @brief Confusion matrix and the figures derived from it. */
struct Confusion
{
  std::vector<std::string> labels;              ///< class names, rows = truth, columns = prediction
  std::vector<std::vector<int>> counts;
  Reliability reliability;  ///< of the answers added with a confidence

  explicit Confusion(std::vector<std::string> labels);
  /** @throws std::invalid_argument for a label not in labels */
  void add(const std::string& truth, const std::string& predicted);
  /** @brief The same, and the answer's confidence into reliability. */
  void add(const std::string& truth, const std::string& predicted, float confidence);
  int total() const;
  double accuracy() const;
  /** @brief Per class; 0 where the class was never predicted (precision) or never present (recall). */
  std::vector<double> precision() const;
  std::vector<double> recall() const;
  /** @brief Samples of each class (row sums). */
  std::vector<int> support() const;
};

/** @brief A sample as the experiments see it: who, what, and its cached frame descriptors. */
struct LabelledSample
{
  std::string person;
  std::string action;
  const SampleFrames* frames = nullptr;
  /** A training copy (the same motion rendered again, synth::SampleSpec::copy): it trains, and it is
   *  never tested nor a held-out query of the inner cross-validation. */
  bool copy = false;
};

/**
 * @brief Builds a model from the samples at @p rows: PCA fitted on their frame descriptors when
 *        params.use_pca (or @p fitted when given), then one sequence descriptor per sample. A sample without any frame
 *        descriptor (no flow was ever found) counts as one still frame: all zeros.
 *        posture_flow: with pyramid.mirror On each sample is added mirrored too; with the linear
 *        classifier, pyramid.c = 0, mirror Choose and flow Choose are decided by cross-validation
 *        (chooseLinear) on these rows alone, and the choice is recorded in the model's parameters;
 *        the same cross-validation (also when nothing is left to choose) fits the classifier's
 *        temperature, so that its probabilities are calibrated (uncalibrated with one person).
 * @param memo if given, cross-validations answered before on the same samples are not run again
 *        (the same model results)
 * @throws std::invalid_argument if @p rows is empty
 */
class SelectionMemo;
ActionModel trainModel(const std::vector<LabelledSample>& samples, const std::vector<std::size_t>& rows,
                       const RecognitionParams& params, const Pca* fitted = nullptr, SelectionMemo* memo = nullptr);

/** @brief The values of the linear classifier's C that chooseLinear tries. */
const std::vector<double>& linearCandidates();

/** @brief What chooseLinear chose. */
struct LinearChoice
{
  double c = 0.0;
  bool mirror = false;  ///< train with the mirrored copies too
  double score = -1.0;  ///< its mean accuracy over the held-out groups (-1: not cross-validated)
  double temperature = 0.0;  ///< fitted on its held-out answers (fitTemperature; 0: not cross-validated)
};

/**
 * @brief Model-selection answers kept for the variants of one evaluation (thread-safe). trainModel
 *        asks one cross-validation per flow encoding and posture it may choose; a variant that
 *        chooses posture (posture_flow_choose_posture) asks the very questions that the variants
 *        with posture on and off asked on the same rows, and with a memo each is answered once.
 *        A question is its rows (each one's person, action and frame descriptors, by address: a memo
 *        serves samples whose frames stay in place), every recognition parameter, and the options
 *        of C and mirroring.
 */
class SelectionMemo
{
public:
  /** @brief The answer to @p question, if it was given before. */
  std::optional<LinearChoice> find(const std::string& question) const;
  void add(const std::string& question, const LinearChoice& answer);
  /** @brief How many questions find() answered. */
  int hits() const;

private:
  mutable std::mutex mutex_;
  std::map<std::string, LinearChoice> answers_;
  mutable int hits_ = 0;
};

/**
 * @brief Chooses the linear classifier's C (of @p c_options), and whether to add the mirrored
 *        copies (of @p mirror_options; @p mirrored holds row i mirrored), by cross-validation over
 *        people: the people of @p persons are dealt into @p inner_folds groups, each group is held
 *        out in turn (its original rows are the queries), and the setting with the best mean
 *        accuracy wins (on a tie the earlier option). The temperature that calibrates the
 *        probabilities is fitted on the held-out answers of the setting chosen. Only the rows given
 *        are seen, so called on a fold's training set it never sees a test person.
 * @param queries if given, the rows that may be held-out queries (false: a training copy, which
 *        trains when its person is not held out and is never asked)
 */
LinearChoice chooseLinear(const Eigen::MatrixXf& x, const Eigen::MatrixXf* mirrored,
                          const std::vector<std::string>& labels, const std::vector<std::string>& persons,
                          const std::vector<bool>& mirror_options, const std::vector<double>& c_options,
                          int inner_folds = 3, const std::vector<bool>* queries = nullptr);

/** @brief The PCA basis trainModel fits on the frame descriptors of @p rows. */
Pca fitPca(const std::vector<LabelledSample>& samples, const std::vector<std::size_t>& rows, double variance);

/** @brief The sequence descriptor of one sample under @p model (zeros for a sample without frames). */
Eigen::VectorXf sequenceOf(const LabelledSample& sample, const ActionModel& model);

/**
 * @brief Trains on each fold's training samples and classifies its test samples.
 * @param fold_accuracy if given, receives each fold's accuracy
 * @param fold_pcas if given and params.use_pca: the fold's PCA bases, fitted on the first call
 *        (empty vector) and reused after, since the basis does not depend on F
 * @param jobs folds trained at once (threads)
 * @param fold_choices if given, receives each tested fold's model's pyramid parameters: what its
 *        cross-validation chose (C, mirror, posture, flow encoding)
 * @param memo if given, model-selection answers shared with other calls on the same samples
 * @throws std::invalid_argument if a fold's training set contains a person of its test set, or if
 *         it tests a training copy (LabelledSample::copy)
 */
Confusion runFolds(const std::vector<LabelledSample>& samples, const std::vector<Fold>& folds,
                   const RecognitionParams& params, std::vector<double>* fold_accuracy = nullptr,
                   std::vector<Pca>* fold_pcas = nullptr, int jobs = 1,
                   std::vector<PyramidParams>* fold_choices = nullptr, SelectionMemo* memo = nullptr);

/** @brief Sorted, de-duplicated copy. */
std::vector<std::string> uniqueSorted(std::vector<std::string> v);

}  // namespace action_flow
