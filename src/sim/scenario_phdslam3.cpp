#include "sim/scenario_phdslam3.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "core/error.hpp"
#include "core/random.hpp"
#include "io/mat_reader.hpp"

namespace glmbslam::sim {

PhdSlam3Environment load_phdslam3_environment(const std::filesystem::path& mat_file) {
  const io::MatFile mat(mat_file);
  const std::string file = mat_file.string();
  PhdSlam3Environment env;
  env.file = mat_file;

  const Eigen::MatrixXd lm = mat.read_matrix("Landmark_Groundtruth", io::kAnySize, 5);
  if (lm.rows() < 1) throw InputError(file, "variable 'Landmark_Groundtruth' has no landmarks");
  for (Eigen::Index i = 0; i < lm.rows(); ++i) env.landmarks.emplace_back(lm(i, 1), lm(i, 2));

  const Eigen::MatrixXd gt = mat.read_matrix("Robot_Groundtruth", 3, io::kAnySize);
  const Eigen::Index steps = gt.cols();
  if (steps < 2) throw InputError(file, "variable 'Robot_Groundtruth' must have at least 2 columns");
  const Eigen::MatrixXd ctl = mat.read_matrix("Robot_Control", 2, steps);
  const Eigen::MatrixXd q = mat.read_matrix("Qodo", 2, 2);
  if (std::abs(q(0, 1) - q(1, 0)) > 1e-12 * (1.0 + q.cwiseAbs().maxCoeff()) ||
      q.llt().info() != Eigen::Success ||
      !(q(0, 0) > 0.0 && q(1, 1) > 0.0 && q(0, 0) * q(1, 1) - q(0, 1) * q(1, 0) > 0.0)) {
    throw InputError(file, "variable 'Qodo' must be a symmetric positive definite 2x2 matrix");
  }
  env.dt = mat.read_scalar("T");
  if (!(env.dt > 0.0)) throw InputError(file, "variable 'T' (time step) must be positive");
  for (Eigen::Index k = 0; k < steps; ++k) {
    env.poses.emplace_back(gt(0, k), gt(1, k), gt(2, k));
    env.controls.emplace_back(ctl(0, k), ctl(1, k));
  }
  env.odometry_noise = q;
  return env;
}

Scenario2D make_phdslam3_scenario(const PhdSlam3Environment& env, std::uint64_t run_index,
                                  const PhdSlam3Options& o) {
  Scenario2D s;
  s.name = "phdslam3";
  s.dt = env.dt;
  s.landmarks = env.landmarks;
  const std::size_t steps =
      o.max_steps > 0 ? std::min<std::size_t>(o.max_steps, env.poses.size()) : env.poses.size();
  s.poses.assign(env.poses.begin(), env.poses.begin() + static_cast<std::ptrdiff_t>(steps));
  s.true_controls.assign(env.controls.begin(), env.controls.begin() + static_cast<std::ptrdiff_t>(steps));
  s.true_controls[0].setZero();
  s.control_noise = env.odometry_noise;
  s.sensor.min_range = 0.0;
  s.sensor.max_range = o.max_range;
  s.sensor.max_bearing = o.max_bearing_deg * M_PI / 180.0;
  s.sensor.detection_probability = o.detection_probability;
  s.sensor.clutter_rate = o.clutter_rate;
  const double sb = o.sigma_bearing_deg * M_PI / 180.0;
  s.sensor.measurement_noise = Eigen::Vector2d(o.sigma_range * o.sigma_range, sb * sb).asDiagonal();

  RandomStream odometry_rng(run_index, 0);
  RandomStream measurement_rng(run_index, 1);
  const Eigen::Matrix2d chol_q = s.control_noise.llt().matrixL();
  const Eigen::Matrix2d chol_r = s.sensor.measurement_noise.llt().matrixL();
  s.controls.assign(steps, Eigen::Vector2d::Zero());
  s.measurements.resize(steps);
  s.measurement_sources.resize(steps);
  std::vector<Eigen::Vector2d> z;
  std::vector<int> src;
  for (std::size_t k = 0; k < steps; ++k) {
    if (k > 0) {
      s.controls[k] =
          s.true_controls[k] + chol_q * Eigen::Vector2d(odometry_rng.normal(), odometry_rng.normal());
    }
    z.clear();
    src.clear();
    for (std::size_t i = 0; i < s.landmarks.size(); ++i) {
      const Eigen::Vector2d clean = range_bearing(s.poses[k], s.landmarks[i]);
      if (s.sensor.in_field_of_view(clean(0), clean(1))) {
        z.push_back(clean);
        src.push_back(static_cast<int>(i));
      }
    }
    const int n_clutter = measurement_rng.poisson(o.clutter_rate);
    for (int c = 0; c < n_clutter; ++c) {
      const double r = measurement_rng.uniform(0.0, s.sensor.max_range);
      const double b = measurement_rng.uniform(-s.sensor.max_bearing, s.sensor.max_bearing);
      z.emplace_back(r, b);
      src.push_back(-1);
    }
    auto& out_z = s.measurements[k];
    auto& out_src = s.measurement_sources[k];
    for (std::size_t j = 0; j < z.size(); ++j) {
      const Eigen::Vector2d noisy =
          z[j] + chol_r * Eigen::Vector2d(measurement_rng.normal(), measurement_rng.normal());
      if (measurement_rng.uniform() < s.sensor.detection_probability) {
        out_z.emplace_back(noisy(0), std::remainder(noisy(1), 2.0 * M_PI));
        out_src.push_back(src[j]);
      }
    }
  }
  check_scenario(s);
  return s;
}

}  // namespace glmbslam::sim
