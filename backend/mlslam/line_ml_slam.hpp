#pragma once
// RFS-ML-SLAM on paper 004's 1D problem (Sec. VI-A; models in backend/models/line_models.hpp): the parts of
// RfsMlSlam (rfs_ml_slam.hpp) for a robot on a line. Poses and landmarks are 1-vectors on the Euclidean line;
// the motion factor is W (x_i − x_{i−1} − u_i) (Eq. 2), the measurement factor the generic √β W (z − ẑ) of
// ceres_factors_2d.hpp (Eq. 3 weighted by the E-step's β), and p_D falls smoothly at both ends of the
// sensor's interval (digest 3.5: a hard border makes Eq. 7 jump as a landmark crosses it).
#include <cmath>

#include <ceres/ceres.h>
#include <Eigen/Core>

#include "backend/mlslam/ceres_factors_2d.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/mlslam/rfs_ml_slam.hpp"
#include "backend/models/line_models.hpp"

namespace glmbslam::backend {

/// p_D(m | x) = p_D,in · σ((r_max − z)/w) · σ((z − r_min)/w), z = m − x, σ the logistic function.
class SmoothDetection1D {
 public:
  /// width ≤ 0: the measurement noise's standard deviation.
  SmoothDetection1D(const LineMeasurementModel& model, double width)
      : config_(model.config()), w_(width > 0.0 ? width : std::sqrt(model.config().variance)) {}

  double operator()(const LineMeasurementModel& /*model*/, const LinePose& /*x*/,
                    const LineMeasurementModel::Landmark& /*m*/,
                    const LineMeasurementModel::Measurement& z) const {
    return config_.p_detect_inside * logistic((config_.max_range - z(0)) / w_) *
           logistic((z(0) - config_.min_range) / w_);
  }
  /// Landmarks farther than this from the pose have p_D < 1e-6·p_D,in (never candidates).
  double query_radius() const {
    return std::max(std::abs(config_.max_range), std::abs(config_.min_range)) + 14.0 * w_;
  }
  /// False where p_D < 1e-6·p_D,in for sure.
  bool maybe_in_view(const LineMeasurementModel& /*model*/, const LinePose& x,
                     const LineMeasurementModel::Landmark& m) const {
    const double z = (m - x)(0);
    return z >= config_.min_range - 14.0 * w_ && z <= config_.max_range + 14.0 * w_;
  }

 private:
  static double logistic(double t) { return 1.0 / (1.0 + std::exp(-t)); }
  LineSensorConfig config_;
  double w_;
};

/// r = w (x_i − x_{i−1} − u), w = 1/√q (Eq. 2); linear, so its Jacobians are constants.
class LineMotionFactor : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  LineMotionFactor(double u, double w) : u_(u), w_(w) {}
  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    residuals[0] = w_ * (p[1][0] - p[0][0] - u_);
    if (jacobians != nullptr) {
      if (jacobians[0] != nullptr) jacobians[0][0] = -w_;
      if (jacobians[1] != nullptr) jacobians[1][0] = w_;
    }
    return true;
  }

 private:
  double u_, w_;
};

struct LineMlSlamParts {
  using Pose = LinePose;
  using Detection = SmoothDetection1D;
  using Manifold = ceres::EuclideanManifold<1>;
  static constexpr int kBlockSize = 1;
  static Detection detection(const LineMeasurementModel& model, const MlSlamConfig& c) {
    return Detection(model, c.border_range_m);
  }
  static double length_scale(const LineMeasurementModel& model) { return std::sqrt(model.noise()(0, 0)); }
  static void to_block(const Pose& x, double* block) { block[0] = x(0); }
  static Pose from_block(const double* block) { return Pose::Constant(block[0]); }
  static ceres::CostFunction* motion_factor(const LineMotion& /*motion*/, const LineMotion::Control& u,
                                            const LineMotion::Covariance& W, const Pose& /*prev*/,
                                            double scale) {
    return new LineMotionFactor(u(0), W(0, 0) / std::sqrt(scale));
  }
  static ceres::CostFunction* measurement_factor(const LineMeasurementModel& model,
                                                 const LineMeasurementModel::Measurement& z,
                                                 const LineMeasurementModel::MeasurementCovariance& W,
                                                 double beta) {
    return new WeightedMeasurementFactor<LineMeasurementModel>(model, z, W, beta);
  }
};

/// RFS-ML-SLAM (or, with association "nearest_neighbour", vector ML) on the line.
using LineMlSlam = RfsMlSlam<LineMotion, LineMeasurementModel, LineMlSlamParts>;

}  // namespace glmbslam::backend
