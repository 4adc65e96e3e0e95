/**
 * @file action_classifier.h
 * @brief Nearest-neighbour classification of sequence descriptors.
 */
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <utility>
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
  /**
   * How sure the classifier is, in [0,1], for a threshold: the label's probability from the
   * linear classifier; from nearest neighbours margin / (distance + margin) (0 when margin <= 0,
   * 1 with a one-label training set).
   */
  float confidence = 0.0f;
};

/**
 * @brief 1-nearest-neighbour (or k-NN majority) by Euclidean distance over sequence descriptors.
 *
 * Exact, and faster than one pass over the whole training matrix: the columns are reordered by
 * decreasing variance over the training set, the distance over the leading columns (the head) is
 * computed for every row first, and it is a lower bound of the full distance; a row is completed
 * only while that bound can still change the answer (with k = 1: beat the nearest row, or the
 * nearest row of another label, which sets the margin; with k > 1: the nearest row of its label or
 * the k-th nearest). Where the head holds most of the variance, few rows are completed and a
 * query reads a fraction of the training set (test_core checks the answers against completing
 * every row; `bench` times both).
 */
class ActionClassifier
{
public:
  /**
   * @param descriptors one training sequence descriptor per row
   * @param labels their labels
   * @param k neighbours that vote; 1 is the paper's nearest neighbour. Ties go to the label
   *        whose nearest member is closest.
   * @throws std::invalid_argument on an empty set, a size mismatch, non-finite values or k < 1
   */
  ActionClassifier(const Eigen::MatrixXf& descriptors, std::vector<std::string> labels, int k = 1);

  /** @throws std::invalid_argument if @p query has the wrong length or is not finite. */
  Classification classify(const Eigen::VectorXf& query) const;

  /** @brief The same answer by a plain scan of every full row: the reference for tests and `bench`. */
  Classification classifyBruteForce(const Eigen::VectorXf& query) const;

  std::size_t size() const { return labels_.size(); }
  int dimension() const { return static_cast<int>(columns_.size()); }
  const std::vector<std::string>& classes() const { return classes_; }

  /** @brief Rows completed by the last classify() on this thread (for the benchmark). */
  static std::size_t lastCompletedRows();

private:
  using RowMajorMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::VectorXf reorder(const Eigen::VectorXf& query) const;
  Eigen::ArrayXf headDistances(const Eigen::VectorXf& reordered_query) const;
  Classification decide(const std::vector<float>& best, const std::vector<std::size_t>& best_row,
                        const std::vector<std::pair<float, std::size_t>>& nearest) const;

  std::vector<Eigen::Index> columns_;  // column order: decreasing variance over the training set
  Eigen::MatrixXf head_;               // rows x leading columns, column-major: the first pass streams it
  RowMajorMatrix tail_;                // rows x remaining columns, row-major: a row is completed in one stream
  std::vector<std::string> labels_;
  std::vector<int> class_of_;          // index into classes_ per training row
  std::vector<std::string> classes_;
  int k_;
};

}  // namespace action_flow
