#include "backend/glmb/gibbs_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/log_math.hpp"

namespace glmbslam::backend {
namespace {
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

int gibbs_sample(const AssociationTable& table, int sweeps, RandomStream& rng, GibbsWorkspace& ws,
                 std::vector<int>& samples) {
  const int P = table.rows();
  const int M = table.num_measurements();
  const int entries = P > 0 ? table.row_end(P - 1) : 0;
  ws.eta.resize(entries);
  ws.owner.assign(M + 1, -1);
  ws.current.resize(P);
  // Linear-space η relative to each row's maximum, and the initial state.
  for (int i = 0; i < P; ++i) {
    double row_max = kLogZero;
    int best = table.row_begin(i);
    for (int e = table.row_begin(i); e < table.row_end(i); ++e) {
      if (table.log_eta(e) > row_max) {
        row_max = table.log_eta(e);
        best = e;
      }
    }
    int start = AssociationTable::kMissed;
    bool has_missed = false;
    for (int e = table.row_begin(i); e < table.row_end(i); ++e) {
      ws.eta[e] = row_max == kLogZero ? 0.0 : std::exp(table.log_eta(e) - row_max);
      if (table.column(e) == AssociationTable::kMissed && ws.eta[e] > 0.0) has_missed = true;
    }
    if (!has_missed && table.row_end(i) > table.row_begin(i)) {
      start = table.column(best);
      if (start > 0 && ws.owner[start] >= 0) start = AssociationTable::kDead;  // rare: fall back to dead
    }
    ws.current[i] = start;
    if (start > 0) ws.owner[start] = i;
  }
  samples.insert(samples.end(), ws.current.begin(), ws.current.end());
  FastUniform uniform(rng);
  for (int s = 0; s < sweeps; ++s) {
    for (int i = 0; i < P; ++i) {
      const int b = table.row_begin(i), e_end = table.row_end(i);
      if (e_end - b <= 1) continue;  // a single possible value
      double total = 0.0;
      for (int e = b; e < e_end; ++e) {
        const int c = table.column(e);
        const bool locked = c > 0 && ws.owner[c] >= 0 && ws.owner[c] != i;
        total += locked ? 0.0 : ws.eta[e];
      }
      if (!(total > 0.0)) continue;  // no valid choice: keep the current value
      double u = uniform() * total;
      int chosen = ws.current[i];
      for (int e = b; e < e_end; ++e) {
        const int c = table.column(e);
        const bool locked = c > 0 && ws.owner[c] >= 0 && ws.owner[c] != i;
        if (locked || ws.eta[e] <= 0.0) continue;
        chosen = c;
        u -= ws.eta[e];
        if (u < 0.0) break;
      }
      if (ws.current[i] > 0) ws.owner[ws.current[i]] = -1;
      ws.current[i] = chosen;
      if (chosen > 0) ws.owner[chosen] = i;
    }
    samples.insert(samples.end(), ws.current.begin(), ws.current.end());
  }
  return sweeps + 1;
}

int unique_solutions(std::vector<int>& samples, int row_count, int count) {
  if (row_count == 0) {
    samples.clear();
    return count > 0 ? 1 : 0;
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
  samples.assign(out.begin(), out.end());
  return distinct;
}

}  // namespace glmbslam::backend
