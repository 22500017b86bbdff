#pragma once
// RFS maximum-likelihood SLAM (paper 004), solved as in digest 3.5 option B:
// maximise the log-likelihood of Eq. 8,
//   l(x_{1:k}, M) = Σ_{i=1}^k log g(x_i | x_{i−1}, u_i) + Σ_{i=0}^k log p(Z_i | x_i, M)      (Eq. 6–8)
// over the trajectory (x_0 held) and the landmark set M, associations summed out (Eq. 7,
// scan_likelihood.hpp), by expectation–maximisation:
//   E-step: marginal association probabilities β_mn^i at the current estimate (ranked assignments per
//           independent block of each scan);
//   M-step: Levenberg–Marquardt (Ceres) on Σ_i ‖x_i ⊖ f(x_{i−1}, u_i)‖²_{P̄} + Σ_i Σ_{m,n} β_mn^i ‖z_n −
//   ẑ(x_i,
//           m)‖²_R, whose gradient at the linearisation point equals ∇l (Eq. 17–18);
// and cardinality moves between rounds (births from unexplained measurements, deaths of landmarks detected
// far less often than p_D predicts, merges of close landmarks), each kept only if l rises (evaluated on the
// scans that see the landmark). A step that lowers l is undone and the solve stops.
//
// The model-specific parts (pose blocks and their Ceres manifold, factors, smooth p_D) come from `Parts`:
// PlanarMlSlamParts (ceres_factors_2d.hpp, 2D range-bearing) or StereoMlSlamParts (stereo_ml_slam.hpp, SE(3)
// poses and (u_L, v, u_R) measurements).
//
// association = "nearest_neighbour" is the vector ML baseline (Eq. 4): every measurement is assigned to the
// nearest landmark (Mahalanobis, within the gate), unassigned measurements become landmarks, and the
// objective is the least-squares cost; associations are re-made every round.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/StdVector>

#include "backend/mlslam/ceres_factors_2d.hpp"
#include "backend/mlslam/em_rounds.hpp"
#include "backend/mlslam/landmark_grid.hpp"
#include "backend/mlslam/m_step_linear_solver.hpp"
#include "backend/mlslam/ml_slam_report.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/mlslam/move_gains.hpp"
#include "backend/mlslam/scan_likelihood.hpp"
#include "backend/mlslam/scan_move_gain.hpp"
#include "backend/mlslam/smooth_detection.hpp"
#include "core/parallel.hpp"
#include "core/stopwatch.hpp"

namespace glmbslam::backend {

template <class Motion, class Model, class Parts = PlanarMlSlamParts<Motion, Model>>
class RfsMlSlam {
 public:
  using Pose = typename Model::Pose;
  using Control = typename Motion::Control;
  using Landmark = typename Model::Landmark;
  using Measurement = typename Model::Measurement;
  using PoseList = std::vector<Pose, Eigen::aligned_allocator<Pose>>;
  using LandmarkList = std::vector<Landmark, Eigen::aligned_allocator<Landmark>>;
  using MeasurementSet = std::vector<Measurement, Eigen::aligned_allocator<Measurement>>;
  using ControlList = std::vector<Control, Eigen::aligned_allocator<Control>>;

  /// Throws ConfigError on an invalid config.
  RfsMlSlam(const Motion& motion, const Model& model, const MlSlamConfig& config)
      : motion_(motion), model_(model), config_(config), p_D_(Parts::detection(model, config)) {
    validate_mlslam_config(config_);
    const double scale = Parts::length_scale(model);
    if (config_.birth_radius_m <= 0.0) config_.birth_radius_m = 10.0 * scale;
    if (config_.merge_distance_m <= 0.0) config_.merge_distance_m = 10.0 * scale;
  }

  /// A predicate asked before every EM round (and, standalone, before every new stretch of steps): when it
  /// says true the solve ends with the last completed round's estimate and MlSlamReport::stopped (an
  /// interrupted run keeps what the rounds so far gained). Empty = never.
  void set_stop(std::function<bool()> stop) { stop_ = std::move(stop); }

