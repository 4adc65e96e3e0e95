#include <action_flow/action_classifier.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <utility>

namespace action_flow
{
namespace
{
// Share of the columns in the head: the first pass reads this share of the training set. On the
// synthetic set's real descriptors without PCA a quarter bounds so well that about 15 of 495 rows
// need completing; after PCA the variance is spread evenly and most rows are completed
// (benchmarks/results.md).
constexpr double kHeadShare = 0.25;

thread_local std::size_t completed_rows = 0;

/**
 * What one query's search has completed so far: each label's nearest row and its distance, and the
 * k nearest rows (a max-heap on distance) for the vote.
 */
struct NearestRows
{
  NearestRows(std::size_t classes, std::size_t rows, int k)
    : best(classes, std::numeric_limits<float>::infinity()), best_row(classes, 0), done(rows, 0), k(k)
  {
  }

  /// Row @p i, of label @p c, completed at distance @p d.
  void add(Eigen::Index i, int c, float d)
  {
    done[i] = 1;
    if (d < best[c] || (d == best[c] && static_cast<std::size_t>(i) < best_row[c]))
    {
      best[c] = d;
      best_row[c] = static_cast<std::size_t>(i);
    }
    if (k > 1)
    {
      nearest.emplace(d, static_cast<std::size_t>(i));
      if (nearest.size() > static_cast<std::size_t>(k))
        nearest.pop();
    }
  }

  /// The smallest and second smallest of the labels' nearest distances, and the first one's label.
  void updateTwo()
  {
    first = second = std::numeric_limits<float>::infinity();
    for (std::size_t c = 0; c < best.size(); ++c)
      if (best[c] < first)
      {
        second = first;
        first = best[c];
        first_class = static_cast<int>(c);
      }
      else if (best[c] < second)
        second = best[c];
  }

  /**
   * Whether a row of label @p c whose distance is at least @p bound can change the answer. With
   * k = 1 the answer needs only the nearest row and the nearest row of another label (the margin): a
   * row matters while its bound is below the second smallest of the labels' nearest distances (both
   * only shrink as rows are completed, so a row skipped stays irrelevant). With k > 1 every voting
   * label's nearest distance is used, so each label's must be exact.
   */
  bool matters(int c, float bound) const
  {
    if (k == 1)
      return c == first_class ? bound <= first : bound <= second;
    return bound <= best[c] || nearest.size() < static_cast<std::size_t>(k) || bound <= nearest.top().first;
  }

  /// The k nearest rows as (distance, row), farthest first; empties the heap.
  std::vector<std::pair<float, std::size_t>> votes()
  {
    std::vector<std::pair<float, std::size_t>> out;
    for (; !nearest.empty(); nearest.pop())
      out.push_back(nearest.top());
    return out;
  }

  std::vector<float> best;
  std::vector<std::size_t> best_row;
  std::vector<char> done;
  std::priority_queue<std::pair<float, std::size_t>> nearest;
  int k;
  float first = std::numeric_limits<float>::infinity(), second = first;
  int first_class = -1;
};
}  // namespace

ActionClassifier::ActionClassifier(const Eigen::MatrixXf& descriptors, std::vector<std::string> labels, int k)
  : labels_(std::move(labels)), k_(k)
{
  if (descriptors.rows() == 0 || descriptors.cols() == 0)
    throw std::invalid_argument("ActionClassifier: the training set is empty");
  if (static_cast<std::size_t>(descriptors.rows()) != labels_.size())
    throw std::invalid_argument("ActionClassifier: descriptors and labels differ in number");
  if (k_ < 1)
    throw std::invalid_argument("ActionClassifier: k must be at least 1");
  if (!descriptors.allFinite())
    throw std::invalid_argument("ActionClassifier: the training set contains NaN or inf");
  for (const auto& l : labels_)
  {
    auto it = std::find(classes_.begin(), classes_.end(), l);
    class_of_.push_back(static_cast<int>(it - classes_.begin()));
    if (it == classes_.end())
      classes_.push_back(l);
  }
  const Eigen::Index dims = descriptors.cols();
  // The mean evaluated first: inside the broadcast Eigen would recompute it for every row.
  const Eigen::RowVectorXf mean = descriptors.colwise().mean();
  const Eigen::RowVectorXf variance = (descriptors.rowwise() - mean).array().square().colwise().sum().matrix();
  columns_.resize(static_cast<std::size_t>(dims));
  std::iota(columns_.begin(), columns_.end(), Eigen::Index(0));
  std::stable_sort(columns_.begin(), columns_.end(),
                   [&](Eigen::Index a, Eigen::Index b) { return variance[a] > variance[b]; });
  const Eigen::Index head = std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::ceil(kHeadShare * dims)));
  // Reorder the columns row by row on a row-major copy: writing the columns of a row-major
  // matrix one by one strides through memory and made building a model slower than using it.
  const RowMajorMatrix rows = descriptors;
  RowMajorMatrix reordered(rows.rows(), dims);
  for (Eigen::Index i = 0; i < rows.rows(); ++i)
    for (Eigen::Index j = 0; j < dims; ++j)
      reordered(i, j) = rows(i, columns_[j]);
  head_ = reordered.leftCols(head);
  tail_ = reordered.rightCols(dims - head);
}

