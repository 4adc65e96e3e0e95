#include <action_flow/action_classifier.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

namespace action_flow
{
ActionClassifier::ActionClassifier(Eigen::MatrixXf descriptors, std::vector<std::string> labels, int k)
  : descriptors_(std::move(descriptors)), labels_(std::move(labels)), k_(k)
{
  if (descriptors_.rows() == 0 || descriptors_.cols() == 0)
    throw std::invalid_argument("ActionClassifier: the training set is empty");
  if (static_cast<std::size_t>(descriptors_.rows()) != labels_.size())
    throw std::invalid_argument("ActionClassifier: descriptors and labels differ in number");
  if (k_ < 1)
    throw std::invalid_argument("ActionClassifier: k must be at least 1");
  squared_norms_ = descriptors_.rowwise().squaredNorm();
  for (const auto& l : labels_)
  {
    auto it = std::find(classes_.begin(), classes_.end(), l);
    class_of_.push_back(static_cast<int>(it - classes_.begin()));
    if (it == classes_.end())
      classes_.push_back(l);
  }
}

Classification ActionClassifier::classify(const Eigen::VectorXf& query) const
{
  if (query.size() != descriptors_.cols())
    throw std::invalid_argument("ActionClassifier: descriptor length " + std::to_string(query.size()) +
                                " does not match the model (" + std::to_string(descriptors_.cols()) + ")");
  if (!query.allFinite())
    throw std::invalid_argument("ActionClassifier: descriptor contains NaN or inf");
  // One matrix-vector product for all distances.
  const Eigen::VectorXf d2 = ((squared_norms_ - 2.0f * (descriptors_ * query)).array() + query.squaredNorm())
                                 .cwiseMax(0.0f)
                                 .matrix();
  const std::size_t n = labels_.size();
  // Nearest member of each class.
  std::vector<float> best(classes_.size(), std::numeric_limits<float>::infinity());
  std::vector<std::size_t> best_row(classes_.size(), 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const int c = class_of_[i];
    if (d2[i] < best[c])
    {
      best[c] = d2[i];
      best_row[c] = i;
    }
  }
  int winner;
  if (k_ == 1)
  {
    winner = static_cast<int>(std::min_element(best.begin(), best.end()) - best.begin());
  }
  else
  {
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), 0);
    const std::size_t k = std::min<std::size_t>(k_, n);
    std::partial_sort(order.begin(), order.begin() + k, order.end(),
                      [&](std::size_t a, std::size_t b) { return d2[a] < d2[b]; });
    std::vector<int> votes(classes_.size(), 0);
    for (std::size_t i = 0; i < k; ++i)
      ++votes[class_of_[order[i]]];
    winner = 0;
    for (int c = 1; c < static_cast<int>(classes_.size()); ++c)
      if (votes[c] > votes[winner] || (votes[c] == votes[winner] && best[c] < best[winner]))
        winner = c;
  }
  Classification out;
  out.label = classes_[winner];
  out.distance = std::sqrt(best[winner]);
  out.neighbour = best_row[winner];
  float other = std::numeric_limits<float>::infinity();
  for (std::size_t c = 0; c < classes_.size(); ++c)
    if (static_cast<int>(c) != winner)
      other = std::min(other, best[c]);
  out.margin = std::isinf(other) ? other : std::sqrt(other) - out.distance;
  return out;
}

}  // namespace action_flow