  /// Called by solve_from_odometry after each increment with (steps solved, all steps, landmarks). Empty =
  /// none.
  void set_progress(std::function<void(std::size_t, std::size_t, std::size_t)> progress) {
    progress_ = std::move(progress);
  }

  /// Refines `poses` (x_0..x_K; x_0 held) and `map` in place. controls[k] drives x_{k−1} to x_k (controls[0]
  /// unused); scans[k] = Z_k. Returns the solve's statistics.
  MlSlamReport solve(PoseList& poses, const ControlList& controls, const std::vector<MeasurementSet>& scans,
                     LandmarkList& map) const {
    check_sizes(poses, controls, scans);
    Stopwatch watch;
    State s{poses, map, {}, {}};
    // the noise scale of the starting trajectory (its ML value there), before the first M-step
    if (estimates_motion_noise()) s.motion_scale = estimate_motion_scale(s.poses, controls);
    MlSlamReport report;
    auto timed_e_step = [&](State& state) {
      Stopwatch e;
      e_step(state, controls, scans);
      report.e_step_ms += e.elapsed_ms();
    };
    run_em_rounds(
        s, config_, nearest_neighbour(), timed_e_step,
        [&](State& next) {
          Stopwatch m;
          m_step(next, controls, scans);
          report.m_step_ms += m.elapsed_ms();
          if (nearest_neighbour()) add_unassigned_as_landmarks(next, scans);
        },
        blend_towards<Motion, State>,
        [&](State& state) {
          if (!config_.cardinality_moves || nearest_neighbour()) return 0;
          Stopwatch c;
          const int accepted = cardinality_moves(state, scans, report);
          report.moves_ms += c.elapsed_ms();
          return accepted;
        },
        stop_, report);
    report.ms = watch.elapsed_ms();
    report.motion_scale = s.motion_scale;
    poses = std::move(s.poses);
    map = std::move(s.map);
    return report;
  }

  /// Standalone (paper 004's setting): the trajectory initialised by dead reckoning from x_0, the map from
  /// the measurements (births). With config.incremental_steps > 0 the problem grows by that many steps at a
  /// time, each new stretch of trajectory dead-reckoned from the last refined pose; with
  /// config.incremental_window > 0 each increment solves only its last steps (solve_window) and one solve of
  /// the whole problem follows.
  MlSlamReport solve_from_odometry(const Pose& x0, const ControlList& controls,
                                   const std::vector<MeasurementSet>& scans, PoseList& poses,
                                   LandmarkList& map) const {
    const std::size_t K = scans.size();
    poses.assign(1, x0);
    map.clear();
    if (nearest_neighbour()) initial_map_from_scan(x0, scans.front(), map);
    const std::size_t chunk = config_.incremental_steps > 0
                                  ? static_cast<std::size_t>(config_.incremental_steps)
                                  : std::max<std::size_t>(K, 1);
    const std::size_t window = config_.incremental_window > 0 && config_.incremental_steps > 0
                                   ? static_cast<std::size_t>(config_.incremental_window)
                                   : std::max<std::size_t>(K, 1);
    MlSlamReport total;
    auto add = [&](const MlSlamReport& r) {
      if (total.rounds == 0) total.initial_log_likelihood = r.initial_log_likelihood;
      total.rounds += r.rounds;
      total.births += r.births;
      total.deaths += r.deaths;
      total.merges += r.merges;
      total.final_log_likelihood = r.final_log_likelihood;
      total.motion_scale = r.motion_scale;
      total.stopped = r.stopped;
      total.log_likelihood_per_round.insert(total.log_likelihood_per_round.end(),
                                            r.log_likelihood_per_round.begin(),
                                            r.log_likelihood_per_round.end());
    };
    Stopwatch watch;
    for (std::size_t end = std::min(K, chunk + 1);; end = std::min(K, end + chunk)) {
      while (poses.size() < end)
        poses.push_back(initial_pose(poses.back(), controls[poses.size()], scans[poses.size()], map));
      add(solve_window(end > window ? end - window : 0, end, poses, controls, scans, map));
      if (progress_) progress_(end, K, map.size());
      if (end == K || total.stopped || (stop_ && stop_())) {
        total.stopped = total.stopped || end < K;  // poses then holds steps 0..end−1 only
        break;
      }
    }
    // after windows: the whole problem once, from the windows' estimate
    if (window < K && !total.stopped && !(stop_ && stop_())) add(solve(poses, controls, scans, map));
    total.ms = watch.elapsed_ms();
    return total;
  }

