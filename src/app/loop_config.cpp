#include "app/loop_config.hpp"

namespace glmbslam::app {

void load_loop_config(ConfigNode node, LoopDetectorOptions& o) {
  node.read_in_range<std::size_t>("keyframe_every", o.keyframe_every, 1, 100000);
  node.read_in_range<std::size_t>("min_gap_frames", o.min_gap_frames, 1, 100000000);
  node.read_in_range("search_radius_m", o.search_radius_m, 0.0, 1e6);
  node.read_in_range("search_radius_per_m", o.search_radius_per_m, 0.0, 10.0);
  node.read_in_range("max_search_radius_m", o.max_search_radius_m, 0.0, 1e6);
  node.read_in_range("max_view_angle_deg", o.max_view_angle_deg, 0.0, 180.0);
  node.read_in_range<std::size_t>("candidates", o.candidates, 1, 1000);
  node.read_in_range("max_depth_m", o.max_depth_m, 0.1, 1e6);
  node.read_in_range<std::size_t>("max_points", o.max_points, 3, 100000);
  node.read_in_range("max_hamming", o.max_hamming, 0, 256);
  node.read_in_range("ratio", o.ratio, 0.0, 1.0);
  node.read_in_range("inlier_px", o.inlier_px, 0.0, 1e3);
  node.read_in_range("ransac_iterations", o.ransac_iterations, 1, 1000000);
  node.read_in_range<std::size_t>("min_inliers", o.min_inliers, 3, 100000);
  node.read_in_range("sigma_translation_m", o.sigma_translation_m, 1e-9, 1e6);
  node.read_in_range("sigma_rotation_rad", o.sigma_rotation_rad, 1e-12, 10.0);
  node.finish();
}

}  // namespace glmbslam::app
