#include "frontend/stereo_pose_refiner.hpp"

#include <cmath>
#include <deque>
#include <stdexcept>

#include <ceres/evaluation_callback.h>
#include <ceres/loss_function.h>
#include <ceres/problem.h>
#include <ceres/sized_cost_function.h>
#include <ceres/solver.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/gaussian.hpp"
#include "frontend/se3_manifold.hpp"

namespace glmbslam::frontend {

namespace {

// The shared model: whitened residuals r_i = W_i e_i with W_iᵀ W_i = S_i⁻¹ (W_i = L_i⁻¹, S_i = L_i L_iᵀ) and
// their Jacobians ∂r_i/∂ξ = W_i ∂e_i/∂ξ. For a point seen in the current left image only, W_i is the 2×2
// whitening of (u_L, v) in the top-left corner and the third residual is zero. The whitening is evaluated at
// a given pose and then held fixed while solving (the IRLS-style weights of a round); both solvers refresh it
// at the same poses (start of the refinement, solution of every round), so they minimise the same objective
// with exact gradients and converge to the same point.
class WhitenedModel {
 public:
  WhitenedModel(const StereoCamera& camera, const std::vector<TrackedPoint>& points)
      : camera_(camera),
        points_(points),
        sigma_x_(points.size()),
        W_(points.size(), Eigen::Matrix3d::Zero()) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      sigma_x_[i] = camera.triangulation_covariance(points[i].z_ref, points[i].sigma_ref);
    }
  }

  /// W_i at T for the active points: S_i = σ_cur,i² I + J_X Σ_X,i J_Xᵀ (J_X = ∂π(T⁻¹X)/∂X).
  void update_whitening(const Pose3& T, const std::vector<char>& active) {
    const Eigen::Matrix3d Rt = T.linear().transpose();
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!active[i]) continue;
      const TrackedPoint& t = points_[i];
      const Eigen::Vector3d pc = Rt * (t.point_ref - T.translation());
      W_[i].setZero();
      if (pc.z() <= 1e-6) continue;
      const Eigen::Matrix3d Jx = camera_.project_jacobian(pc) * Rt;
      Eigen::Matrix3d S = Jx * sigma_x_[i] * Jx.transpose();
      S.diagonal().array() += t.sigma_cur * t.sigma_cur;
      if (t.cur_stereo) {
        const Eigen::LLT<Eigen::Matrix3d> llt(S);
        W_[i] = llt.matrixL().solve(Eigen::Matrix3d::Identity());
      } else {
        const Eigen::LLT<Eigen::Matrix2d> llt(S.topLeftCorner<2, 2>());
        W_[i].topLeftCorner<2, 2>() = llt.matrixL().solve(Eigen::Matrix2d::Identity());
      }
    }
  }

  /// r_i and (if J is not null) ∂r_i/∂ξ at T; false if the point is behind the current camera.
  bool residual(std::size_t i, const Pose3& T, Eigen::Vector3d* r, Matrix36d* J) const {
    const TrackedPoint& t = points_[i];
    const Eigen::Vector3d pc = T.linear().transpose() * (t.point_ref - T.translation());
    if (pc.z() <= 1e-6) return false;
    Matrix36d Jp;
    const Eigen::Vector3d e =
        camera_.project_from_pose(T, t.point_ref, J != nullptr ? &Jp : nullptr) - t.z_cur;
    const Eigen::Matrix3d& W = W_[i];
    if (t.cur_stereo) {
      *r = W * e;
      if (J != nullptr) *J = W * Jp;
    } else {
      r->head<2>() = W.topLeftCorner<2, 2>() * e.head<2>();
      (*r)(2) = 0.0;
      if (J != nullptr) {
        J->topRows<2>() = W.topLeftCorner<2, 2>() * Jp.topRows<2>();
        J->row(2).setZero();
      }
    }
    return true;
  }

  std::size_t size() const { return points_.size(); }

 private:
  const StereoCamera& camera_;
  const std::vector<TrackedPoint>& points_;
  std::vector<Eigen::Matrix3d> sigma_x_;
  std::vector<Eigen::Matrix3d> W_;
};