  /// Solves steps first..end−1 of `poses` (x_first held) on their scans, with the landmarks any of them may
  /// see; the other landmarks and the poses outside the window are kept as they are.
  MlSlamReport solve_window(std::size_t first, std::size_t end, PoseList& poses, const ControlList& controls,
                            const std::vector<MeasurementSet>& scans, LandmarkList& map) const {
    PoseList x(poses.begin() + static_cast<std::ptrdiff_t>(first),
               poses.begin() + static_cast<std::ptrdiff_t>(end));
    const ControlList u(controls.begin() + static_cast<std::ptrdiff_t>(first),
                        controls.begin() + static_cast<std::ptrdiff_t>(end));  // u[0] unused: x_first held
    const std::vector<MeasurementSet> z(scans.begin() + static_cast<std::ptrdiff_t>(first),
                                        scans.begin() + static_cast<std::ptrdiff_t>(end));
    LandmarkList inside, outside;
    for (const auto& m : map) {
      const bool seen =
          first == 0 || std::any_of(x.begin(), x.end(), [&](const Pose& p) { return maybe_in_view(p, m); });
      (seen ? inside : outside).push_back(m);
    }
    const MlSlamReport r = solve(x, u, z, inside);
    std::copy(x.begin(), x.end(), poses.begin() + static_cast<std::ptrdiff_t>(first));
    map = std::move(outside);
    map.insert(map.end(), inside.begin(), inside.end());
    return r;
  }

  /// Where solve_from_odometry starts a new pose: the dead-reckoned f(x_prev, u), or with
  /// MlSlamConfig::initial_pose_search = n the best point of an n^d grid over ±3σ of the motion noise by
  /// log g(x | x_prev, u) + log p(Z | x, M).
  Pose initial_pose(const Pose& prev, const Control& u, const MeasurementSet& Z,
                    const LandmarkList& map) const {
    const Pose mean = motion_.predict(prev, u);
    const int n = config_.initial_pose_search;
    if (n < 2 || map.empty() || Z.empty()) return mean;
    using Tangent = typename Motion::Tangent;
    constexpr int d = Tangent::RowsAtCompileTime;
    const auto P = motion_.process_noise(prev, u);
    const typename Motion::Covariance L = P.llt().matrixL();
    const Grid grid = grid_of(map);
    ScanLikelihoodOptions o = scan_options();
    o.marginals = false;
    auto score = [&](const Pose& x, const Tangent& t) {
      return -0.5 * t.squaredNorm() +
             evaluate_scan(model_, p_D_, x, gather(map, candidates_of(x, map, grid)), Z, o).log_likelihood;
    };
    Pose best = mean;
    double best_score = score(mean, Tangent::Zero());
    long long total = 1;
    for (int i = 0; i < d; ++i) total *= n;
    for (long long idx = 0; idx < total; ++idx) {
      Tangent t;
      long long rest = idx;
      for (int i = 0; i < d; ++i, rest /= n) t(i) = -3.0 + 6.0 * static_cast<double>(rest % n) / (n - 1);
      const Pose x = Motion::retract(mean, L * t);
      const double l = score(x, t);
      if (l > best_score) best_score = l, best = x;
    }
    return best;
  }

  /// l of Eq. 8 (RFS) at the given estimate; for nearest_neighbour, −½ of the vector cost of Eq. 4.
  double log_likelihood(const PoseList& poses, const ControlList& controls,
                        const std::vector<MeasurementSet>& scans, const LandmarkList& map) const {
    check_sizes(poses, controls, scans);
    State s{poses, map, {}, {}};
    e_step(s, controls, scans);
    return s.log_likelihood;
  }

