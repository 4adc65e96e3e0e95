/**
 * @file linear_classifier.h
 * @brief The default recognizer's classifier: L2-regularised logistic regression, one model per
 *        label against the rest, trained with liblinear; a probability per label.
 *
 * Training uses liblinear (Debian's liblinear-dev). A trained classifier is only its weights, so
 * classifying is a matrix-vector product here, without liblinear: inputs are standardised with
 * the training set's column means and overall spread, and each label's score is s = w.x + b.
 *
 * The probability of a label: calibrated (temperature T > 0, fitted by fitTemperature on answers
 * the classifier did not train on), the softmax of s / T; uncalibrated (T = 0, as in model files
 * before format 5), 1 / (1 + exp(-s)) divided by the sum over labels, as liblinear's
 * predict_probability does.
 */
#pragma once

#include <action_flow/action_classifier.h>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace action_flow
{
/**
 * @brief Rows to train linear classifiers on many subsets of (model selection): the rows and
 *        their Gram matrix, computed once. LinearClassifier::train on a subset of them solves the
 *        same problem as on those rows alone, in their span, from the Gram matrix: the long rows
 *        are read again only to write the final weights.
 */
class GramRows
{
public:
  /** @throws std::invalid_argument on non-finite values */
  explicit GramRows(Eigen::MatrixXf x);
  Eigen::Index rows() const { return x_.rows(); }
  const Eigen::MatrixXf& x() const { return x_; }
  /** The inner products of the rows less their mean (subsets centre on their own means). */
  const Eigen::MatrixXd& gram() const { return gram_; }

private:
  Eigen::MatrixXf x_;
  Eigen::MatrixXd gram_;
};

class LinearClassifier
{
public:
  LinearClassifier() = default;
  /** @brief From stored parts; @throws std::invalid_argument if their sizes disagree. */
  LinearClassifier(std::vector<std::string> classes, Eigen::MatrixXf weights, Eigen::VectorXf bias,
                   Eigen::VectorXf mean, Eigen::VectorXf scale, double temperature = 0.0);

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
  /** @brief The same on rows @p rows of @p g (one label each), in their span. */
  static std::vector<LinearClassifier> train(const GramRows& g, const std::vector<Eigen::Index>& rows,
                                             const std::vector<std::string>& labels, const std::vector<double>& cs);
  /**
   * @brief The scores (queries x classes, one matrix per C) that train(g, rows, labels, cs) would
   *        give rows @p queries of @p g, without writing its weights (held-out answers for model
   *        selection). @p classes receives the labels in the scores' column order.
   */
  static std::vector<Eigen::MatrixXf> heldOutScores(const GramRows& g, const std::vector<Eigen::Index>& rows,
                                                    const std::vector<std::string>& labels,
                                                    const std::vector<Eigen::Index>& queries,
                                                    const std::vector<double>& cs, std::vector<std::string>& classes);

  /**
   * @brief The most probable label. Classification::confidence is its probability, margin the
   *        difference to the next label's, distance 1 - confidence.
   * @throws std::invalid_argument if @p query has the wrong length or is not finite
   */
  Classification classify(const Eigen::VectorXf& query) const;
  /** @brief The probability of each of classes(), in that order. */
  Eigen::VectorXf probabilities(const Eigen::VectorXf& query) const;
  /** @brief Each label's score w.x + b, in the order of classes(). */
  Eigen::VectorXf scores(const Eigen::VectorXf& query) const;
  /** @brief The same classifier with its probabilities the softmax of the scores / @p temperature
   *         (0: uncalibrated). @throws std::invalid_argument if @p temperature < 0 or not finite */
  LinearClassifier calibrated(double temperature) const;

  bool empty() const { return classes_.empty(); }
  int dimension() const { return static_cast<int>(mean_.size()); }
  const std::vector<std::string>& classes() const { return classes_; }
  const Eigen::MatrixXf& weights() const { return weights_; }  ///< classes x dimension
  const Eigen::VectorXf& bias() const { return bias_; }
  const Eigen::VectorXf& mean() const { return mean_; }
  const Eigen::VectorXf& scale() const { return scale_; }  ///< multiplies each centred input (1 / the training set's spread)
  double temperature() const { return temperature_; }       ///< 0: uncalibrated

private:
  std::vector<std::string> classes_;
  Eigen::MatrixXf weights_;
  Eigen::VectorXf bias_, mean_, scale_;
  double temperature_ = 0.0;
};

/** @brief The temperatures fitTemperature chooses among: [kMinTemperature, kMaxTemperature]. */
constexpr double kMinTemperature = 0.05, kMaxTemperature = 20.0;

/**
 * @brief The temperature T that makes softmax(scores / T) most likely to give the true labels
 *        (least negative log-likelihood; the likelihood is log-concave in 1 / T, so a golden-section
 *        search over log T finds it), within [kMinTemperature, kMaxTemperature].
 * @param scores one row of label scores per answer
 * @param truth the true label's column per row
 * @throws std::invalid_argument on no rows, a size mismatch, a column out of range or non-finite scores
 */
double fitTemperature(const Eigen::MatrixXf& scores, const std::vector<int>& truth);

}  // namespace action_flow
