/**
 * @file linear_classifier.h
 * @brief The default recognizer's classifier: L2-regularised logistic regression, one model per
 *        label against the rest, trained with liblinear; a probability per label.
 *
 * Training uses liblinear (Debian's liblinear-dev). A trained classifier is only its weights, so
 * classifying is a matrix-vector product here, without liblinear: inputs are standardised with
 * the training set's column means and overall spread, each label's score w.x + b becomes 1 / (1 + exp(-score)),
 * and the scores are divided by their sum, exactly as liblinear's predict_probability does.
 */
#pragma once

#include <action_flow/action_classifier.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace action_flow
{
class LinearClassifier
{
public:
  LinearClassifier() = default;
  /** @brief From stored parts; @throws std::invalid_argument if their sizes disagree. */
  LinearClassifier(std::vector<std::string> classes, Eigen::MatrixXf weights, Eigen::VectorXf bias,
                   Eigen::VectorXf mean, Eigen::VectorXf scale);

  /**
   * @brief Trains on one descriptor per row of @p x.
   * @param c the regularisation: larger fits the training set more closely
   * @param in_span with fewer rows than columns, solve in the rows' span (exact, and far faster);
   *        false solves over all columns (the reference for the test)
   * @throws std::invalid_argument on an empty set, a size mismatch, non-finite values, c <= 0 or
   *         fewer than 2 labels
   */
  static LinearClassifier train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels, double c,
                                bool in_span = true);
  /** @brief The same for each of @p cs, sharing the standardisation and the span (for model selection). */
  static std::vector<LinearClassifier> train(const Eigen::MatrixXf& x, const std::vector<std::string>& labels,
                                             const std::vector<double>& cs, bool in_span = true);

  /**
   * @brief The most probable label. Classification::confidence is its probability, margin the
   *        difference to the next label's, distance 1 - confidence.
   * @throws std::invalid_argument if @p query has the wrong length or is not finite
   */
  Classification classify(const Eigen::VectorXf& query) const;
  /** @brief The probability of each of classes(), in that order. */
  Eigen::VectorXf probabilities(const Eigen::VectorXf& query) const;

  bool empty() const { return classes_.empty(); }
  int dimension() const { return static_cast<int>(mean_.size()); }
  const std::vector<std::string>& classes() const { return classes_; }
  const Eigen::MatrixXf& weights() const { return weights_; }  ///< classes x dimension
  const Eigen::VectorXf& bias() const { return bias_; }
  const Eigen::VectorXf& mean() const { return mean_; }
  const Eigen::VectorXf& scale() const { return scale_; }  ///< multiplies each centred input (1 / the training set's spread)

private:
  std::vector<std::string> classes_;
  Eigen::MatrixXf weights_;
  Eigen::VectorXf bias_, mean_, scale_;
};

}  // namespace action_flow