  /// log p(Z | x, M) of one scan (Eq. 7) with the solver's p_D and truncation.
  double scan_log_likelihood(const Pose& x, const MeasurementSet& Z, const LandmarkList& map) const {
    ScanLikelihoodOptions o = scan_options();
    o.marginals = false;
    return evaluate_scan(model_, p_D_, x, map, Z, o).log_likelihood;
  }

  const typename Parts::Detection& detection() const { return p_D_; }

  /// log g(x_i | x_{i−1}, u_i) with the noise s·Q: log N(r; 0, Q) + ½ m (1 − 1/s) − ½ d log s, m = rᵀQ⁻¹r.
  double motion_log_density(const Pose& prev, const Pose& cur, const Control& u, double scale) const {
    const double l = motion_.log_density(cur, prev, u);
    if (scale == 1.0) return l;
    const double m = whitened_motion(prev, cur, u).squaredNorm();
    const double d = static_cast<double>(Motion::Tangent::RowsAtCompileTime);
    return l + 0.5 * m * (1.0 - 1.0 / scale) - 0.5 * d * std::log(scale);
  }

  /// The ML motion-noise scale at the current trajectory, s = Σ rᵀQ⁻¹r / (d·K) (MlSlamConfig::motion_noise),
  /// kept within [1e-4, 1e4].
  double estimate_motion_scale(const PoseList& poses, const ControlList& controls) const {
    double sum = 0.0;
    for (std::size_t i = 1; i < poses.size(); ++i)
      sum += whitened_motion(poses[i - 1], poses[i], controls[i]).squaredNorm();
    const double n = static_cast<double>(Motion::Tangent::RowsAtCompileTime) *
                     static_cast<double>(poses.size() > 1 ? poses.size() - 1 : 1);
    return std::clamp(sum / n, 1e-4, 1e4);
  }

 private:
  using State = EmState<PoseList, LandmarkList>;
  using ScanState = typename State::Scan;

  bool nearest_neighbour() const { return config_.association == "nearest_neighbour"; }
  /// MlSlamConfig::motion_noise "estimated" (the vector baseline keeps its unit-weight cost)
  bool estimates_motion_noise() const { return config_.motion_noise == "estimated" && !nearest_neighbour(); }

  ScanLikelihoodOptions scan_options() const {
    ScanLikelihoodOptions o;
    o.gate = config_.gate;
    o.max_assignments = config_.max_assignments;
    o.assignment_log_gap = config_.assignment_log_gap;
    return o;
  }

  static void check_sizes(const PoseList& poses, const ControlList& controls,
                          const std::vector<MeasurementSet>& scans) {
    if (poses.empty() || poses.size() != scans.size() || controls.size() != scans.size()) {
      throw std::invalid_argument("RfsMlSlam: poses, controls and scans must have the same non-zero length");
    }
  }

  bool maybe_in_view(const Pose& x, const Landmark& m) const { return p_D_.maybe_in_view(model_, x, m); }

  using Grid = LandmarkGrid<decltype(Model::landmark_position(std::declval<Landmark>()))::RowsAtCompileTime>;

  /// The voxel hash of the map's landmarks, cells of half the detection model's query radius.
  Grid grid_of(const LandmarkList& map) const {
    return Grid(
        map.size(), [&](std::size_t j) { return Model::landmark_position(map[j]); },
        0.5 * p_D_.query_radius());
  }

  /// The landmarks (map indices, ascending) that p_D may see from x.
  std::vector<int> candidates_of(const Pose& x, const LandmarkList& map, const Grid& grid) const {
    return grid.near_if(Model::position(x), p_D_.query_radius(),
                        [&](int j) { return maybe_in_view(x, map[static_cast<std::size_t>(j)]); });
  }

  LandmarkList gather(const LandmarkList& map, const std::vector<int>& ids) const {
    LandmarkList out;
    out.reserve(ids.size());
    for (int j : ids) out.push_back(map[static_cast<std::size_t>(j)]);
    return out;
  }

