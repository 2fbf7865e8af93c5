#include "kernels/nearest_vertex.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/cancel_token.h"
#include "core/parallel_for.h"

namespace fq {

namespace {

// Cells per axis on either side of the origin (21 bits each in a key); points beyond share
// the last cell, which only an outlier reaches.
constexpr int64_t kHalfRange = int64_t(1) << 20;
constexpr int kMaxHalvings = 24;

int64_t axis_cell(double v, double origin, double cell) {
  const double c = std::floor((v - origin) / cell);
  return static_cast<int64_t>(std::clamp(c, double(-kHalfRange), double(kHalfRange - 1)));
}

uint64_t key_of(int64_t x, int64_t y, int64_t z) {
  return (uint64_t(z + kHalfRange) << 42) | (uint64_t(y + kHalfRange) << 21) | uint64_t(x + kHalfRange);
}

// Quantile q of one axis of the points (nth_element: O(n)).
float axis_quantile(const std::vector<Vec3>& points, float Vec3::*a, double q, std::vector<float>& scratch) {
  scratch.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) scratch[i] = points[i].*a;
  const auto k = static_cast<size_t>(q * double(points.size() - 1));
  std::nth_element(scratch.begin(), scratch.begin() + k, scratch.end());
  return scratch[k];
}

// The origin of the cells (the median of each axis, so that outliers cannot move it) and
// the spread that holds the middle 90 % of the points on the widest axis.
void robust_frame(const std::vector<Vec3>& points, Vec3& origin, float& spread) {
  std::vector<float> scratch;
  spread = 0.f;
  for (float Vec3::*a : {&Vec3::x, &Vec3::y, &Vec3::z}) {
    origin.*a = axis_quantile(points, a, 0.5, scratch);
    spread =
        std::max(spread, axis_quantile(points, a, 0.95, scratch) - axis_quantile(points, a, 0.05, scratch));
  }
}

// (cell key, point) pairs in key order for cells of `cell`; returns the occupied cells.
size_t sort_into_cells(const std::vector<Vec3>& points, Vec3 o, float cell,
                       std::vector<std::pair<uint64_t, uint32_t>>& out) {
  out.resize(points.size());
  for (uint32_t i = 0; i < points.size(); ++i) {
    const Vec3 p = points[i];
    out[i] = {key_of(axis_cell(p.x, o.x, cell), axis_cell(p.y, o.y, cell), axis_cell(p.z, o.z, cell)), i};
  }
  std::sort(out.begin(), out.end());
  size_t cells = 0;
  for (size_t i = 0; i < out.size(); ++i) cells += (i == 0 || out[i].first != out[i - 1].first) ? 1 : 0;
  return cells;
}

constexpr uint64_t kFree = ~uint64_t(0);
constexpr uint64_t kAxisMask = (uint64_t(1) << 21) - 1;
constexpr uint64_t kRowMask = ~kAxisMask;

// Block of a cell coordinate (floor division; blocks keep the cells' key layout).
int64_t block_of(int64_t c) { return (c + kHalfRange) / NearestVertexIndex::kBlockCells - kHalfRange; }
uint64_t block_key(int64_t x, int64_t y, int64_t z) { return key_of(block_of(x), block_of(y), block_of(z)); }

float gap2(double v, double origin, double cell, int64_t i) {
  const double lo = origin + double(i) * cell, hi = lo + cell;
  const double d = v < lo ? lo - v : (v > hi ? v - hi : 0.0);
  return static_cast<float>(d * d);
}

}  // namespace

NearestVertexIndex::CellCoords NearestVertexIndex::coords_of(Vec3 p) const {
  return {axis_cell(p.x, origin_.x, cell_), axis_cell(p.y, origin_.y, cell_),
          axis_cell(p.z, origin_.z, cell_)};
}

