// The flow's neighbour grid and batch matching (neighbour_grid.h).
#include "neighbour_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace action_flow
{
namespace
{
// Grid cell size relative to the mean spacing of the points in their bounding box.
constexpr double kCellScale = 0.8;
}  // namespace

FlowFrame::Index::Index(const std::vector<Eigen::Vector3f>& pts, const std::vector<Eigen::Vector3f>& colours)
{
  const std::size_t n = pts.size();
  if (n == 0)
  {
    start.assign(2, 0);
    return;
  }
  Eigen::Vector3f lo = pts[0], hi = pts[0];
  for (const auto& p : pts)
  {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Cell size: about the mean spacing of n points filling the bounding box (a flat or thin cloud
  // counts as 1/20 of its largest extent thick). For a voxelised person and K = 50 this puts the
  // K-th neighbour two to three cells away; 0.8 used the fewest instructions of 0.6-1.2 for
  // person clouds at 0.06, 0.04 and 0.02 m voxels (docs/bench.md).
  const Eigen::Vector3f ext = hi - lo;
  const float floor_ext = std::max(1e-4f, 0.05f * ext.maxCoeff());
  const double volume = static_cast<double>(std::max(ext.x(), floor_ext)) * std::max(ext.y(), floor_ext) *
                        std::max(ext.z(), floor_ext);
  cell = static_cast<float>(kCellScale * std::cbrt(volume / static_cast<double>(n)));
  // Keep the dense cell array within a few times the point count, whatever the cloud's shape.
  for (;;)
  {
    inv_cell = 1.0f / cell;
    nx = static_cast<int>(ext.x() * inv_cell) + 1;
    ny = static_cast<int>(ext.y() * inv_cell) + 1;
    nz = static_cast<int>(ext.z() * inv_cell) + 1;
    if (static_cast<double>(nx) * ny * nz <= 8.0 * n + 64)
      break;
    cell *= 1.25f;
  }
  origin = lo;
  const std::size_t cells = static_cast<std::size_t>(nx) * ny * nz;
  std::vector<std::uint32_t> cell_of(n);
  start.assign(cells + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t c = coord(pts[i].x(), origin.x(), nx) +
                          static_cast<std::size_t>(nx) * (coord(pts[i].y(), origin.y(), ny) +
                                                          static_cast<std::size_t>(ny) * coord(pts[i].z(), origin.z(), nz));
    cell_of[i] = static_cast<std::uint32_t>(c);
    ++start[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c)
    start[c + 1] += start[c];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  x.resize(n), y.resize(n), z.resize(n), c0.resize(n), c1.resize(n), c2.resize(n), id.resize(n), slot.resize(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint32_t s = fill[cell_of[i]]++;
    x[s] = pts[i].x(), y[s] = pts[i].y(), z[s] = pts[i].z();
    c0[s] = colours[i].x(), c1[s] = colours[i].y(), c2[s] = colours[i].z();
    id[s] = static_cast<std::uint32_t>(i);
    slot[i] = s;
  }
}

FlowFrame::Index::Cube FlowFrame::Index::cube(const float* q, int r) const
{
  Cube c;
  const int n[3] = { nx, ny, nz };
  float safe = std::numeric_limits<float>::infinity();
  for (int a = 0; a < 3; ++a)
  {
    const int centre = coord(q[a], origin[a], n[a]);
    c.lo[a] = centre - r;
    c.hi[a] = centre + r;
    // A face on the grid's border bounds nothing: no point lies beyond it.
    if (c.lo[a] > 0)
      safe = std::min(safe, q[a] - (origin[a] + c.lo[a] * cell));
    else
      c.lo[a] = 0;
    if (c.hi[a] < n[a] - 1)
      safe = std::min(safe, origin[a] + (c.hi[a] + 1) * cell - q[a]);
    else
      c.hi[a] = n[a] - 1;
  }
  // Shrunk by a relative 1e-5 so that float rounding of squared distances cannot admit a point
  // from outside the cube as nearer than one inside it.
  c.safe_sq = std::isinf(safe) ? safe : (safe > 0.0f ? safe * safe * (1.0f - 1e-5f) : -1.0f);
  return c;
}

void FlowFrame::Index::gather(const float* q, const Cube& c, std::vector<float>& d2,
                              std::vector<std::uint32_t>& slots) const
{
  d2.clear();
  slots.clear();
  const float qx = q[0], qy = q[1], qz = q[2];
  for (int k = c.lo[2]; k <= c.hi[2]; ++k)
    for (int j = c.lo[1]; j <= c.hi[1]; ++j)
    {
      // Cells lo..hi of one row are consecutive, so their points are one run of slots.
      const std::size_t row = static_cast<std::size_t>(nx) * (j + static_cast<std::size_t>(ny) * k);
      const std::uint32_t b = start[row + c.lo[0]], e = start[row + c.hi[0] + 1];
      const std::size_t old = d2.size();
      d2.resize(old + (e - b));
      slots.resize(old + (e - b));
      float* out = d2.data() + old;
      std::uint32_t* so = slots.data() + old;
      for (std::uint32_t s = b; s < e; ++s)
      {
        const float dx = x[s] - qx, dy = y[s] - qy, dz = z[s] - qz;
        out[s - b] = dx * dx + dy * dy + dz * dz;
        so[s - b] = s;
      }
    }
}

void FlowFrame::Index::gatherNearest(const float* q, std::size_t k, int& r, std::vector<float>& d2,
                                     std::vector<std::uint32_t>& slots) const
{
  for (;;)
  {
    const Cube c = cube(q, r);
    gather(q, c, d2, slots);
    if (std::isinf(c.safe_sq))
      return;  // the whole grid
    std::size_t inside = 0;
    for (float d : d2)
      inside += d <= c.safe_sq;
    if (inside >= k)
      return;
    ++r;
  }
}

FlowFrame::FlowFrame(const Cloud& cloud, double stamp) : stamp_(stamp)
{
  xyz_.reserve(cloud.size());
  colour_.reserve(cloud.size());
  for (const auto& p : cloud.points)
  {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    xyz_.emplace_back(p.x, p.y, p.z);
    colour_.push_back(hsvCone(rgbToHsv(p.r, p.g, p.b)));
  }
  index_ = std::make_unique<Index>(xyz_, colour_);
}

FlowFrame::~FlowFrame() = default;

void FlowFrame::nearest(const Eigen::Vector3f& q, int k, std::vector<std::size_t>& indices,
                        std::vector<float>& sq_dists) const
{
  const std::size_t n = std::min<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), xyz_.size());
  indices.clear();
  sq_dists.clear();
  if (n == 0)
    return;
  std::vector<float> d2;
  std::vector<std::uint32_t> slots;
  int r = 1;
  index_->gatherNearest(q.data(), n, r, d2, slots);
  std::vector<std::uint32_t> order(d2.size());
  for (std::uint32_t i = 0; i < order.size(); ++i)
    order[i] = i;
  const Index& ix = *index_;
  std::partial_sort(order.begin(), order.begin() + n, order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return d2[a] < d2[b] || (d2[a] == d2[b] && ix.id[slots[a]] < ix.id[slots[b]]);
  });
  for (std::size_t i = 0; i < n; ++i)
  {
    indices.push_back(ix.id[slots[order[i]]]);
    sq_dists.push_back(d2[order[i]]);
  }
}

void FlowFrame::within(const Eigen::Vector3f& q, float radius, std::vector<std::size_t>& indices) const
{
  indices.clear();
  if (xyz_.empty() || !(radius > 0.0f))
    return;
  const Index& ix = *index_;
  const float r2 = radius * radius;
  Index::Cube c;
  const int n[3] = { ix.nx, ix.ny, ix.nz };
  for (int a = 0; a < 3; ++a)
  {
    c.lo[a] = ix.coord(q[a] - radius, ix.origin[a], n[a]);
    c.hi[a] = ix.coord(q[a] + radius, ix.origin[a], n[a]);
  }
  std::vector<float> d2;
  std::vector<std::uint32_t> slots;
  ix.gather(q.data(), c, d2, slots);
  for (std::size_t i = 0; i < d2.size(); ++i)
    if (d2[i] < r2)
      indices.push_back(ix.id[slots[i]]);
}

namespace
{
// The paper's step 1 for a batch of query points, grouped by the cell of @p to's grid they fall
// in: the points of a cube of cells around that cell are copied once into contiguous arrays, and
// every query of the group scans those with vectorisable loops.
class BatchMatcher
{
public:
  BatchMatcher(const FlowFrame::Index& to, std::size_t k) : to_(to), k_(k) {}

  /** Fills out[q] for every q in @p queries (indices into @p from). */
  void run(const FlowFrame& from, const std::vector<std::uint32_t>& queries, std::vector<std::size_t>& out)
  {
    // Counting sort of the queries by the cell of `to` they fall in.
    const FlowFrame::Index& ix = to_;
    const std::size_t cells = ix.start.size() - 1;
    std::vector<std::uint32_t> cell_of(queries.size()), first(cells + 1, 0), order(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i)
    {
      const Eigen::Vector3f& q = from.point(queries[i]);
      cell_of[i] = static_cast<std::uint32_t>(
          ix.coord(q.x(), ix.origin.x(), ix.nx) +
          static_cast<std::size_t>(ix.nx) *
              (ix.coord(q.y(), ix.origin.y(), ix.ny) + static_cast<std::size_t>(ix.ny) * ix.coord(q.z(), ix.origin.z(), ix.nz)));
      ++first[cell_of[i] + 1];
    }
    for (std::size_t c = 0; c < cells; ++c)
      first[c + 1] += first[c];
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < queries.size(); ++i)
      order[fill[cell_of[i]]++] = queries[i];

    for (std::size_t c = 0; c < cells; ++c)
    {
      if (first[c] == first[c + 1])
        continue;
      const int centre[3] = { static_cast<int>(c % ix.nx), static_cast<int>((c / ix.nx) % ix.ny),
                              static_cast<int>(c / (static_cast<std::size_t>(ix.nx) * ix.ny)) };
      gatherCube(centre, r_);
      for (std::uint32_t i = first[c]; i < first[c + 1]; ++i)
        out[order[i]] = matchOne(from.point(order[i]), from.colour(order[i]), centre);
      // Neighbouring cells need about the same cube; a roomy one is tried a size smaller next.
      if (x_.size() > 4 * k_ && r_ > 1)
        --r_;
    }
  }

private:
  void gatherCube(const int centre[3], int r)
  {
    const FlowFrame::Index& ix = to_;
    const int n[3] = { ix.nx, ix.ny, ix.nz };
    r_ = r;
    whole_ = true;
    for (int a = 0; a < 3; ++a)
    {
      lo_[a] = std::max(0, centre[a] - r);
      hi_[a] = std::min(n[a] - 1, centre[a] + r);
      lo_open_[a] = lo_[a] == 0;  // on the grid's border: nothing lies beyond, the face bounds nothing
      hi_open_[a] = hi_[a] == n[a] - 1;
      whole_ = whole_ && lo_open_[a] && hi_open_[a];
    }
    x_.clear(), y_.clear(), z_.clear(), c0_.clear(), c1_.clear(), c2_.clear(), id_.clear();
    for (int k = lo_[2]; k <= hi_[2]; ++k)
      for (int j = lo_[1]; j <= hi_[1]; ++j)
      {
        // Cells lo..hi of one row are consecutive, so their points are one run of slots.
        const std::size_t row = static_cast<std::size_t>(ix.nx) * (j + static_cast<std::size_t>(ix.ny) * k);
        const std::uint32_t b = ix.start[row + lo_[0]], e = ix.start[row + hi_[0] + 1];
        x_.insert(x_.end(), ix.x.begin() + b, ix.x.begin() + e);
        y_.insert(y_.end(), ix.y.begin() + b, ix.y.begin() + e);
        z_.insert(z_.end(), ix.z.begin() + b, ix.z.begin() + e);
        c0_.insert(c0_.end(), ix.c0.begin() + b, ix.c0.begin() + e);
        c1_.insert(c1_.end(), ix.c1.begin() + b, ix.c1.begin() + e);
        c2_.insert(c2_.end(), ix.c2.begin() + b, ix.c2.begin() + e);
        id_.insert(id_.end(), ix.id.begin() + b, ix.id.begin() + e);
      }
  }

  // Squared radius of the ball around q that the gathered cube surely contains, shrunk by a
  // relative 1e-5 so that float rounding cannot admit a point from outside as nearer than one inside.
  float safeSq(const Eigen::Vector3f& q) const
  {
    if (whole_)
      return std::numeric_limits<float>::infinity();
    const FlowFrame::Index& ix = to_;
    float safe = std::numeric_limits<float>::infinity();
    for (int a = 0; a < 3; ++a)
    {
      if (!lo_open_[a])
        safe = std::min(safe, q[a] - (ix.origin[a] + lo_[a] * ix.cell));
      if (!hi_open_[a])
        safe = std::min(safe, ix.origin[a] + (hi_[a] + 1) * ix.cell - q[a]);
    }
    return safe > 0.0f ? safe * safe * (1.0f - 1e-5f) : -1.0f;
  }

  // Among the k nearest points (XYZ) the nearest in colour; among equal colours the nearer point.
  // The k nearest are never sorted: candidates are tried in order of colour distance, and the first
  // with fewer than k candidates nearer than it (in the (distance, index) order) wins; usually the
  // first or second try. The cube is grown until k candidates lie within safeSq, so that the
  // candidates' order is the frame's order up to the k-th.
  std::size_t matchOne(const Eigen::Vector3f& q, const Eigen::Vector3f& qc, const int centre[3])
  {
    const std::size_t m = gatherEnough(q, centre);
    colourDistances(qc, m);
    return nearestColour(std::min(k_, m), m);
  }

  // out[i]: the squared distance from q to (a[i], b[i], c[i]), for every candidate (a loop over
  // separate coordinate arrays, which the compiler vectorises).
  static void squaredDistances(const std::vector<float>& a, const std::vector<float>& b, const std::vector<float>& c,
                               const Eigen::Vector3f& q, std::vector<float>& out)
  {
    const std::size_t m = a.size();
    out.resize(m);
    const float qa = q.x(), qb = q.y(), qc = q.z();
    const float *pa = a.data(), *pb = b.data(), *pc = c.data();
    float* o = out.data();
    for (std::size_t i = 0; i < m; ++i)
    {
      const float u = pa[i] - qa, v = pb[i] - qb, w = pc[i] - qc;
      o[i] = u * u + v * v + w * w;
    }
  }

  // Fills d2_ with the squared distances from q to the gathered candidates, growing the cube until
  // k of them lie within its safe radius (safe_); returns the number of candidates.
  std::size_t gatherEnough(const Eigen::Vector3f& q, const int centre[3])
  {
    for (;;)
    {
      const std::size_t m = x_.size();
      squaredDistances(x_, y_, z_, q, d2_);
      const float* d2 = d2_.data();
      const float safe = safe_ = safeSq(q);
      if (std::isinf(safe))
        return m;
      std::uint32_t inside = 0;  // 32-bit counters keep these loops vectorised
      for (std::size_t i = 0; i < m; ++i)
        inside += d2[i] <= safe ? 1u : 0u;
      if (inside >= k_)
        return m;
      gatherCube(centre, r_ + 1);
    }
  }

  // hbits_: the squared colour distances from qc to the m candidates, as bit patterns. Those of
  // non-negative floats order as the floats do; an integer minimum is vectorised where a float one
  // (NaN rules) is not.
  void colourDistances(const Eigen::Vector3f& qc, std::size_t m)
  {
    squaredDistances(c0_, c1_, c2_, qc, h_);
    hbits_.resize(m);
    std::memcpy(hbits_.data(), h_.data(), m * sizeof(float));
  }

  // The id of the candidate nearest in colour among the kk nearest in space (see matchOne).
  std::uint32_t nearestColour(std::size_t kk, std::size_t m)
  {
    const float* d2 = d2_.data();
    const std::uint32_t* id = id_.data();
    // First try: the candidate with the least (colour distance, distance, index).
    const std::int32_t* hb = hbits_.data();
    std::int32_t hmin = hb[0];
    for (std::size_t i = 1; i < m; ++i)
      hmin = hb[i] < hmin ? hb[i] : hmin;
    std::size_t best = 0;
    while (hb[best] != hmin)
      ++best;
    for (std::size_t i = best + 1; i < m; ++i)  // equal colour distances: rare
      if (hb[i] == hmin && (d2[i] < d2[best] || (d2[i] == d2[best] && id[i] < id[best])))
        best = i;
    const float db = d2[best];
    std::uint32_t less = 0, equal = 0;
    for (std::size_t i = 0; i < m; ++i)
    {
      less += d2[i] < db ? 1u : 0u;
      equal += d2[i] == db ? 1u : 0u;
    }
    if (less + equal <= kk)
      return id[best];  // within the k nearest whatever the order among equal distances
    // Otherwise find the k-th nearest (all k lie within the safe radius) by selecting on integer
    // keys (distance bits, index), then take the best colour among candidates up to it.
    keys_.clear();
    auto key = [&](std::size_t i) {
      std::uint32_t bits;
      std::memcpy(&bits, &d2[i], sizeof bits);  // non-negative floats order as their bits
      return (static_cast<std::uint64_t>(bits) << 32) | id[i];
    };
    for (std::size_t i = 0; i < m; ++i)
      if (d2[i] <= safe_)
        keys_.push_back(key(i));
    std::nth_element(keys_.begin(), keys_.begin() + (kk - 1), keys_.end());
    const std::uint64_t kth = keys_[kk - 1];
    std::int32_t best_h = std::numeric_limits<std::int32_t>::max();
    std::uint64_t best_key = 0;
    for (std::size_t i = 0; i < m; ++i)
    {
      const std::uint64_t k = key(i);
      if (k <= kth && (hb[i] < best_h || (hb[i] == best_h && k < best_key)))
      {
        best_h = hb[i];
        best_key = k;
        best = i;
      }
    }
    return id[best];
  }

  const FlowFrame::Index& to_;
  std::size_t k_;
  int r_ = 1;
  int lo_[3] = { 0, 0, 0 }, hi_[3] = { 0, 0, 0 };
  bool lo_open_[3] = { true, true, true }, hi_open_[3] = { true, true, true };
  bool whole_ = true;
  std::vector<float> x_, y_, z_, c0_, c1_, c2_, d2_, h_;
  std::vector<std::uint32_t> id_;
  std::vector<std::uint64_t> keys_;
  std::vector<std::int32_t> hbits_;
  float safe_ = 0.0f;  // safeSq of the current query
};
}  // namespace

void matchNearest(const FlowFrame& from, const FlowFrame::Index& to, std::size_t k,
                  const std::vector<std::uint32_t>& queries, std::vector<std::size_t>& out)
{
  BatchMatcher(to, k).run(from, queries, out);
}

}  // namespace action_flow