  /// β and l at the current estimate (parallel over scans; each scan writes only its own slot).
  void e_step(State& s, const ControlList& controls, const std::vector<MeasurementSet>& scans) const {
    const std::size_t K = scans.size();
    s.scans.assign(K, {});
    s.motion_ll.assign(K, 0.0);
    const ScanLikelihoodOptions o = scan_options();
    const Grid grid = grid_of(s.map);
    parallel_for(K, [&](std::size_t i) {
      ScanState& ss = s.scans[i];
      ss.candidates = candidates_of(s.poses[i], s.map, grid);
      if (nearest_neighbour()) {
        ss.association = nearest_neighbour_scan(s.poses[i], gather(s.map, ss.candidates), scans[i]);
      } else {
        ss.association = evaluate_scan(model_, p_D_, s.poses[i], gather(s.map, ss.candidates), scans[i], o);
      }
      if (i > 0) {
        s.motion_ll[i] = nearest_neighbour()
                             ? -0.5 * whitened_motion(s.poses[i - 1], s.poses[i], controls[i]).squaredNorm()
                             : motion_log_density(s.poses[i - 1], s.poses[i], controls[i], s.motion_scale);
      }
    });
    s.log_likelihood = 0.0;
    for (std::size_t i = 0; i < K; ++i)
      s.log_likelihood += s.motion_ll[i] + s.scans[i].association.log_likelihood;
  }

  typename Motion::Tangent whitened_motion(const Pose& prev, const Pose& cur, const Control& u) const {
    return whitening(motion_.process_noise(prev, u)) * Motion::local(cur, motion_.predict(prev, u));
  }

  /// Vector baseline: each measurement to its nearest gated landmark (β = 1); l = −½ Σ ‖r‖² (Eq. 4).
  ScanAssociation nearest_neighbour_scan(const Pose& x, const LandmarkList& M,
                                         const MeasurementSet& Z) const {
    ScanAssociation out;
    out.p_detect.assign(M.size(), 1.0);
    for (std::size_t j = 0; j < Z.size(); ++j) {
      int best = -1;
      double best_d = config_.gate;
      for (std::size_t p = 0; p < M.size(); ++p) {
        const double d = mahalanobis_squared(model_.residual(Z[j], model_.predict(x, M[p])), model_.noise());
        if (d <= best_d) best_d = d, best = static_cast<int>(p);
      }
      if (best < 0) continue;
      out.betas.push_back({best, static_cast<int>(j), 1.0});
      out.log_likelihood -= 0.5 * best_d;
    }
    return out;
  }

  void initial_map_from_scan(const Pose& x, const MeasurementSet& Z, LandmarkList& map) const {
    for (const auto& z : Z) map.push_back(inverse(x, z));
  }

  Landmark inverse(const Pose& x, const Measurement& z) const {
    Landmark m;
    typename Model::LandmarkCovariance P;
    model_.initialize(x, z, &m, &P);
    return m;
  }

  /// Vector baseline: a measurement no landmark explains (none within the gate, new landmarks included)
  /// becomes a landmark, scan by scan (the usual map initialisation).
  void add_unassigned_as_landmarks(State& s, const std::vector<MeasurementSet>& scans) const {
    for (std::size_t i = 0; i < scans.size(); ++i) {
      std::vector<char> used(scans[i].size(), 0);
      for (const auto& b : s.scans[i].association.betas) used[static_cast<std::size_t>(b.measurement)] = 1;
      for (std::size_t j = 0; j < scans[i].size(); ++j) {
        if (used[j] != 0) continue;
        bool explained = false;
        for (const auto& m : s.map) {
          const auto r = model_.residual(scans[i][j], model_.predict(s.poses[i], m));
          explained = explained || mahalanobis_squared(r, model_.noise()) <= config_.gate;
        }
        if (!explained) s.map.push_back(inverse(s.poses[i], scans[i][j]));
      }
    }
  }

