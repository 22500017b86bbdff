#pragma once
// The M-step of the stereo EM (paper 004 Eq. 17–18 as weighted least squares, digest 3.5 option B) as one
// ceres::Problem kept for a whole solve: the pose blocks, the motion factors W (x_i ⊖ f(x_{i−1}, u_i)) (Eq.
// 2; Q depends on the control only) and one StereoPairFactor per (pose, landmark) pair that the E-step ever
// associated are added once; each round only resets the pairs' weights (z̄, B) from the new β. Pairs the
// E-step no longer associates keep B = 0 (no cost, no gradient), new pairs are added. This saves rebuilding
// and freeing ~10⁶ residual blocks every round; Ceres still preprocesses each Solve.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Core>
#include <Eigen/StdVector>

#include "backend/mlslam/ceres_factors_3d.hpp"
#include "backend/mlslam/m_step_linear_solver.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/mlslam/stereo_fill_reducing_ordering.hpp"
#include "backend/models/se3_motion.hpp"
#include "backend/models/stereo_measurement_model.hpp"
#include "core/gaussian.hpp"

namespace glmbslam::backend {

class StereoMStepProblem {
 public:
  using PoseList = std::vector<Pose3, Eigen::aligned_allocator<Pose3>>;
  using LandmarkList = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;
  using ControlList = std::vector<RelativePoseControl, Eigen::aligned_allocator<RelativePoseControl>>;

  /// controls[k] drives x_{k−1} to x_k (controls[0] unused); `landmarks` is the map's size (fixed for the
  /// problem's life). Levenberg–Marquardt with config.solver_iterations iterations per solve and the linear
  /// solver of config.linear_solver (as RfsMlSlam's M-step).
  StereoMStepProblem(const Se3Motion& motion, const StereoMeasurementModel& model,
                     const ControlList& controls, std::size_t landmarks, const MlSlamConfig& config)
      : context_{model.camera(), whitening(model.noise())},
        problem_(problem_options()),
        poses_(controls.size() * kPose3BlockSize),
        landmarks_(landmarks * 3),
        pairs_of_scan_(controls.size()) {
    const std::size_t K = controls.size();
    for (std::size_t i = 0; i < K; ++i) problem_.AddParameterBlock(pose(i), kPose3BlockSize, &manifold_);
    if (K > 0) problem_.SetParameterBlockConstant(pose(0));
    for (std::size_t i = 1; i < K; ++i) {
      const Pose3 any = Pose3::Identity();  // Se3Motion's Q depends on the control only
      problem_.AddResidualBlock(
          make_relative_pose_factor(controls[i].delta, whitening(motion.process_noise(any, controls[i]))),
          nullptr, pose(i - 1), pose(i));
    }
    options_.linear_solver_type = m_step_linear_solver(config, K);
    options_.max_num_iterations = config.solver_iterations;
    options_.initial_trust_region_radius = config.initial_trust_region_radius;
    options_.num_threads = 1;
    options_.logging_type = ceres::SILENT;
  }

  /// Starts a new round's weights: every pair to B = 0.
  void clear_weights() {
    for (auto& s : sums_) s.setZero();
  }

  /// Adds β z_n to the pair (pose i, landmark j) (Eq. 18's weighted measurement).
  void add(std::size_t i, int j, const Eigen::Vector3d& z, double beta) {
    Eigen::Vector4d& s = sums_[pair_index(i, j)];
    s.head<3>() += beta * z;
    s(3) += beta;
  }

