/**
 * @file action_model.h
 * @brief The trained model: training sequence descriptors, their labels and people, and every
 *        parameter that shaped them. Saved as one binary file with a format version and checksum.
 */
#pragma once

#include <action_flow/action_classifier.h>
#include <action_flow/flow_estimator.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/pca.h>

#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief Every parameter of the method, from person cloud to sequence descriptor. */
struct RecognitionParams
{
  float voxel_size = 0.02f;  ///< person clouds are voxelised to this (m); the paper's 0.02
  FlowParams flow;
  GridParams grid;
  int frames = 30;           ///< F, frames per sequence descriptor
  bool use_pca = false;      ///< project frame descriptors on a PCA basis
  double pca_variance = 0.99;
  int neighbours = 1;        ///< k of the k-NN classifier (1 = the paper's nearest neighbour)
};

/**
 * @brief Names the parameters in which @p model and @p runtime differ in a way that changes the
 *        descriptors ("flow.k: model 50, runtime 30; ..."); empty when they agree.
 *        The classifier's k may differ: it does not shape the descriptors.
 */
std::string describeDifferences(const RecognitionParams& model, const RecognitionParams& runtime);

/** @brief A model file could not be read, is damaged, or does not fit the runtime. */
class ModelError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** @brief Training set and its parameters. */
struct ActionModel
{
  /** Bumped whenever the layout of the file changes; older files are refused with a clear message. */
  static constexpr std::uint32_t kFormatVersion = 1;

  RecognitionParams params;
  Pca pca;                          ///< empty unless params.use_pca
  Eigen::MatrixXf descriptors;      ///< one sequence descriptor per row
  std::vector<std::string> labels;  ///< action of each row
  std::vector<std::string> persons; ///< who performed each row (for leave-one-person-out)

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

  /** @brief A classifier over the training rows. */
  ActionClassifier classifier() const;
};

}  // namespace action_flow