  /// One M-step: LM on the motion factors and the β-weighted measurement factors.
  void m_step(State& s, const ControlList& controls, const std::vector<MeasurementSet>& scans) const {
    const std::size_t K = scans.size();
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.disable_all_safety_checks = true;  // each block is added once, by construction
    ceres::Problem problem(po);
    constexpr int B = Parts::kBlockSize;
    std::vector<double> blocks(K * B);
    auto block = [&](std::size_t i) { return blocks.data() + i * B; };
    for (std::size_t i = 0; i < K; ++i) Parts::to_block(s.poses[i], block(i));
    for (std::size_t i = 1; i < K; ++i) {
      const auto W = whitening(motion_.process_noise(s.poses[i - 1], controls[i]));
      problem.AddResidualBlock(Parts::motion_factor(motion_, controls[i], W, s.poses[i - 1], s.motion_scale),
                               nullptr, block(i - 1), block(i));
    }
    const auto W_R = whitening(model_.noise());
    for (std::size_t i = 0; i < K; ++i) {
      const ScanState& ss = s.scans[i];
      for (const auto& b : ss.association.betas) {
        if (b.beta < config_.min_responsibility) continue;
        Landmark& m = s.map[static_cast<std::size_t>(ss.candidates[static_cast<std::size_t>(b.landmark)])];
        problem.AddResidualBlock(
            Parts::measurement_factor(model_, scans[i][static_cast<std::size_t>(b.measurement)], W_R, b.beta),
            nullptr, block(i), m.data());
      }
    }
    for (std::size_t i = 0; i < K; ++i) {
      if (!problem.HasParameterBlock(block(i))) continue;
      problem.SetManifold(block(i), &manifold_);
    }
    if (!problem.HasParameterBlock(block(0))) return;
    problem.SetParameterBlockConstant(block(0));
    ceres::Solver::Options so;
    so.linear_solver_type = m_step_linear_solver(config_, K);
    if (so.linear_solver_type != ceres::SPARSE_NORMAL_CHOLESKY) {
      // bundle-adjustment shape: the landmarks (group 0) are eliminated first; the ordering is given, not
      // searched for
      auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
      for (auto& m : s.map)
        if (problem.HasParameterBlock(m.data())) ordering->AddElementToGroup(m.data(), 0);
      for (std::size_t i = 0; i < K; ++i)
        if (problem.HasParameterBlock(block(i))) ordering->AddElementToGroup(block(i), 1);
      so.linear_solver_ordering = ordering;
      so.preconditioner_type = ceres::SCHUR_JACOBI;
    }
    so.max_num_iterations = config_.solver_iterations;
    so.initial_trust_region_radius = config_.initial_trust_region_radius;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    for (std::size_t i = 1; i < K; ++i) s.poses[i] = Parts::from_block(block(i));
    // the conditional M-step of the noise scale given the new trajectory (raises l again)
    if (estimates_motion_noise()) s.motion_scale = estimate_motion_scale(s.poses, controls);
  }

  // ---- cardinality moves -------------------------------------------------------------------------------

  /// Δl of replacing the landmarks `removed` (map indices) by `added` on the scans that see any of them.
  double move_gain(const State& s, const std::vector<MeasurementSet>& scans, const std::vector<int>& removed,
                   const LandmarkList& added, std::vector<std::size_t>* affected) const {
    affected->clear();
    for (std::size_t i = 0; i < scans.size(); ++i) {
      bool touched = false;
      for (const auto& m : added) touched = touched || maybe_in_view(s.poses[i], m);
      for (int r : removed)
        touched = touched || maybe_in_view(s.poses[i], s.map[static_cast<std::size_t>(r)]);
      if (touched) affected->push_back(i);
    }
    ScanLikelihoodOptions o = scan_options();
    o.marginals = false;
    double gain = 0.0;
    // per scan, only the blocks the move touches (scan_move_gain.hpp), in parallel; summed in scan order
    std::vector<double> gains(affected->size(), 0.0);
    parallel_for(affected->size(), [&](std::size_t a) {
      const std::size_t i = (*affected)[a];
      const std::vector<int>& candidates = s.scans[i].candidates;
      std::vector<int> at;  // positions of the removed landmarks in the scan's candidate list
      for (int r : removed) {
        const auto it = std::find(candidates.begin(), candidates.end(), r);
        if (it != candidates.end()) at.push_back(static_cast<int>(it - candidates.begin()));
      }
      LandmarkList in_view;
      for (const auto& m : added)
        if (maybe_in_view(s.poses[i], m)) in_view.push_back(m);
      gains[a] =
          scan_move_gain(model_, p_D_, s.poses[i], gather(s.map, candidates), at, in_view, scans[i], o);
    });
    for (double g : gains) gain += g;
    return gain;
  }

