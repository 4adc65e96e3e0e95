/**
 * @file action_classifier.h
 * @brief Nearest-neighbour classification of sequence descriptors.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief The answer for one sequence. */
struct Classification
{
  std::string label;
  /** Euclidean distance to the nearest training sequence of that label. */
  float distance = 0.0f;
  /**
   * Distance to the nearest training sequence of any other label minus @ref distance: how
   * clearly this label won (negative is possible with k > 1). Infinity if the training set has
   * only one label.
   */
  float margin = 0.0f;
  /** Row of the nearest training sequence of that label. */
  std::size_t neighbour = 0;
};

/**
 * @brief 1-nearest-neighbour (or k-NN majority) by Euclidean distance over sequence descriptors.
 */
class ActionClassifier
{
public:
  /**
   * @param descriptors one training sequence descriptor per row
   * @param labels their labels
   * @param k neighbours that vote; 1 is the paper's nearest neighbour. Ties go to the label
   *        whose nearest member is closest.
   * @throws std::invalid_argument on an empty set, a size mismatch or k < 1
   */
  ActionClassifier(Eigen::MatrixXf descriptors, std::vector<std::string> labels, int k = 1);

  /** @throws std::invalid_argument if @p query has the wrong length or is not finite. */
  Classification classify(const Eigen::VectorXf& query) const;

  std::size_t size() const { return labels_.size(); }
  int dimension() const { return static_cast<int>(descriptors_.cols()); }
  const std::vector<std::string>& classes() const { return classes_; }

private:
  Eigen::MatrixXf descriptors_;     // rows = training sequences
  Eigen::VectorXf squared_norms_;   // |d_i|^2, precomputed for |q - d|^2 = |q|^2 - 2 q.d + |d|^2
  std::vector<std::string> labels_;
  std::vector<int> class_of_;       // index into classes_ per training row
  std::vector<std::string> classes_;
  int k_;
};

}  // namespace action_flow