void NearestVertexIndex::build(const float* xyz, uint32_t n, float cell) {
  keys_.clear();
  rows_ = {};
  blocks_ = {};
  cell_start_.clear();
  sorted_.clear();
  order_.clear();
  cell_ = std::isfinite(cell) && cell > 0.f ? cell : 1.f;
  if (n == 0) return;
  std::vector<Vec3> points(n);
  for (uint32_t i = 0; i < n; ++i)
    points[i] = {xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]};
  float spread = 0.f;
  robust_frame(points, origin_, spread);
  std::vector<std::pair<uint64_t, uint32_t>> best, trial;
  size_t best_cells = sort_into_cells(points, origin_, cell_, best);
  // Too few cells: a cell wider than a quarter of the points' spread cannot be right (the
  // mean edge of a frame with a vertex far away), so start from there; then halve while the
  // cell leaves more than kCellLoad points per occupied cell and halving still splits them
  // (a pile of points on one spot never splits: it keeps its cell).
  if (n > kCellLoad * best_cells && spread > 0.f && cell_ > 0.25f * spread) {
    cell_ = 0.25f * spread;
    best_cells = sort_into_cells(points, origin_, cell_, best);
  }
  const CancelToken* cancel = current_cancel_token();
  for (int h = 0; h < kMaxHalvings && n > kCellLoad * best_cells; ++h) {
    if (cancel != nullptr && cancel->expired()) break;  // a coarse index is still a right one
    const float half = 0.5f * cell_;
    if (!(half > 0.f)) break;
    const size_t cells = sort_into_cells(points, origin_, half, trial);
    if (2 * cells < 3 * best_cells) break;
    best.swap(trial);
    best_cells = cells;
    cell_ = half;
  }
  keys_.reserve(best_cells);
  cell_start_.reserve(best_cells + 1);
  sorted_.resize(n);
  order_.resize(n);
  for (uint32_t k = 0; k < n; ++k) {
    if (k == 0 || best[k].first != best[k - 1].first) {
      keys_.push_back(best[k].first);
      cell_start_.push_back(k);
    }
    order_[k] = best[k].second;
    sorted_[k] = points[best[k].second];
  }
  cell_start_.push_back(n);
  rows_.reset(keys_.size());
  blocks_.reset(keys_.size());
  for (uint32_t k = 0; k < keys_.size(); ++k) {
    const uint64_t key = keys_[k];
    const int64_t x = int64_t(key & kAxisMask) - kHalfRange,
                  y = int64_t((key >> 21) & kAxisMask) - kHalfRange, z = int64_t(key >> 42) - kHalfRange;
    blocks_.insert(block_key(x, y, z), 0, 0);
    const uint64_t r = key & kRowMask;
    if (k > 0 && (keys_[k - 1] & kRowMask) == r) continue;  // not the row's first cell
    uint32_t last = k + 1;
    while (last < keys_.size() && (keys_[last] & kRowMask) == r) ++last;
    rows_.insert(r, k, last);
  }
}

void NearestVertexIndex::KeyTable::reset(size_t keys) {
  bits_ = 1;
  while ((size_t(1) << bits_) < 2 * keys) ++bits_;  // at most half full
  slots_.assign(size_t(1) << bits_, {kFree, 0, 0});
}

size_t NearestVertexIndex::KeyTable::slot_of(uint64_t key) const {
  return size_t((key * 0x9E3779B97F4A7C15ull) >> (64 - bits_));
}

void NearestVertexIndex::KeyTable::insert(uint64_t key, uint32_t first, uint32_t last) {
  const size_t mask = slots_.size() - 1;
  size_t slot = slot_of(key);
  while (slots_[slot].key != kFree && slots_[slot].key != key) slot = (slot + 1) & mask;
  slots_[slot] = {key, first, last};
}

std::pair<uint32_t, uint32_t> NearestVertexIndex::KeyTable::find(uint64_t key) const {
  const size_t mask = slots_.size() - 1;
  for (size_t slot = slot_of(key);; slot = (slot + 1) & mask) {
    if (slots_[slot].key == key) return {slots_[slot].first, slots_[slot].last};
    if (slots_[slot].key == kFree) return {0, 0};
  }
}

bool NearestVertexIndex::KeyTable::contains(uint64_t key) const {
  const size_t mask = slots_.size() - 1;
  for (size_t slot = slot_of(key);; slot = (slot + 1) & mask) {
    if (slots_[slot].key == key) return true;
    if (slots_[slot].key == kFree) return false;
  }
}

