#pragma once
// Gibbs sampler for the δ-GLMB joint prediction/update (Vo, Vo & Hoang 2017; digest 0.2).
//
// An AssociationTable holds, for each row i (a surviving track or a birth), the sparse non-zero entries of
// η_i(·) in log space over the columns
//   kDead (= −1):   dead / not born            η_i(−1) = 1 − P̄_S  or  1 − r_B
//   kMissed (= 0):  alive and missed           η_i(0)  = P̄_S (or r_B) · (1 − p_D)
//   j ≥ 1:          alive and detected by z_j  η_i(j)  = P̄_S (or r_B) · p_D · N(z_j; ẑ, S) / κ(z_j)
// (1-based measurement columns as in Vo's toolbox). Gated-out entries are simply absent.
// The sampler draws γ ∈ {−1, 0, 1..M}^P with stationary distribution π(γ) ∝ Π_i η_i(γ_i) restricted to γ
// whose positive entries are distinct (a measurement is used at most once).
#include <cstdint>
#include <vector>

#include "core/random.hpp"

namespace glmbslam::backend {

class AssociationTable {
 public:
  static constexpr int kDead = -1;
  static constexpr int kMissed = 0;

  /// Empties the table (keeps capacity) for a problem with `num_measurements` measurements.
  void reset(int num_measurements) {
    num_measurements_ = num_measurements;
    row_start_.clear();
    row_start_.push_back(0);
    column_.clear();
    log_eta_.clear();
    eta_.clear();
    start_.clear();
    total_.clear();
  }
  /// Adds entry (column, log η) to the current (last) row. Entries with log η = −∞ may be skipped by callers.
  void add(int column, double log_eta) {
    column_.push_back(column);
    log_eta_.push_back(log_eta);
  }
  /// Closes the current row (and prepares it for sampling: η relative to the row maximum and the row's
  /// starting value); the next add() starts a new one.
  void end_row();

  int rows() const { return static_cast<int>(row_start_.size()) - 1; }
  int num_measurements() const { return num_measurements_; }
  int row_begin(int i) const { return row_start_[i]; }
  int row_end(int i) const { return row_start_[i + 1]; }
  int column(int e) const { return column_[e]; }
  double log_eta(int e) const { return log_eta_[e]; }
  /// exp(log η − the row's maximum) (0 for a row whose entries are all −∞).
  double eta(int e) const { return eta_[e]; }
  /// The sampler's initial value for row i: kMissed if the row has a non-zero missed entry (or no entry),
  /// otherwise the column of its best entry.
  int start(int i) const { return start_[i]; }
  /// Σ_e η(e) over row i (in entry order): the sampler's normaliser when none of its columns is taken.
  double total(int i) const { return total_[i]; }
  const int* column_data() const { return column_.data(); }
  const double* eta_data() const { return eta_.data(); }

  /// log Π_i η_i(γ_i) for an assignment (−∞ if some γ_i has no entry).
  double log_weight(const int* gamma) const;

 private:
  int num_measurements_ = 0;
  std::vector<int> row_start_{0};
  std::vector<int> column_;
  std::vector<double> log_eta_;
  std::vector<double> eta_;
  std::vector<int> start_;
  std::vector<double> total_;
};

/// Reusable buffers so that repeated sampling does not allocate.
struct GibbsWorkspace {
  std::vector<int> owner;    ///< per column c (at c + 1): the row using measurement c, or −1
  std::vector<int> current;  ///< current γ
  std::vector<int> rows;     ///< row ids (identity) for the whole-table overload
  std::vector<int> locked;   ///< per row: its measurement columns taken by another row
  std::vector<int> column_start, column_rows;  ///< per measurement column: the rows with an entry for it
};

/// Runs `sweeps` Gibbs sweeps starting from "all missed" (rows without a missed entry start at their best
/// entry) and appends the initial state and every sweep's γ (rows() ints each) to `samples`.
/// Returns the number of solutions appended (sweeps + 1). A table with zero rows yields one empty solution.
int gibbs_sample(const AssociationTable& table, int sweeps, RandomStream& rng, GibbsWorkspace& ws,
                 std::vector<int>& samples);

/// The same chain over the sub-table made of rows row_ids[0..num_rows) of `table` (in that order), so that
/// rows prepared once can be sampled for many subsets. γ is indexed by position in row_ids. With
/// skip_repeats, a sweep that leaves γ unchanged is not appended (it repeats the previous solution; the
/// distinct solutions and their first-occurrence order are unchanged); returns the number appended.
/// The random numbers drawn do not depend on skip_repeats.
int gibbs_sample(const AssociationTable& table, const int* row_ids, int num_rows, int sweeps,
                 RandomStream& rng, GibbsWorkspace& ws, std::vector<int>& samples, bool skip_repeats);

/// Removes duplicate solutions (each `row_count` ints, stored contiguously) in place, in an order that
/// depends only on the solutions; returns the number of distinct solutions.
int unique_solutions(std::vector<int>& samples, int row_count, int count);

}  // namespace glmbslam::backend