/// Huber ρ on χ² = ‖r‖² (ceres::HuberLoss convention): ρ = χ² for √χ² ≤ δ, 2δ√χ² − δ² above; w = ρ'.
double huber_cost(double chi2, double delta) {
  const double s = std::sqrt(chi2);
  return s <= delta ? chi2 : 2.0 * delta * s - delta * delta;
}
double huber_weight(double chi2, double delta) {
  const double s = std::sqrt(chi2);
  return s <= delta ? 1.0 : delta / s;
}

struct Linearization {
  double cost = 0.0;
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  int used = 0;
};

/// Σ ρ(χ²_i), Gauss–Newton information Σ w_i J_iᵀ J_i and gradient Σ w_i J_iᵀ r_i over the active points.
Linearization linearize(const WhitenedModel& model, const Pose3& T, const std::vector<char>& active,
                        double delta) {
  Linearization lin;
  Eigen::Vector3d r;
  Matrix36d J;
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (!active[i] || !model.residual(i, T, &r, &J)) continue;
    const double chi2 = r.squaredNorm();
    const double w = huber_weight(chi2, delta);
    lin.cost += huber_cost(chi2, delta);
    lin.H.noalias() += w * J.transpose() * J;
    lin.g.noalias() += w * J.transpose() * r;
    ++lin.used;
  }
  return lin;
}

/// At the solution T of a round: refresh the whitening at T, then drop the active points behind the camera or
/// with χ² above the gate (3-dof gate for stereo, the 2-dof one scaled by 5.991 / 7.815 for mono). Returns
/// the indices removed.
std::vector<std::size_t> gate_points(WhitenedModel& model, const std::vector<TrackedPoint>& points,
                                     const Pose3& T, const PoseRefinementOptions& options,
                                     std::vector<char>* active) {
  model.update_whitening(T, *active);
  const double gate2 = options.chi2_threshold * 5.991 / 7.815;
  std::vector<std::size_t> removed;
  Eigen::Vector3d r;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!(*active)[i]) continue;
    const bool in_front = model.residual(i, T, &r, nullptr);
    const double gate = points[i].cur_stereo ? options.chi2_threshold : gate2;
    if (!in_front || r.squaredNorm() > gate) {
      (*active)[i] = 0;
      removed.push_back(i);
    }
  }
  return removed;
}

/// Result with the start pose and the points in front of both cameras at the start marked as inliers.
PoseRefinementResult initial_result(const std::vector<TrackedPoint>& points, const Pose3& initial_T_ref_cur) {
  PoseRefinementResult result;
  const std::size_t n = points.size();
  result.inlier.assign(n, 1);
  result.T_ref_cur = initial_T_ref_cur;
  const Pose3 T0inv = initial_T_ref_cur.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d pc = T0inv * points[i].point_ref;
    if (points[i].point_ref.z() <= 1e-6 || pc.z() <= 1e-6) result.inlier[i] = 0;
  }
  return result;
}

/// χ² of every point at T (whitening refreshed there for all of them, the active ones unchanged).
std::vector<double> all_chi2(WhitenedModel& model, const Pose3& T) {
  const std::vector<char> all(model.size(), 1);
  model.update_whitening(T, all);
  std::vector<double> chi2(model.size(), std::nan(""));
  Eigen::Vector3d r;
  for (std::size_t i = 0; i < model.size(); ++i) {
    if (model.residual(i, T, &r, nullptr)) chi2[i] = r.squaredNorm();
  }
  return chi2;
}

/// Covariance = H⁻¹ if H (6×6 information) is well conditioned; false otherwise.
bool invert_information(Matrix6d H, Matrix6d* covariance) {
  symmetrize(H);
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(H);
  if (es.eigenvalues().minCoeff() <= 1e-12 * std::max(1.0, es.eigenvalues().maxCoeff())) return false;
  *covariance =
      es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  symmetrize(*covariance);
  return true;
}