bool NearestVertexIndex::any_block_near(Vec3 p, float r) const {
  const CellCoords lo = coords_of({p.x - r, p.y - r, p.z - r}), hi = coords_of({p.x + r, p.y + r, p.z + r});
  for (int64_t z = block_of(lo.z); z <= block_of(hi.z); ++z)
    for (int64_t y = block_of(lo.y); y <= block_of(hi.y); ++y)
      for (int64_t x = block_of(lo.x); x <= block_of(hi.x); ++x)
        if (blocks_.contains(key_of(x, y, z))) return true;
  return false;
}

uint32_t NearestVertexIndex::nearest(Vec3 p, float max_radius) const {
  if (sorted_.empty() || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return kNone;
  const float reach = std::min(max_radius, kMaxReachCells * cell_);
  if (!(reach >= 0.f)) return kNone;
  uint32_t budget = kMaxCandidates;
  bool blocks_checked = false;
  // Growing spheres: the first that holds a point holds the nearest one.
  // Half a cell first: most queries (a vertex of the next capture of the same surface) find
  // their nearest within it, among ~8 cells instead of ~27.
  for (float r = std::min(0.5f * cell_, reach);; r = std::min(2.f * r, reach)) {
    const float r2 = r * r;
    const CellCoords lo = coords_of({p.x - r, p.y - r, p.z - r}), hi = coords_of({p.x + r, p.y + r, p.z + r});
    uint32_t best = kNone;
    float best_d2 = 0.f;
    for (int64_t iz = lo.z; iz <= hi.z && budget > 0; ++iz) {
      const float gz = gap2(p.z, origin_.z, cell_, iz);
      if (gz > r2) continue;
      for (int64_t iy = lo.y; iy <= hi.y && budget > 0; ++iy) {
        const float gyz = gz + gap2(p.y, origin_.y, cell_, iy);
        if (gyz > r2) continue;
        const float rx = std::sqrt(r2 - gyz);  // half-width of the sphere in this row
        const int64_t x0 = axis_cell(p.x - rx, origin_.x, cell_), x1 = axis_cell(p.x + rx, origin_.x, cell_);
        // x is the fastest axis of a key: the row's cells are one run of keys_, its points one run of
        // sorted_.
        const auto [row_first, row_last] = rows_.find(key_of(-kHalfRange, iy, iz));
        if (row_first == row_last) continue;
        // A row crossing a surface holds a few cells: a linear scan, a binary search in a long one.
        const uint64_t k0 = key_of(x0, iy, iz), k1 = key_of(x1, iy, iz);
        uint32_t first = row_first;
        if (row_last - row_first > 8)
          first = uint32_t(std::lower_bound(keys_.begin() + row_first, keys_.begin() + row_last, k0) -
                           keys_.begin());
        else
          while (first < row_last && keys_[first] < k0) ++first;
        uint32_t last = first;
        while (last < row_last && keys_[last] <= k1) ++last;  // at most 2 reach + 1 cells
        const uint32_t begin = cell_start_[first], end = cell_start_[last];
        for (uint32_t j = begin; j < end && budget > 0; ++j, --budget) {
          const Vec3 d = sorted_[j] - p;
          const float d2 = norm2(d);
          if (d2 <= r2 && (best == kNone || d2 < best_d2)) {
            best = j;
            best_d2 = d2;
          }
        }
      }
    }
    if (best != kNone) return order_[best];
    if (!(r < reach) || budget == 0) return kNone;
    // Before the wide rings (81 and 289 rows), whether anything lies within reach at all.
    if (!blocks_checked && 2.f * r >= 2.f * cell_) {
      if (!any_block_near(p, reach)) return kNone;
      blocks_checked = true;
    }
  }
}

void NearestVertexIndex::nearest_all(const float* xyz, uint32_t n, float max_radius,
                                     std::vector<uint32_t>& out, int threads) const {
  out.resize(n);
  parallel_for(n, threads, [&](uint32_t i) {
    const float* q = xyz + 3 * size_t(i);
    out[i] = nearest({q[0], q[1], q[2]}, max_radius);
  });
}

}  // namespace fq