  /// An upper bound on the Δl of adding the landmark a (move_gains.hpp).
  double birth_gain_bound(const State& s, const std::vector<MeasurementSet>& scans,
                          const GatedDensity<Model>& g, const Landmark& a) const {
    double bound = 0.0;
    for (std::size_t i = 0; i < scans.size(); ++i)
      if (maybe_in_view(s.poses[i], a))
        bound += log_birth_ratio_bound(model_, p_D_, g, s.poses[i], a, scans[i]);
    return bound;
  }

  /// Applies an accepted move: removed landmarks are marked dead (NaN) until compaction; the affected scans'
  /// E-step entries are recomputed.
  void apply_move(State& s, const std::vector<MeasurementSet>& scans, const std::vector<int>& removed,
                  const LandmarkList& added, const std::vector<std::size_t>& affected) const {
    for (int r : removed) s.map[static_cast<std::size_t>(r)].setConstant(std::nan(""));
    for (const auto& m : added) s.map.push_back(m);
    const ScanLikelihoodOptions o = scan_options();
    for (std::size_t i : affected) {
      ScanState& ss = s.scans[i];
      s.log_likelihood -= ss.association.log_likelihood;
      ss.candidates.clear();
      for (std::size_t j = 0; j < s.map.size(); ++j)
        if (s.map[j].allFinite() && maybe_in_view(s.poses[i], s.map[j]))
          ss.candidates.push_back(static_cast<int>(j));
      ss.association = evaluate_scan(model_, p_D_, s.poses[i], gather(s.map, ss.candidates), scans[i], o);
      s.log_likelihood += ss.association.log_likelihood;
    }
  }

  int cardinality_moves(State& s, const std::vector<MeasurementSet>& scans, MlSlamReport& report) const {
    int accepted = 0;
    std::vector<std::size_t> affected;
    // deaths: landmarks detected far less often than p_D predicts
    std::vector<double> detected(s.map.size(), 0.0), expected(s.map.size(), 0.0);
    for (const auto& ss : s.scans) {
      for (std::size_t p = 0; p < ss.candidates.size(); ++p)
        expected[static_cast<std::size_t>(ss.candidates[p])] += ss.association.p_detect[p];
      for (const auto& b : ss.association.betas)
        detected[static_cast<std::size_t>(ss.candidates[static_cast<std::size_t>(b.landmark)])] += b.beta;
    }
    const std::size_t M0 = s.map.size();
    for (std::size_t j = 0; j < M0; ++j) {
      if (detected[j] >= config_.death_ratio * expected[j]) continue;
      const std::vector<int> removed{static_cast<int>(j)};
      if (move_gain(s, scans, removed, {}, &affected) > 0.0) {
        apply_move(s, scans, removed, {}, affected);
        ++report.deaths;
        ++accepted;
      }
    }
    // merges: landmarks closer than merge_distance, replaced by their detection-weighted mean
    for (std::size_t a = 0; a < M0; ++a) {
      for (std::size_t b = a + 1; b < M0; ++b) {
        if (!s.map[a].allFinite() || !s.map[b].allFinite()) continue;
        if ((Model::landmark_position(s.map[a]) - Model::landmark_position(s.map[b])).norm() >
            config_.merge_distance_m)
          continue;
        const double wa = detected[a] + 1e-9, wb = detected[b] + 1e-9;
        const LandmarkList merged{(wa * s.map[a] + wb * s.map[b]) / (wa + wb)};
        const std::vector<int> removed{static_cast<int>(a), static_cast<int>(b)};
        if (move_gain(s, scans, removed, merged, &affected) > 0.0) {
          apply_move(s, scans, removed, merged, affected);
          ++report.merges;
          ++accepted;
        }
      }
    }
    // births: clusters of unexplained measurements
    const GatedDensity<Model> g(model_, config_.gate);
    for (const Landmark& m : birth_candidates(s, scans)) {
      if (!(birth_gain_bound(s, scans, g, m) > 0.0)) continue;  // Δl ≤ bound ≤ 0: no birth
      const LandmarkList added{m};
      if (move_gain(s, scans, {}, added, &affected) > 0.0) {
        apply_move(s, scans, {}, added, affected);
        ++report.births;
        ++accepted;
      }
    }
    if (accepted > 0) compact(s);
    return accepted;
  }