// ---------------------------------------------------------------------------------------------------------
// Ceres: one analytic cost per point, the whitened residual of the shared model (kDim = 3 stereo, 2 mono)
// with ∂r/∂ξ in the first six columns of the 7-column ambient Jacobian (Se3RightManifold's convention). A
// point behind the current camera gives a zero residual (it drops out, as in the Gauss–Newton solver).
// The pose block as a Pose3, converted once per evaluation point (Ceres writes the point being evaluated into
// the user's block before calling PrepareForEvaluation when a callback is set).
class PoseBlockCache final : public ceres::EvaluationCallback {
 public:
  explicit PoseBlockCache(const double* block) : block_(block), T_(block_to_pose(block)) {}
  void PrepareForEvaluation(bool /*evaluate_jacobians*/, bool new_evaluation_point) override {
    if (new_evaluation_point) T_ = block_to_pose(block_);
  }
  const Pose3& pose() const { return T_; }

 private:
  const double* block_;
  Pose3 T_;
};

template <int kDim>
class WhitenedStereoCost final : public ceres::SizedCostFunction<kDim, 7> {
 public:
  WhitenedStereoCost(const WhitenedModel& model, const PoseBlockCache& pose, std::size_t index)
      : model_(model), pose_(pose), index_(index) {}

  bool Evaluate(double const* const* /*parameters*/, double* residuals, double** jacobians) const override {
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    Eigen::Vector3d r;
    Matrix36d J;
    if (!model_.residual(index_, pose_.pose(), &r, want_jacobian ? &J : nullptr)) {
      r.setZero();
      J.setZero();
    }
    for (int k = 0; k < kDim; ++k) residuals[k] = r(k);
    if (want_jacobian) {
      Eigen::Map<Eigen::Matrix<double, kDim, 7, Eigen::RowMajor>> Jm(jacobians[0]);
      Jm.template leftCols<6>() = J.topRows<kDim>();
      Jm.col(6).setZero();
    }
    return true;
  }

 private:
  const WhitenedModel& model_;
  const PoseBlockCache& pose_;
  std::size_t index_;
};

PoseRefinementResult refine_ceres(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                  const Pose3& initial_T_ref_cur, const PoseRefinementOptions& options) {
  PoseRefinementResult result = initial_result(points, initial_T_ref_cur);
  const std::size_t n = points.size();
  WhitenedModel model(camera, points);
  model.update_whitening(initial_T_ref_cur, result.inlier);
  if (options.gate_at_start) gate_points(model, points, initial_T_ref_cur, options, &result.inlier);
  double pose[7];
  pose_to_block(initial_T_ref_cur, pose);

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.enable_fast_removal = true;
  PoseBlockCache pose_cache(pose);
  problem_options.evaluation_callback = &pose_cache;
  ceres::Problem problem(problem_options);
  Se3RightManifold manifold;
  ceres::HuberLoss huber(options.huber_delta);  // ρ(s) = s for s ≤ δ², 2δ√s − δ² above
  problem.AddParameterBlock(pose, 7, &manifold);

  // Cost functions live in deques (stable addresses, no moves); one residual block per usable point.
  std::deque<WhitenedStereoCost<3>> stereo_costs;
  std::deque<WhitenedStereoCost<2>> mono_costs;
  std::vector<ceres::ResidualBlockId> block(n, nullptr);
  int active = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!result.inlier[i]) continue;
    ceres::CostFunction* cost =
        points[i].cur_stereo
            ? static_cast<ceres::CostFunction*>(&stereo_costs.emplace_back(model, pose_cache, i))
            : static_cast<ceres::CostFunction*>(&mono_costs.emplace_back(model, pose_cache, i));
    block[i] = problem.AddResidualBlock(cost, &huber, pose);
    ++active;
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  // The start (PnP) is close: a wide trust region makes Levenberg–Marquardt behave like Gauss–Newton, and the
  // tolerances stop it once the step no longer changes the pose at the sub-micrometre level (the Gauss–Newton
  // solver's criterion), instead of running every round to max_iterations.
  solver_options.initial_trust_region_radius = 1e8;
  solver_options.function_tolerance = 1e-10;
  solver_options.gradient_tolerance = 1e-12;
  solver_options.parameter_tolerance = 1e-8;

  for (int round = 0; round < options.rounds; ++round) {
    if (active < 4) return result;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
    if (!summary.IsSolutionUsable()) return result;
    // χ² gate at the solution (whitening refreshed there); another round only if it removed something.
    const std::vector<std::size_t> removed =
        gate_points(model, points, block_to_pose(pose), options, &result.inlier);
    for (const std::size_t i : removed) problem.RemoveResidualBlock(block[i]);
    active -= static_cast<int>(removed.size());
    if (removed.empty()) break;
  }

  // Information at the solution: Σ ρ'(χ²_i) J_iᵀ J_i, which is what Ceres' corrected Jacobian of a Huber loss
  // gives (ρ'' ≤ 0 ⇒ J scaled by √ρ'), computed from the shared model without an Evaluate/CRS round trip.
  result.T_ref_cur = block_to_pose(pose);
  const Linearization lin = linearize(model, result.T_ref_cur, result.inlier, options.huber_delta);
  result.inliers = lin.used;
  if (lin.used < 4) return result;
  result.success = invert_information(lin.H, &result.covariance);
  result.chi2 = all_chi2(model, result.T_ref_cur);
  return result;
}

