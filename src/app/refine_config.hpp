#pragma once
// Settings of the stereo refinement stage (`glmbslam run --refine ml`, pipeline/refinement_stage.hpp): RFS
// maximum-likelihood SLAM (paper 004, backend/mlslam) on the filter's trajectory and map, over a sliding
// window online and over the whole run at the end. YAML mapping `refine` of the stereo config
// (config/kitti*.yaml document every key); its child `mlslam` holds the solver's settings
// (backend/mlslam/mlslam_config.hpp).
#include <string>

#include "app/pipeline/loop_detector.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "core/config_node.hpp"

namespace glmbslam::app {

struct RefineSettings {
  bool enabled = false;    ///< run the refinement (also `--refine ml`)
  int window = 10;         ///< frames of the online sliding window (its first pose held); 0 = no window
  int every = 5;           ///< solve the window every this many frames
  bool final_pass = true;  ///< key `final`: one solve over the whole run at the end (replaces the online one)
  int window_rounds = 3;   ///< EM rounds of a window solve (the final pass uses mlslam.max_rounds)
  /// The final pass's M-step: Levenberg–Marquardt iterations (mlslam.solver_iterations is the windows') and
  /// initial trust region radius (mlslam.initial_trust_region_radius is the windows'). One nearly undamped
  /// step per EM round: a damped start holds back the slow bends of a long trajectory (MlSlamConfig), and the
  /// E-step re-weights after every step anyway (docs/investigations.md, "The final pass's M-step").
  int final_solver_iterations = 1;
  double final_trust_region_radius = 1e8;
  /// Where the final pass starts: "windows" (the online windows' refined trajectory, each landmark moved
  /// with the refinement of the frame that mapped it; the filter's when there is no window) or "filter"
  /// (the filter's trajectory and map). EM only climbs to the nearest optimum, and the windows' start is
  /// nearer a better one: rendered 01 refined t_rel 0.667 % from the filter, 0.293 % from the windows.
  std::string final_start = "windows";
  /// before the final pass, revisits close the loops of its start (pipeline/loop_closing.hpp)
  bool loop_closure = true;
  LoopDetectorOptions loop;  ///< key `loop`
  backend::MlSlamConfig ml = default_stereo_mlslam_config();

  static backend::MlSlamConfig default_stereo_mlslam_config();
  /// `ml` with the final pass's M-step settings.
  backend::MlSlamConfig final_pass_mlslam_config() const;
};

/// Reads `node` (the `refine` mapping) over `c`; throws ConfigError naming the key on a bad value.
void load_refine_config(ConfigNode node, RefineSettings& c);

}  // namespace glmbslam::app
