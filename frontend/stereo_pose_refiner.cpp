#include "frontend/stereo_pose_refiner.hpp"

#include <memory>

#include <ceres/ceres.h>

#include "core/gaussian.hpp"
#include "frontend/se3_manifold.hpp"

namespace glmbslam::frontend {

namespace {

// Reference-frame observation: r = (π(X) − z) / σ; block: X (3).
class ReferenceResidual : public ceres::SizedCostFunction<3, 3> {
 public:
  ReferenceResidual(const StereoCamera& cam, const Eigen::Vector3d& z, double sigma)
      : cam_(cam), z_(z), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    const Eigen::Map<const Eigen::Vector3d> X(p[0]);
    if (X.z() <= 1e-6) return false;
    Eigen::Map<Eigen::Vector3d> res(r);
    res = (cam_.project(X) - z_) * inv_sigma_;
    if (J != nullptr && J[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J0(J[0]);
      J0 = cam_.project_jacobian(X) * inv_sigma_;
    }
    return true;
  }

 private:
  const StereoCamera& cam_;
  Eigen::Vector3d z_;
  double inv_sigma_;
};

// Current-frame observation: r = (π(T⁻¹ X) − z) / σ, first D rows (D = 3 stereo, 2 = (u_L, v)); blocks: T
// (7), X (3).
template <int D>
class CurrentResidual : public ceres::SizedCostFunction<D, 7, 3> {
 public:
  CurrentResidual(const StereoCamera& cam, const Eigen::Vector3d& z, double sigma)
      : cam_(cam), z_(z), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* p, double* r, double** J) const override {
    const Pose3 T = block_to_pose(p[0]);
    const Eigen::Map<const Eigen::Vector3d> X(p[1]);
    const Eigen::Vector3d pc = T.linear().transpose() * (X - T.translation());
    if (pc.z() <= 1e-6) return false;
    Matrix36d Jp;
    Eigen::Matrix3d Jx;
    const bool want = J != nullptr && (J[0] != nullptr || J[1] != nullptr);
    const Eigen::Vector3d z = cam_.project_from_pose(T, X, want ? &Jp : nullptr, want ? &Jx : nullptr);
    Eigen::Map<Eigen::Matrix<double, D, 1>> res(r);
    res = (z - z_).template head<D>() * inv_sigma_;
    if (J != nullptr) {
      if (J[0] != nullptr) {
        Eigen::Map<Eigen::Matrix<double, D, 7, Eigen::RowMajor>> J0(J[0]);
        J0.template leftCols<6>() = Jp.template topRows<D>() * inv_sigma_;
        J0.col(6).setZero();
      }
      if (J[1] != nullptr) {
        Eigen::Map<Eigen::Matrix<double, D, 3, Eigen::RowMajor>> J1(J[1]);
        J1 = Jx.template topRows<D>() * inv_sigma_;
      }
    }
    return true;
  }

 private:
  const StereoCamera& cam_;
  Eigen::Vector3d z_;
  double inv_sigma_;
};

}  // namespace