  /// Unexplained measurements (clutter responsibility 1 − Σ_m β_mn ≥ birth_responsibility) mapped through the
  /// inverse model and clustered greedily on a grid of birth_radius cells; clusters with enough support,
  /// most supported first.
  LandmarkList birth_candidates(const State& s, const std::vector<MeasurementSet>& scans) const {
    struct Cluster {
      Landmark sum;
      int count = 0;
      Landmark mean() const { return sum / static_cast<double>(count); }
    };
    std::vector<Cluster> clusters;
    std::unordered_map<long long, std::vector<int>> grid;
    const double cell = std::max(config_.birth_radius_m, 1e-9);
    auto key = [&](long long cx, long long cy) { return cx * 1000003LL + cy; };
    for (std::size_t i = 0; i < scans.size(); ++i) {
      std::vector<double> explained(scans[i].size(), 0.0);
      for (const auto& b : s.scans[i].association.betas)
        explained[static_cast<std::size_t>(b.measurement)] += b.beta;
      for (std::size_t j = 0; j < scans[i].size(); ++j) {
        if (1.0 - explained[j] < config_.birth_responsibility) continue;
        const Landmark m = inverse(s.poses[i], scans[i][j]);
        const auto q = Model::landmark_position(m);
        const long long cx = static_cast<long long>(std::floor(q(0) / cell));
        long long cy = 0;  // the cells are squares in the plane (intervals on the line)
        if constexpr (std::decay_t<decltype(q)>::RowsAtCompileTime >= 2)
          cy = static_cast<long long>(std::floor(q(1) / cell));
        int best = -1;
        double best_d = config_.birth_radius_m;
        for (long long dx = -1; dx <= 1; ++dx)
          for (long long dy = -1; dy <= 1; ++dy) {
            const auto it = grid.find(key(cx + dx, cy + dy));
            if (it == grid.end()) continue;
            for (int c : it->second) {
              const double d = (Model::landmark_position(clusters[static_cast<std::size_t>(c)].mean()) -
                                Model::landmark_position(m))
                                   .norm();
              if (d < best_d || (d == best_d && c < best)) best_d = d, best = c;
            }
          }
        if (best < 0) {
          grid[key(cx, cy)].push_back(static_cast<int>(clusters.size()));
          clusters.push_back({m, 1});
        } else {
          clusters[static_cast<std::size_t>(best)].sum += m;
          ++clusters[static_cast<std::size_t>(best)].count;
        }
      }
    }
    std::vector<std::size_t> order(clusters.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return clusters[a].count > clusters[b].count; });
    LandmarkList out;
    for (std::size_t c : order)
      if (clusters[c].count >= config_.birth_min_support) out.push_back(clusters[c].mean());
    return out;
  }

  /// Removes the dead landmarks and renumbers the scans' candidate lists.
  static void compact(State& s) {
    std::vector<int> new_index(s.map.size(), -1);
    LandmarkList kept;
    for (std::size_t j = 0; j < s.map.size(); ++j) {
      if (!s.map[j].allFinite()) continue;
      new_index[j] = static_cast<int>(kept.size());
      kept.push_back(s.map[j]);
    }
    s.map = std::move(kept);
    for (auto& ss : s.scans)
      for (int& c : ss.candidates) c = new_index[static_cast<std::size_t>(c)];
  }

  Motion motion_;
  Model model_;
  MlSlamConfig config_;
  typename Parts::Detection p_D_;
  std::function<void(std::size_t, std::size_t, std::size_t)> progress_;
  std::function<bool()> stop_;
  mutable typename Parts::Manifold manifold_;
};

}  // namespace glmbslam::backend