  /// Levenberg–Marquardt from (poses, map) on the weights added since clear_weights(); writes the result
  /// back (x_0 held).
  void solve(PoseList& poses, LandmarkList& map) {
    for (std::size_t p = 0; p < factors_.size(); ++p) {
      const double B = sums_[p](3);
      factors_[p]->set(B > 0.0 ? Eigen::Vector3d(sums_[p].head<3>() / B) : Eigen::Vector3d::Zero(), B);
    }
    for (std::size_t i = 0; i < poses.size(); ++i) pose3_to_block(poses[i], pose(i));
    for (std::size_t j = 0; j < map.size(); ++j) Eigen::Map<Eigen::Vector3d>{landmark(j)} = map[j];
    if (factors_.empty()) return;  // no measurement factor: the motion factors hold at the start
    ceres::Solver::Options o = options_;
    if (o.linear_solver_type == ceres::SPARSE_NORMAL_CHOLESKY) {
      // the nested dissection order, recomputed when pairs were added
      if (ordered_pairs_ != factors_.size()) {
        fill_reducing_ordering_ = nested_dissection_ordering(poses.size(), map.size());
        ordered_pairs_ = factors_.size();
      }
      o.linear_solver_ordering = fill_reducing_ordering_;
    } else {
      // bundle-adjustment shape: the landmarks (group 0) are eliminated first
      auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
      for (std::size_t j = 0; j < map.size(); ++j)
        if (problem_.HasParameterBlock(landmark(j))) ordering->AddElementToGroup(landmark(j), 0);
      for (std::size_t i = 0; i < poses.size(); ++i) ordering->AddElementToGroup(pose(i), 1);
      o.linear_solver_ordering = ordering;
      o.preconditioner_type = ceres::SCHUR_JACOBI;
    }
    ceres::Solver::Summary summary;
    ceres::Solve(o, &problem_, &summary);
    for (std::size_t i = 1; i < poses.size(); ++i) poses[i] = pose3_from_block(pose(i));
    for (std::size_t j = 0; j < map.size(); ++j)
      if (problem_.HasParameterBlock(landmark(j))) map[j] = Eigen::Map<const Eigen::Vector3d>(landmark(j));
  }

  /// Measurement factors in the problem (pairs associated in some round so far).
  std::size_t pairs() const { return factors_.size(); }

 private:
  static ceres::Problem::Options problem_options() {
    ceres::Problem::Options o;
    o.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    o.disable_all_safety_checks = true;  // each block is added once, by construction
    return o;
  }

  /// Every parameter block of the problem in its own elimination group, in nested dissection order of the
  /// normal equations' block graph (poses 0..K−1, then landmarks K + j; motion and pair factors as edges).
  std::shared_ptr<ceres::ParameterBlockOrdering> nested_dissection_ordering(std::size_t K, std::size_t M) {
    std::vector<std::vector<int>> adjacency(K + M);
    for (std::size_t i = 0; i < K; ++i) {
      if (i > 0)
        adjacency[i].push_back(static_cast<int>(i - 1)), adjacency[i - 1].push_back(static_cast<int>(i));
      for (const auto& pair : pairs_of_scan_[i]) {
        adjacency[i].push_back(static_cast<int>(K) + pair.first);
        adjacency[K + static_cast<std::size_t>(pair.first)].push_back(static_cast<int>(i));
      }
    }
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    int group = 0;
    for (int b : nested_dissection_order(adjacency)) {
      const auto node = static_cast<std::size_t>(b);
      double* block = node < K ? pose(node) : landmark(node - K);
      if (problem_.HasParameterBlock(block)) ordering->AddElementToGroup(block, group++);
    }
    return ordering;
  }

  double* pose(std::size_t i) { return poses_.data() + i * kPose3BlockSize; }
  double* landmark(int j) { return landmarks_.data() + static_cast<std::size_t>(j) * 3; }
  double* landmark(std::size_t j) { return landmarks_.data() + j * 3; }

  /// The pair's index in factors_/sums_, adding its factor on first use (per scan: sorted by landmark).
  std::size_t pair_index(std::size_t i, int j) {
    auto& pairs = pairs_of_scan_[i];
    auto it = std::lower_bound(pairs.begin(), pairs.end(), std::make_pair(j, std::size_t{0}));
    if (it != pairs.end() && it->first == j) return it->second;
    const std::size_t p = factors_.size();
    factors_.push_back(new StereoPairFactor(&context_));
    sums_.emplace_back(Eigen::Vector4d::Zero());
    problem_.AddResidualBlock(factors_.back(), nullptr, pose(i), landmark(j));
    pairs.insert(it, {j, p});
    return p;
  }

  StereoFactorContext context_;
  Pose3CeresManifold manifold_;
  ceres::Problem problem_;  ///< owns the factors (factors_ are views)
  ceres::Solver::Options options_;
  std::vector<double> poses_, landmarks_;                                ///< the parameter blocks
  std::vector<std::vector<std::pair<int, std::size_t>>> pairs_of_scan_;  ///< (landmark, pair) per scan
  std::vector<StereoPairFactor*> factors_;
  std::shared_ptr<ceres::ParameterBlockOrdering> fill_reducing_ordering_;
  std::size_t ordered_pairs_ = 0;  ///< factors_.size() when fill_reducing_ordering_ was computed
  std::vector<Eigen::Vector4d, Eigen::aligned_allocator<Eigen::Vector4d>> sums_;  ///< (Σ β z, Σ β) per pair
};

}  // namespace glmbslam::backend
