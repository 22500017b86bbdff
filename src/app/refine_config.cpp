#include "app/refine_config.hpp"

#include "app/loop_config.hpp"

namespace glmbslam::app {

backend::MlSlamConfig RefineSettings::default_stereo_mlslam_config() {
  backend::MlSlamConfig c;
  c.max_rounds =
      30;  // KITTI raw 0001 seed 0, refined ATE: 10 rounds 0.0606 m, 30 (converged after 19) 0.0571 m
  c.solver_iterations =
      3;  // the E-step re-weights between short M-steps (rendered 07, 300 frames: same optimum)
  c.relative_tolerance =
      3e-3;  // the last rounds add little: rendered 07, 14 -> 9 rounds, ATE 0.0935 -> 0.0939 m
  c.linear_solver = "auto";
  c.border_range_m = 0.0;  // 2 % of the maximum depth
  c.border_pixels = 0.0;   // the pixel σ
  // births, deaths and merges: each tried on every scan that may see the landmark, the dominant cost of a
  // solve on a stereo map of thousands of landmarks (config key refine.mlslam.cardinality_moves)
  c.cardinality_moves = false;
  c.birth_radius_m = 0.3;  // unexplained measurements triangulating this close form one landmark
  c.merge_distance_m = 0.1;
  c.incremental_steps = 0;  // not used by the refinement (it starts from the filter's estimate)
  return c;
}

backend::MlSlamConfig RefineSettings::final_pass_mlslam_config() const {
  backend::MlSlamConfig c = ml;
  c.solver_iterations = final_solver_iterations;
  c.initial_trust_region_radius = final_trust_region_radius;
  return c;
}

void load_refine_config(ConfigNode node, RefineSettings& c) {
  node.read("enabled", c.enabled);
  node.read_in_range("window", c.window, 0, 100000);
  if (c.window == 1) node.fail("window", "must be 0 (no online window) or at least 2 frames");
  node.read_in_range("every", c.every, 1, 100000);
  node.read("final", c.final_pass);
  node.read_in_range("window_rounds", c.window_rounds, 1, 1000);
  node.read_choice("final_start", c.final_start, {"windows", "filter"});
  node.read_in_range("final_solver_iterations", c.final_solver_iterations, 1, 10000);
  node.read_in_range("final_trust_region_radius", c.final_trust_region_radius, 1e-6, 1e16);
  node.read("loop_closure", c.loop_closure);
  if (node.has("loop")) load_loop_config(node.child("loop"), c.loop);
  if (node.has("mlslam")) backend::load_mlslam_config(node.child("mlslam"), c.ml);
  node.finish();
}

}  // namespace glmbslam::app
