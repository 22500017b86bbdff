#include "backend/glmb/gibbs_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/log_math.hpp"

namespace glmbslam::backend {
namespace {
/// Chains with at least this many sweeps keep per-row counts of taken columns (see gibbs_sample).
constexpr int kCountedSweeps = 4;

/// xoshiro256+ seeded from the caller's stream: a fast generator for the many categorical draws of one call
/// (deterministic given the stream's state).
class FastUniform {
 public:
  explicit FastUniform(RandomStream& rng) {
    std::uint64_t x = rng.engine()();
    for (auto& v : s_) v = x = splitmix64(x);
  }
  double operator()() {
    const std::uint64_t result = s_[0] + s_[3];
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = (s_[3] << 45) | (s_[3] >> 19);
    return static_cast<double>(result >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t s_[4];
};
}  // namespace

double AssociationTable::log_weight(const int* gamma) const {
  double s = 0.0;
  for (int i = 0; i < rows(); ++i) {
    bool found = false;
    for (int e = row_begin(i); e < row_end(i); ++e) {
      if (column_[e] == gamma[i]) {
        s += log_eta_[e];
        found = true;
        break;
      }
    }
    if (!found) return kLogZero;
  }
  return s;
}

void AssociationTable::end_row() {
  const int b = row_start_.back();
  const int e_end = static_cast<int>(column_.size());
  row_start_.push_back(e_end);
  double row_max = kLogZero;
  int best = b;
  for (int e = b; e < e_end; ++e) {
    if (log_eta_[e] > row_max) {
      row_max = log_eta_[e];
      best = e;
    }
  }
  bool has_missed = false;
  eta_.resize(e_end);
  for (int e = b; e < e_end; ++e) {
    eta_[e] = row_max == kLogZero ? 0.0 : std::exp(log_eta_[e] - row_max);
    if (column_[e] == kMissed && eta_[e] > 0.0) has_missed = true;
  }
  start_.push_back(!has_missed && e_end > b ? column_[best] : kMissed);
  double total = 0.0;
  for (int e = b; e < e_end; ++e) total += eta_[e];
  total_.push_back(total);
}

int gibbs_sample(const AssociationTable& table, int sweeps, RandomStream& rng, GibbsWorkspace& ws,
                 std::vector<int>& samples) {
  ws.rows.resize(table.rows());
  std::iota(ws.rows.begin(), ws.rows.end(), 0);
  return gibbs_sample(table, ws.rows.data(), table.rows(), sweeps, rng, ws, samples, false);
}

int gibbs_sample(const AssociationTable& table, const int* row_ids, int num_rows, int sweeps,
                 RandomStream& rng, GibbsWorkspace& ws, std::vector<int>& samples, bool skip_repeats) {
  const int P = num_rows;
  const int M = table.num_measurements();
  // owner[c] for c ∈ {−1, 0, 1..M}: the row using measurement c (dead and missed are never owned, so
  // "locked" is owner[c] ≥ 0 ∧ owner[c] ≠ i for every column)
  ws.owner.assign(static_cast<std::size_t>(M) + 2, -1);
  int* const owner = ws.owner.data() + 1;
  ws.current.resize(P);
  int* const current = ws.current.data();
  for (int i = 0; i < P; ++i) {
    int start = table.start(row_ids[i]);
    if (start > 0 && owner[start] >= 0) start = AssociationTable::kDead;  // rare: fall back to dead
    current[i] = start;
    if (start > 0) owner[start] = i;
  }
  samples.insert(samples.end(), current, current + P);
  int appended = 1;
  const int* const column = table.column_data();
  const double* const eta = table.eta_data();
  // locked[i] = the number of row i's measurement columns owned by another row. While it is 0 (the usual
  // case) the conditional of row i is its whole row: the normaliser is the precomputed row total and no
  // entry needs the owner test. The counts change only when a row changes its measurement. Setting them up
  // costs about one sweep, so short chains keep every row on the owner test (locked[i] = −1 forces it).
  ws.locked.assign(P, -1);
  int* const locked = ws.locked.data();
  const bool counts = sweeps >= kCountedSweeps;
  if (counts) {
    ws.column_start.assign(static_cast<std::size_t>(M) + 2, 0);
    for (int i = 0; i < P; ++i) {
      const int r = row_ids[i];
      for (int e = table.row_begin(r); e < table.row_end(r); ++e)
        if (column[e] > 0) ++ws.column_start[column[e] + 1];
    }
    for (int c = 1; c <= M + 1; ++c) ws.column_start[c] += ws.column_start[c - 1];
    ws.column_rows.resize(ws.column_start[M + 1]);
    {
      int* fill = ws.owner.data() + 1;  // owner is reused as a fill cursor per column, then reset below
      for (int c = 1; c <= M; ++c) fill[c] = ws.column_start[c];
      for (int i = 0; i < P; ++i) {
        const int r = row_ids[i];
        for (int e = table.row_begin(r); e < table.row_end(r); ++e)
          if (column[e] > 0) ws.column_rows[fill[column[e]]++] = i;
      }
      for (int c = 1; c <= M; ++c) fill[c] = -1;
      for (int i = 0; i < P; ++i)
        if (current[i] > 0) owner[current[i]] = i;
    }
    std::fill(locked, locked + P, 0);
  }
  const int* const column_start = ws.column_start.data();
  const int* const column_rows = ws.column_rows.data();
  auto take = [&](int c, int i, int delta) {  // row i takes (+1) or releases (−1) column c > 0
    if (!counts) return;
    for (int k = column_start[c]; k < column_start[c + 1]; ++k)
      if (column_rows[k] != i) locked[column_rows[k]] += delta;
  };
  for (int i = 0; i < P; ++i)
    if (current[i] > 0) take(current[i], i, 1);
  FastUniform uniform(rng);  // one draw from rng per call, whatever the table
  for (int s = 0; s < sweeps; ++s) {
    bool changed = false;
    for (int i = 0; i < P; ++i) {
      const int r = row_ids[i];
      const int b = table.row_begin(r), e_end = table.row_end(r);
      if (e_end - b <= 1) continue;  // a single possible value
      int chosen = current[i];
      if (locked[i] == 0) {
        const double total = table.total(r);
        if (!(total > 0.0)) continue;  // no valid choice: keep the current value
        double u = uniform() * total;
        for (int e = b; e < e_end; ++e) {
          if (eta[e] <= 0.0) continue;
          chosen = column[e];
          u -= eta[e];
          if (u < 0.0) break;
        }
      } else {
        double total = 0.0;
        for (int e = b; e < e_end; ++e) {
          const int o = owner[column[e]];
          if (!(o >= 0 && o != i)) total += eta[e];
        }
        if (!(total > 0.0)) continue;
        double u = uniform() * total;
        for (int e = b; e < e_end; ++e) {
          const int o = owner[column[e]];
          if ((o >= 0 && o != i) || eta[e] <= 0.0) continue;
          chosen = column[e];
          u -= eta[e];
          if (u < 0.0) break;
        }
      }
      if (chosen != current[i]) {
        if (current[i] > 0) {
          owner[current[i]] = -1;
          take(current[i], i, -1);
        }
        current[i] = chosen;
        if (chosen > 0) {
          owner[chosen] = i;
          take(chosen, i, 1);
        }
        changed = true;
      }
    }
    if (changed || !skip_repeats) {
      samples.insert(samples.end(), current, current + P);
      ++appended;
    }
  }
  return appended;
}

int unique_solutions(std::vector<int>& samples, int row_count, int count) {
  if (row_count == 0) {
    samples.clear();
    return count > 0 ? 1 : 0;
  }
  if (count <= 1) {
    samples.resize(static_cast<std::size_t>(count > 0 ? count : 0) * row_count);
    return count > 0 ? count : 0;
  }
  thread_local std::vector<std::pair<std::uint64_t, int>> keyed;
  thread_local std::vector<int> out;
  keyed.clear();
  for (int k = 0; k < count; ++k) {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    const int* g = samples.data() + static_cast<std::size_t>(k) * row_count;
    for (int i = 0; i < row_count; ++i) h = splitmix64(h ^ static_cast<std::uint32_t>(g[i] + 2));
    keyed.emplace_back(h, k);
  }
  std::sort(keyed.begin(), keyed.end());
  auto row = [&](int k) { return samples.begin() + static_cast<std::size_t>(k) * row_count; };
  out.clear();
  int distinct = 0;
  std::size_t group_start = 0;
  for (std::size_t n = 0; n < keyed.size(); ++n) {
    if (n == 0 || keyed[n].first != keyed[n - 1].first) group_start = n;
    bool duplicate = false;
    for (std::size_t m = group_start; m < n && !duplicate; ++m)
      duplicate = std::equal(row(keyed[m].second), row(keyed[m].second) + row_count, row(keyed[n].second));
    if (duplicate) continue;
    out.insert(out.end(), row(keyed[n].second), row(keyed[n].second) + row_count);
    ++distinct;
  }
  samples.swap(out);  // (out keeps the old buffer for the next call)
  return distinct;
}

}  // namespace glmbslam::backend
