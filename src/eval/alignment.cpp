#include "eval/alignment.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/SVD>

namespace glmbslam::eval {

Similarity3 umeyama_alignment(const Eigen::Matrix3Xd& source, const Eigen::Matrix3Xd& target,
                              bool with_scale) {
  if (source.cols() != target.cols()) throw std::invalid_argument("umeyama_alignment: point counts differ");
  if (source.cols() == 0) throw std::invalid_argument("umeyama_alignment: no points");
  const double n = static_cast<double>(source.cols());
  const Eigen::Vector3d mu_s = source.rowwise().mean();  // eq. (34)
  const Eigen::Vector3d mu_t = target.rowwise().mean();  // eq. (35)
  const Eigen::Matrix3Xd s0 = source.colwise() - mu_s;
  const Eigen::Matrix3Xd t0 = target.colwise() - mu_t;
  const double var_s = s0.squaredNorm() / n;              // eq. (36)
  const Eigen::Matrix3d sigma = t0 * s0.transpose() / n;  // eq. (38)
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d = Eigen::Vector3d::Ones();  // eq. (39): S
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) d(2) = -1.0;
  Similarity3 out;
  out.rotation = svd.matrixU() * d.asDiagonal() * svd.matrixV().transpose();  // eq. (40)
  if (with_scale) {
    out.scale = var_s > 0.0 ? svd.singularValues().dot(d) / var_s : 1.0;  // eq. (42)
  }
  out.translation = mu_t - out.scale * out.rotation * mu_s;  // eq. (41)
  return out;
}

Eigen::Matrix3Xd positions_of(const PoseList& poses) {
  Eigen::Matrix3Xd p(3, static_cast<Eigen::Index>(poses.size()));
  for (size_t i = 0; i < poses.size(); ++i) p.col(static_cast<Eigen::Index>(i)) = poses[i].translation();
  return p;
}

namespace {

double errors_after(const Similarity3& a, const Eigen::Matrix3Xd& est, const Eigen::Matrix3Xd& gt,
                    std::vector<double>& errors) {
  errors.resize(static_cast<size_t>(est.cols()));
  double sum_sq = 0.0;
  for (Eigen::Index i = 0; i < est.cols(); ++i) {
    const double e = (gt.col(i) - a.apply(est.col(i))).norm();
    errors[static_cast<size_t>(i)] = e;
    sum_sq += e * e;
  }
  return std::sqrt(sum_sq / static_cast<double>(est.cols()));
}

}  // namespace

AteResult evaluate_ate(const PoseList& gt, const PoseList& est) {
  if (gt.size() != est.size()) {
    throw std::invalid_argument("evaluate_ate: ground truth has " + std::to_string(gt.size()) +
                                " poses, estimate has " + std::to_string(est.size()));
  }
  if (gt.empty()) throw std::invalid_argument("evaluate_ate: empty trajectories");
  const Eigen::Matrix3Xd p_gt = positions_of(gt);
  const Eigen::Matrix3Xd p_est = positions_of(est);
  AteResult r;
  r.poses = static_cast<int>(gt.size());
  r.se3_alignment = umeyama_alignment(p_est, p_gt, false);
  r.se3_rmse_m = errors_after(r.se3_alignment, p_est, p_gt, r.se3_errors_m);
  // A ground truth that stays in one place (a still camera) fixes no scale: the similarity would shrink the
  // estimate onto the point (scale 0, error 0). Sim(3) is then reported as undefined.
  const double gt_spread =
      std::sqrt((p_gt.colwise() - p_gt.rowwise().mean()).squaredNorm() / static_cast<double>(p_gt.cols()));
  if (gt_spread < kMinSim3Spread) {
    r.sim3_alignment = r.se3_alignment;
    r.sim3_scale = r.sim3_rmse_m = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  r.sim3_alignment = umeyama_alignment(p_est, p_gt, true);
  r.sim3_scale = r.sim3_alignment.scale;
  r.sim3_rmse_m = errors_after(r.sim3_alignment, p_est, p_gt, r.sim3_errors_m);
  return r;
}

}  // namespace glmbslam::eval
