#include "backend/glmb/gibbs_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/log_math.hpp"

namespace glmbslam::backend {

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
  for (int s = 0; s < sweeps; ++s) {
    for (int i = 0; i < P; ++i) {
      const int b = table.row_begin(i), e_end = table.row_end(i);
      double total = 0.0;
      for (int e = b; e < e_end; ++e) {
        const int c = table.column(e);
        const bool locked = c > 0 && ws.owner[c] >= 0 && ws.owner[c] != i;
        total += locked ? 0.0 : ws.eta[e];
      }
      if (!(total > 0.0)) continue;  // no valid choice: keep the current value
      double u = rng.uniform() * total;
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
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](int a, int b) {
    return std::lexicographical_compare(
        samples.begin() + a * row_count, samples.begin() + (a + 1) * row_count,
        samples.begin() + b * row_count, samples.begin() + (b + 1) * row_count);
  };
  auto equal = [&](int a, int b) {
    return std::equal(samples.begin() + a * row_count, samples.begin() + (a + 1) * row_count,
                      samples.begin() + b * row_count);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> out;
  out.reserve(samples.size());
  int distinct = 0;
  for (int k = 0; k < count; ++k) {
    if (k > 0 && equal(order[k], order[k - 1])) continue;
    out.insert(out.end(), samples.begin() + order[k] * row_count,
               samples.begin() + (order[k] + 1) * row_count);
    ++distinct;
  }
  samples.swap(out);
  return distinct;
}

}  // namespace glmbslam::backend