std::size_t ActionClassifier::lastCompletedRows()
{
  return completed_rows;
}

Eigen::VectorXf ActionClassifier::reorder(const Eigen::VectorXf& query) const
{
  if (query.size() != dimension())
    throw std::invalid_argument("ActionClassifier: descriptor length " + std::to_string(query.size()) +
                                " does not match the model (" + std::to_string(dimension()) + ")");
  if (!query.allFinite())
    throw std::invalid_argument("ActionClassifier: descriptor contains NaN or inf");
  Eigen::VectorXf q(query.size());
  for (std::size_t j = 0; j < columns_.size(); ++j)
    q[static_cast<Eigen::Index>(j)] = query[columns_[j]];
  return q;
}

Classification ActionClassifier::classify(const Eigen::VectorXf& query) const
{
  const Eigen::VectorXf q = reorder(query);
  const Eigen::Index n = head_.rows();
  const Eigen::ArrayXf bound = headDistances(q);
  const Eigen::Array<float, 1, Eigen::Dynamic> q_tail = q.tail(tail_.cols()).transpose().array();
  completed_rows = 0;
  NearestRows rows(classes_.size(), static_cast<std::size_t>(n), k_);
  const auto take = [&](Eigen::Index i) {
    ++completed_rows;
    rows.add(i, class_of_[i], bound[i] + (tail_.row(i).array() - q_tail).square().sum());
  };

  // Pass 2: complete each label's most promising row first (so that every label has a nearest
  // distance to prune with), then any row whose bound can still win.
  std::vector<Eigen::Index> seed(classes_.size(), -1);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    Eigen::Index& s = seed[class_of_[i]];
    if (s < 0 || bound[i] < bound[s])
      s = i;
  }
  for (const Eigen::Index s : seed)
    take(s);
  rows.updateTwo();
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const int c = class_of_[i];
    if (rows.done[i] || !rows.matters(c, bound[i]))
      continue;
    const float before = rows.best[c];
    take(i);
    if (k_ == 1 && rows.best[c] < before)
      rows.updateTwo();
  }
  return decide(rows.best, rows.best_row, rows.votes());
}

Eigen::ArrayXf ActionClassifier::headDistances(const Eigen::VectorXf& q) const
{
  // Squared distance over the head, for every row, a column at a time (the head is column-major):
  // a lower bound of the full distance.
  Eigen::ArrayXf bound = Eigen::ArrayXf::Zero(head_.rows());
  for (Eigen::Index j = 0; j < head_.cols(); ++j)
    bound += (head_.col(j).array() - q[j]).square();
  return bound;
}

Classification ActionClassifier::classifyBruteForce(const Eigen::VectorXf& query) const
{
  // Every row completed, summed exactly as classify() sums it, so that both give the same floats.
  const Eigen::VectorXf q = reorder(query);
  const Eigen::ArrayXf head = headDistances(q);
  const Eigen::Array<float, 1, Eigen::Dynamic> q_tail = q.tail(tail_.cols()).transpose().array();
  std::vector<float> best(classes_.size(), std::numeric_limits<float>::infinity());
  std::vector<std::size_t> best_row(classes_.size(), 0);
  std::vector<std::pair<float, std::size_t>> all;
  for (Eigen::Index i = 0; i < head_.rows(); ++i)
  {
    const float d = head[i] + (tail_.row(i).array() - q_tail).square().sum();
    const int c = class_of_[i];
    if (d < best[c])
    {
      best[c] = d;
      best_row[c] = static_cast<std::size_t>(i);
    }
    all.emplace_back(d, static_cast<std::size_t>(i));
  }
  std::vector<std::pair<float, std::size_t>> votes;
  if (k_ > 1)
  {
    const std::size_t k = std::min<std::size_t>(k_, all.size());
    std::partial_sort(all.begin(), all.begin() + k, all.end());
    votes.assign(all.begin(), all.begin() + k);
  }
  return decide(best, best_row, votes);
}

Classification ActionClassifier::decide(const std::vector<float>& best, const std::vector<std::size_t>& best_row,
                                        const std::vector<std::pair<float, std::size_t>>& nearest) const
{
  int winner = static_cast<int>(std::min_element(best.begin(), best.end()) - best.begin());
  if (k_ > 1)
  {
    std::vector<int> votes(classes_.size(), 0);
    for (const auto& n : nearest)
      ++votes[class_of_[n.second]];
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
  if (std::isinf(out.margin))
    out.confidence = 1.0f;
  else if (out.margin > 0.0f)
    out.confidence = out.margin / (out.distance + out.margin);
  return out;
}

}  // namespace action_flow
