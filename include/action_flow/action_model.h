/**
 * @file action_model.h
 * @brief The trained model: training sequence descriptors, their labels and people, and every
 *        parameter that shaped them. Saved as one binary file with a format version and checksum.
 */
#pragma once

#include <action_flow/action_classifier.h>
#include <action_flow/flow_estimator.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/linear_classifier.h>
#include <action_flow/pca.h>
#include <action_flow/temporal_pyramid.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief Which recognizer turns flow into labels. */
enum class Recognizer
{
  Paper,       ///< the paper's: SUMFLOW/MEANFLOW frames, F of them concatenated (PCA optional), k-NN
  PostureFlow  ///< the default: posture-and-flow frames, a temporal pyramid, a linear classifier
};
template <>
struct EnumNames<Recognizer>
{
  static constexpr const char* names[] = { "paper", "posture_flow" };
};
/** "paper" or "posture_flow". */
std::string toString(Recognizer r);
/** @throws std::invalid_argument for any other name. */
Recognizer recognizerFromString(const std::string& name);

/**
 * @brief Every parameter of the method, from person cloud to sequence descriptor (declared in
 *        visit(); param_table.h). The person clouds' voxel size is the tracker's
 *        (TrackerParams::person_voxel_size, the paper's 0.02 m), declared there only. The struct's defaults are the paper's method;
 *        defaultRecognitionParams() selects the default recognizer, posture_flow.
 */
struct RecognitionParams
{
  Recognizer recognizer = Recognizer::Paper;
  FlowParams flow;
  GridParams grid;           ///< the grid of both recognizers (aggregation: the paper's only)
  int frames = 30;           ///< paper: F, frames per sequence descriptor
  bool use_pca = false;      ///< paper: project frame descriptors on a PCA basis
  double pca_variance = 0.99;
  int neighbours = 1;        ///< paper (and posture_flow with classifier nn): k of the k-NN classifier
  PyramidParams pyramid;     ///< posture_flow: the parts after the frame descriptor

  template <class Self, class V>
  static void visit(Self& p, V&& v)
  {
    v("recognizer", p.recognizer,
      "posture_flow (posture and flow, temporal pyramid, linear classifier) or paper (Munaro et al.)",
      Shapes::Frames);
    FlowParams::visit(p.flow, v);
    GridParams::visit(p.grid, v);
    v("frames", p.frames, "paper: F, frames per sequence descriptor", Shapes::Model);
    v("use_pca", p.use_pca, "paper: project frame descriptors on a PCA basis", Shapes::Model);
    v("pca_variance", p.pca_variance, "paper: the share of variance the PCA basis keeps", Shapes::Model);
    v("neighbours", p.neighbours, "k of the k-NN classifier (paper, and posture_flow with nn)", Shapes::Model);
    PyramidParams::visit(p.pyramid, v);
  }
};

/** @brief The default recognizer's parameters (posture_flow, every part on). */
RecognitionParams defaultRecognitionParams();

/** @brief Length of one frame descriptor under @p p: 3 per cube (paper) or the posture-and-flow layout. */
int frameDescriptorLength(const RecognitionParams& p);

/**
 * @brief The frame descriptor of a person under @p p: GridDescriptor (paper, from the flow alone)
 *        or PostureFlowDescriptor (from the person's cloud and flow).
 */
Eigen::VectorXf frameDescriptor(const RecognitionParams& p, const Cloud& cloud, const FlowVectors& flow,
                                const PersonFrame& where);

/**
 * @brief Names the parameters that shape the frame descriptors (Shapes::Frames) in which @p model
 *        and @p runtime differ ("flow/k: model 50, runtime 30; ..."); empty when they agree. The
 *        others (the classifier's k, the pyramid's parts) are the model's to decide.
 */
std::string describeDifferences(const RecognitionParams& model, const RecognitionParams& runtime);

/** @brief A model file could not be read, is damaged, or does not fit the runtime. */
class ModelError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/**
 * @brief A model's classifier, whichever it is: k-NN over the training sequences (ActionClassifier)
 *        or the linear classifier.
 */
class SequenceClassifier
{
public:
  explicit SequenceClassifier(ActionClassifier nearest) : nearest_(std::move(nearest)) {}
  explicit SequenceClassifier(LinearClassifier linear) : linear_(std::move(linear)) {}
  /** @throws std::invalid_argument if @p sequence has the wrong length or is not finite. */
  Classification classify(const Eigen::VectorXf& sequence) const
  {
    return nearest_ ? nearest_->classify(sequence) : linear_.classify(sequence);
  }
  const std::vector<std::string>& classes() const { return nearest_ ? nearest_->classes() : linear_.classes(); }

private:
  std::optional<ActionClassifier> nearest_;
  LinearClassifier linear_;
};

/** @brief Training set and its parameters. */
struct ActionModel
{
  /**
   * Bumped whenever the layout of the file changes; other versions are refused with a clear
   * message. Version 4 stores the parameters by name (param_table.h), so adding one no longer
   * changes the layout; files of versions 1-3 must be retrained. Version 5 adds the linear
   * classifier's temperature; version 4 files still load, uncalibrated. Version 6 changes a
   * default, not the layout: the temporal pyramid's maxima (pyramid/max_pooling) are on, and
   * files of versions 4 and 5, which do not name them, load with them off, as they were trained.
   * Version 7 likewise turns on the pyramid's Fourier magnitudes (pyramid/fourier); older files
   * load with none.
   */
  static constexpr std::uint32_t kFormatVersion = 7;
  static constexpr std::uint32_t kOldestReadableVersion = 4;

  RecognitionParams params;
  Pca pca;                          ///< empty unless params.use_pca
  Eigen::MatrixXf descriptors;      ///< one sequence descriptor per row
  std::vector<std::string> labels;  ///< action of each row
  std::vector<std::string> persons; ///< who performed each row (for leave-one-person-out)
  LinearClassifier linear;          ///< posture_flow with the linear classifier: its weights

  /**
   * @brief Writes the model to @p path atomically (a temporary file renamed into place).
   * @throws ModelError naming the file if it cannot be written or the model is inconsistent
   */
  void save(const std::string& path) const;

  /**
   * @brief Reads a model.
   * @throws ModelError naming the file and the fault: missing, not a model, wrong version,
   *         truncated, checksum mismatch, inconsistent sizes
   */
  static ActionModel load(const std::string& path);

  /** @throws ModelError naming @p path and the differing parameters if they do not agree. */
  void checkCompatible(const RecognitionParams& runtime, const std::string& path) const;

  /** @brief The sequence descriptor of a person's frame descriptors (in time order) under this model. */
  Eigen::VectorXf sequence(const std::vector<Eigen::VectorXf>& frames, const std::vector<double>& stamps) const;
  /** @brief Length of that sequence descriptor. */
  Eigen::Index sequenceLength() const;
  /** @brief The model's classifier: k-NN over the training rows, or the linear classifier. */
  SequenceClassifier classifier() const;
};

}  // namespace action_flow