PoseRefinementResult refine_stereo_pose(const StereoCamera& camera, const std::vector<TrackedPoint>& points,
                                        const Pose3& initial_T_ref_cur,
                                        const PoseRefinementOptions& options) {
  PoseRefinementResult result;
  const std::size_t n = points.size();
  result.inlier.assign(n, 1);
  result.T_ref_cur = initial_T_ref_cur;
  // Points behind either camera at the start cannot be used.
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d pc = initial_T_ref_cur.inverse() * points[i].point_ref;
    if (points[i].point_ref.z() <= 1e-6 || pc.z() <= 1e-6) result.inlier[i] = 0;
  }
  std::vector<double> X(3 * n);
  double pose[7];
  pose_to_block(initial_T_ref_cur, pose);
  const double gate2 = options.chi2_threshold * 5.991 / 7.815;

  for (int round = 0; round < options.rounds; ++round) {
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    Se3RightManifold manifold;                   // outlives `problem`, which does not own it
    ceres::HuberLoss loss(options.huber_delta);  // one loss object shared by every residual
    ceres::Problem problem(po);
    problem.AddParameterBlock(pose, 7, &manifold);
    int used = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!result.inlier[i]) continue;
      const TrackedPoint& t = points[i];
      double* x = &X[3 * i];
      Eigen::Map<Eigen::Vector3d> xm(x);
      xm = t.point_ref;  // every round restarts points from their triangulation
      problem.AddResidualBlock(new ReferenceResidual(camera, t.z_ref, t.sigma_ref), &loss, x);
      if (t.cur_stereo) {
        problem.AddResidualBlock(new CurrentResidual<3>(camera, t.z_cur, t.sigma_cur), &loss, pose, x);
      } else {
        problem.AddResidualBlock(new CurrentResidual<2>(camera, t.z_cur, t.sigma_cur), &loss, pose, x);
      }
      ++used;
    }
    if (used < 4) return result;
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_SCHUR;
    so.max_num_iterations = options.max_iterations;
    so.num_threads = 1;
    so.logging_type = ceres::SILENT;
    so.minimizer_progress_to_stdout = false;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) return result;

    // χ² gate on each point's current and reference residuals at the solution; another round only if it
    // removed something.
    int removed = 0;
    const Pose3 T = block_to_pose(pose);
    const Pose3 Tinv = T.inverse();
    for (std::size_t i = 0; i < n; ++i) {
      if (!result.inlier[i]) continue;
      const TrackedPoint& t = points[i];
      const Eigen::Vector3d Xi = Eigen::Map<const Eigen::Vector3d>(&X[3 * i]);
      const Eigen::Vector3d pc = Tinv * Xi;
      if (pc.z() <= 1e-6 || Xi.z() <= 1e-6) {
        result.inlier[i] = 0;
        ++removed;
        continue;
      }
      const Eigen::Vector3d rr = (camera.project(Xi) - t.z_ref) / t.sigma_ref;
      const Eigen::Vector3d rc = (camera.project(pc) - t.z_cur) / t.sigma_cur;
      const double chi_c = t.cur_stereo ? rc.squaredNorm() : rc.head<2>().squaredNorm();
      const double gate_c = t.cur_stereo ? options.chi2_threshold : gate2;
      if (chi_c > gate_c || rr.squaredNorm() > options.chi2_threshold) {
        result.inlier[i] = 0;
        ++removed;
      }
    }
    if (removed == 0) break;
  }

  // Information of the pose with the points marginalised (Schur complement), Huber weights at the solution.
  result.T_ref_cur = block_to_pose(pose);
  Matrix6d S = Matrix6d::Zero();
  int inliers = 0;
  auto huber_weight = [&](double s2) {
    const double s = std::sqrt(s2);
    return s <= options.huber_delta ? 1.0 : options.huber_delta / s;
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (!result.inlier[i]) continue;
    const TrackedPoint& t = points[i];
    const Eigen::Vector3d Xi = Eigen::Map<const Eigen::Vector3d>(&X[3 * i]);
    Matrix36d Jp;
    Eigen::Matrix3d Jx;
    const Eigen::Vector3d zc = camera.project_from_pose(result.T_ref_cur, Xi, &Jp, &Jx);
    const int D = t.cur_stereo ? 3 : 2;
    const Eigen::Vector3d rc = (zc - t.z_cur) / t.sigma_cur;
    const double wc = huber_weight(rc.head(D).squaredNorm()) / (t.sigma_cur * t.sigma_cur);
    const Eigen::Matrix3d Jr = camera.project_jacobian(Xi);
    const Eigen::Vector3d rr = (camera.project(Xi) - t.z_ref) / t.sigma_ref;
    const double wr = huber_weight(rr.squaredNorm()) / (t.sigma_ref * t.sigma_ref);
    const Eigen::MatrixXd Jpd = Jp.topRows(D);
    const Eigen::MatrixXd Jxd = Jx.topRows(D);
    const Matrix6d Hpp = wc * Jpd.transpose() * Jpd;
    const Eigen::Matrix<double, 6, 3> Hpx = wc * Jpd.transpose() * Jxd;
    const Eigen::Matrix3d Hxx = wc * Jxd.transpose() * Jxd + wr * Jr.transpose() * Jr;
    S += Hpp - Hpx * Hxx.ldlt().solve(Hpx.transpose());
    ++inliers;
  }
  result.inliers = inliers;
  symmetrize(S);
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(S);
  if (inliers < 4 || es.eigenvalues().minCoeff() <= 1e-12 * std::max(1.0, es.eigenvalues().maxCoeff())) {
    return result;
  }
  result.covariance =
      es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  symmetrize(result.covariance);
  result.success = true;
  return result;
}

}  // namespace glmbslam::frontend
