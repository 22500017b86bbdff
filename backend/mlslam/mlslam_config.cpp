#include "backend/mlslam/mlslam_config.hpp"

#include <string>

namespace glmbslam::backend {

void load_mlslam_config(ConfigNode node, MlSlamConfig& c) {
  node.read_choice("association", c.association, {"rfs", "nearest_neighbour"});
  node.read_in_range("max_rounds", c.max_rounds, 1, 100000);
  node.read_in_range("tolerance", c.tolerance, 0.0, 1e9);
  node.read_in_range("relative_tolerance", c.relative_tolerance, 0.0, 1.0);
  node.read_in_range("solver_iterations", c.solver_iterations, 1, 10000);
  node.read_in_range("initial_trust_region_radius", c.initial_trust_region_radius, 1e-6, 1e16);
  node.read_choice("motion_noise", c.motion_noise, {"configured", "estimated"});
  node.read_choice("linear_solver", c.linear_solver,
                   {"auto", "dense_schur", "sparse_schur", "iterative_schur", "sparse_normal_cholesky"});
  node.read_in_range("max_assignments", c.max_assignments, 1, 100000);
  node.read_in_range("assignment_log_gap", c.assignment_log_gap, 0.0, 1e6);
  node.read_in_range("gate", c.gate, 0.0, 1e9);
  node.read_in_range("min_responsibility", c.min_responsibility, 0.0, 1.0);
  node.read_in_range("border_range_m", c.border_range_m, -1.0, 1e6);
  node.read_in_range("border_bearing_rad", c.border_bearing_rad, -1.0, 10.0);
  node.read_in_range("border_pixels", c.border_pixels, -1.0, 1e4);
  node.read("cardinality_moves", c.cardinality_moves);
  node.read_in_range("birth_responsibility", c.birth_responsibility, 0.0, 1.0);
  node.read_in_range("birth_radius_m", c.birth_radius_m, -1.0, 1e6);
  node.read_in_range("birth_min_support", c.birth_min_support, 1, 1000000);
  node.read_in_range("death_ratio", c.death_ratio, 0.0, 1.0);
  node.read_in_range("merge_distance_m", c.merge_distance_m, -1.0, 1e6);
  node.read_in_range("incremental_steps", c.incremental_steps, 0, 1000000);
  node.read_in_range("incremental_window", c.incremental_window, 0, 1000000);
  node.read_in_range("initial_pose_search", c.initial_pose_search, 0, 1001);
  node.finish();
  validate_mlslam_config(c);
}

void validate_mlslam_config(const MlSlamConfig& c) {
  if (c.association != "rfs" && c.association != "nearest_neighbour") {
    throw ConfigError("mlslam.association must be rfs or nearest_neighbour, got '" + c.association + "'");
  }
  if (c.linear_solver != "auto" && c.linear_solver != "dense_schur" && c.linear_solver != "sparse_schur" &&
      c.linear_solver != "iterative_schur" && c.linear_solver != "sparse_normal_cholesky") {
    throw ConfigError(
        "mlslam.linear_solver must be auto, dense_schur, sparse_schur, iterative_schur or "
        "sparse_normal_cholesky, got '" +
        c.linear_solver + "'");
  }
  if (c.motion_noise != "configured" && c.motion_noise != "estimated") {
    throw ConfigError("mlslam.motion_noise must be configured or estimated, got '" + c.motion_noise + "'");
  }
  if (c.max_rounds < 1 || c.solver_iterations < 1 || c.max_assignments < 1) {
    throw ConfigError("mlslam.max_rounds, solver_iterations and max_assignments must be at least 1");
  }
  if (c.gate <= 0.0) throw ConfigError("mlslam.gate must be positive");
  if (!(c.initial_trust_region_radius > 0.0))
    throw ConfigError("mlslam.initial_trust_region_radius must be positive");
  if (c.initial_pose_search < 0 || c.initial_pose_search > 1001)
    throw ConfigError("mlslam.initial_pose_search must be 0..1001");
  if (c.incremental_window != 0 && c.incremental_window <= c.incremental_steps)
    throw ConfigError("mlslam.incremental_window must be 0 or more than incremental_steps (" +
                      std::to_string(c.incremental_steps) + "), got " + std::to_string(c.incremental_window));
}

}  // namespace glmbslam::backend