// ---------------------------------------------------------------------------------------------------------
// Hand-written Gauss–Newton with Huber (IRLS) weights and step halving if the cost rises.
PoseRefinementResult refine_gauss_newton(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                         const Pose3& initial_T_ref_cur,
                                         const PoseRefinementOptions& options) {
  PoseRefinementResult result = initial_result(points, initial_T_ref_cur);
  WhitenedModel model(camera, points);
  model.update_whitening(initial_T_ref_cur, result.inlier);
  if (options.gate_at_start) gate_points(model, points, initial_T_ref_cur, options, &result.inlier);
  const double delta = options.huber_delta;
  Pose3 T = initial_T_ref_cur;

  for (int round = 0; round < options.rounds; ++round) {
    Linearization lin = linearize(model, T, result.inlier, delta);
    if (lin.used < 4) return result;
    for (int it = 0; it < options.max_iterations; ++it) {
      Eigen::LDLT<Matrix6d> ldlt(lin.H);
      if (ldlt.info() != Eigen::Success) break;
      Vector6d step = -ldlt.solve(lin.g);
      if (!step.allFinite()) break;
      bool accepted = false;
      for (int halving = 0; halving < 6 && !accepted; ++halving, step *= 0.5) {
        const Pose3 Tn = se3_plus(T, step);
        Linearization next = linearize(model, Tn, result.inlier, delta);
        if (next.used >= 4 && next.cost <= lin.cost) {
          T = Tn;
          lin = next;
          accepted = true;
        }
      }
      if (!accepted || step.norm() < 1e-10) break;
    }
    // χ² gate at the solution (whitening refreshed there); another round only if it removed something.
    if (gate_points(model, points, T, options, &result.inlier).empty()) break;
  }

  // Information of the pose at the solution (Huber weights), its inverse is the covariance.
  result.T_ref_cur = T;
  const Linearization lin = linearize(model, T, result.inlier, delta);
  result.inliers = lin.used;
  if (lin.used < 4) return result;
  result.success = invert_information(lin.H, &result.covariance);
  result.chi2 = all_chi2(model, result.T_ref_cur);
  return result;
}

}  // namespace

PoseRefinerKind pose_refiner_kind(const std::string& name) {
  if (name == "ceres") return PoseRefinerKind::kCeres;
  if (name == "gauss_newton") return PoseRefinerKind::kGaussNewton;
  throw std::invalid_argument("unknown pose refiner '" + name + "' (ceres or gauss_newton)");
}

PoseRefinementOptions pose_refinement_options(const VoConfig& config) {
  PoseRefinementOptions opt;
  opt.refiner = pose_refiner_kind(config.refiner);
  opt.huber_delta = config.huber_delta;
  opt.chi2_threshold = config.chi2_threshold;
  opt.rounds = config.refine_rounds;
  opt.max_iterations = config.max_iterations;
  return opt;
}

PoseRefinementResult refine_stereo_pose(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                        const Pose3& initial_T_ref_cur,
                                        const PoseRefinementOptions& options) {
  return options.refiner == PoseRefinerKind::kCeres
             ? refine_ceres(camera, points, initial_T_ref_cur, options)
             : refine_gauss_newton(camera, points, initial_T_ref_cur, options);
}

}  // namespace glmbslam::frontend
