#include "frontend/stereo_pose_refiner.hpp"

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "core/gaussian.hpp"

namespace glmbslam::frontend {

namespace {

struct Linearization {
  double cost = 0.0;
  Matrix6d H = Matrix6d::Zero();
  Vector6d g = Vector6d::Zero();
  int used = 0;
};

class MotionProblem {
 public:
  MotionProblem(const StereoCamera& camera, const std::vector<TrackedPoint>& points, double huber_delta)
      : camera_(camera), points_(points), delta_(huber_delta), sigma_x_(points.size()) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      sigma_x_[i] = camera.triangulation_covariance(points[i].z_ref, points[i].sigma_ref);
    }
  }

  /// χ² of point i at T (e ᵀ S⁻¹ e) with its Jacobian terms; false if the point is behind the camera.
  /// H and g (if not null) receive Jᵀ S⁻¹ J and Jᵀ S⁻¹ e with J = ∂e/∂ξ.
  bool evaluate(std::size_t i, const Pose3& T, double* chi2, Matrix6d* H, Vector6d* g) const {
    const TrackedPoint& t = points_[i];
    const Eigen::Vector3d pc = T.linear().transpose() * (t.point_ref - T.translation());
    if (pc.z() <= 1e-6) return false;
    Matrix36d Jp;
    Eigen::Matrix3d Jx;
    const Eigen::Vector3d z = camera_.project_from_pose(T, t.point_ref, &Jp, &Jx);
    const Eigen::Vector3d e = z - t.z_cur;
    const double s2 = t.sigma_cur * t.sigma_cur;
    Eigen::Matrix3d S = Jx * sigma_x_[i] * Jx.transpose();
    if (t.cur_stereo) {
      S.diagonal().array() += s2;
      const Eigen::Matrix3d Sinv = S.inverse();
      *chi2 = e.dot(Sinv * e);
      if (H != nullptr) {
        const Eigen::Matrix<double, 6, 3> JtSinv = Jp.transpose() * Sinv;
        *H = JtSinv * Jp;
        *g = JtSinv * e;
      }
    } else {
      Eigen::Matrix2d S2 = S.topLeftCorner<2, 2>();
      S2.diagonal().array() += s2;
      const Eigen::Matrix2d Sinv = S2.inverse();
      const Eigen::Vector2d e2 = e.head<2>();
      *chi2 = e2.dot(Sinv * e2);
      if (H != nullptr) {
        const Eigen::Matrix<double, 6, 2> JtSinv = Jp.topRows<2>().transpose() * Sinv;
        *H = JtSinv * Jp.topRows<2>();
        *g = JtSinv * e2;
      }
    }
    return true;
  }

  double huber_weight(double chi2) const {
    const double s = std::sqrt(chi2);
    return s <= delta_ ? 1.0 : delta_ / s;
  }
  double huber_cost(double chi2) const {
    const double s = std::sqrt(chi2);
    return s <= delta_ ? chi2 : 2.0 * delta_ * s - delta_ * delta_;
  }

  Linearization linearize(const Pose3& T, const std::vector<char>& active) const {
    Linearization lin;
    Matrix6d Hi;
    Vector6d gi;
    double chi2 = 0.0;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (!active[i] || !evaluate(i, T, &chi2, &Hi, &gi)) continue;
      const double w = huber_weight(chi2);
      lin.cost += huber_cost(chi2);
      lin.H.noalias() += w * Hi;
      lin.g.noalias() += w * gi;
      ++lin.used;
    }
    return lin;
  }

 private:
  const StereoCamera& camera_;
  const std::vector<TrackedPoint>& points_;
  double delta_;
  std::vector<Eigen::Matrix3d> sigma_x_;
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
  const Pose3 T0inv = initial_T_ref_cur.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d pc = T0inv * points[i].point_ref;
    if (points[i].point_ref.z() <= 1e-6 || pc.z() <= 1e-6) result.inlier[i] = 0;
  }
  const MotionProblem problem(camera, points, options.huber_delta);
  const double gate2 = options.chi2_threshold * 5.991 / 7.815;
  Pose3 T = initial_T_ref_cur;

  for (int round = 0; round < options.rounds; ++round) {
    Linearization lin = problem.linearize(T, result.inlier);
    if (lin.used < 4) return result;
    for (int it = 0; it < options.max_iterations; ++it) {
      Eigen::LDLT<Matrix6d> ldlt(lin.H);
      if (ldlt.info() != Eigen::Success) break;
      Vector6d step = -ldlt.solve(lin.g);
      if (!step.allFinite()) break;
      bool accepted = false;
      for (int halving = 0; halving < 6 && !accepted; ++halving, step *= 0.5) {
        const Pose3 Tn = se3_plus(T, step);
        Linearization next = problem.linearize(Tn, result.inlier);
        if (next.used >= 4 && next.cost <= lin.cost) {
          T = Tn;
          lin = next;
          accepted = true;
        }
      }
      if (!accepted || step.norm() < 1e-10) break;
    }

    // χ² gate at the solution; another round only if it removed something.
    int removed = 0;
    double chi2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!result.inlier[i]) continue;
      const bool in_front = problem.evaluate(i, T, &chi2, nullptr, nullptr);
      const double gate = points[i].cur_stereo ? options.chi2_threshold : gate2;
      if (!in_front || chi2 > gate) {
        result.inlier[i] = 0;
        ++removed;
      }
    }
    if (removed == 0) break;
  }

  // Information of the pose at the solution (Huber weights), its inverse is the covariance.
  result.T_ref_cur = T;
  const Linearization lin = problem.linearize(T, result.inlier);
  result.inliers = lin.used;
  Matrix6d H = lin.H;
  symmetrize(H);
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(H);
  if (lin.used < 4 || es.eigenvalues().minCoeff() <= 1e-12 * std::max(1.0, es.eigenvalues().maxCoeff())) {
    return result;
  }
  result.covariance =
      es.eigenvectors() * es.eigenvalues().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
  symmetrize(result.covariance);
  result.success = true;
  return result;
}

}  // namespace glmbslam::frontend
