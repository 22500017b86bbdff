#include "frontend/frontend_config.hpp"

namespace glmbslam::frontend {

FrontendConfig load_frontend_config(ConfigNode& node) {
  FrontendConfig c;
  {
    ConfigNode n = node.child("orb");
    OrbConfig& o = c.orb;
    n.read_in_range("features", o.features, 10, 100000);
    n.read_in_range("levels", o.levels, 1, 16);
    n.read_in_range("scale_factor", o.scale_factor, 1.01, 2.0);
    n.read_in_range("fast_threshold", o.fast_threshold, 1, 255);
    n.read_in_range("min_fast_threshold", o.min_fast_threshold, 1, 255);
    n.read_in_range("cell_size", o.cell_size, 10, 500);
    n.read_in_range("edge_threshold", o.edge_threshold, 16, 64);
    n.read("parallel", o.parallel);
    n.finish();
  }
  {
    ConfigNode n = node.child("stereo");
    StereoMatchConfig& s = c.stereo;
    n.read_in_range("min_depth_m", s.min_depth_m, 0.01, 1e4);
    n.read_in_range("max_depth_m", s.max_depth_m, 0.02, 1e6);
    if (s.max_depth_m <= s.min_depth_m) n.fail("max_depth_m", "must exceed min_depth_m");
    n.read_in_range("row_band_px", s.row_band_px, 0.0, 50.0);
    n.read_in_range("max_octave_difference", s.max_octave_difference, 0, 16);
    n.read_in_range("max_hamming", s.max_hamming, 1, 256);
    n.read_in_range("ratio", s.ratio, 0.1, 1.0);
    n.read_in_range("sad_half_window", s.sad_half_window, 1, 15);
    n.read_in_range("sad_search_radius", s.sad_search_radius, 1, 20);
    n.read_in_range("outlier_sad_factor", s.outlier_sad_factor, 1.0, 100.0);
    n.read_choice("subpixel_cost", s.subpixel_cost, {"centre", "zero_mean"});
    n.read_choice("subpixel_refine", s.subpixel_refine, {"fit", "lk"});
    n.read("gain_compensation", s.gain_compensation);
    n.read_in_range("pixel_sigma", s.pixel_sigma, 1e-3, 100.0);
    n.finish();
  }
  {
    ConfigNode n = node.child("vo");
    VoConfig& v = c.vo;
    n.read_in_range("search_radius_px", v.search_radius_px, 1.0, 2000.0);
    n.read_in_range("wide_search_radius_px", v.wide_search_radius_px, 1.0, 5000.0);
    n.read_in_range("max_hamming", v.max_hamming, 1, 256);
    n.read_in_range("ratio", v.ratio, 0.1, 1.0);
    n.read_in_range("min_matches", v.min_matches, 4, 100000);
    n.read_in_range("min_inliers", v.min_inliers, 4, 100000);
    n.read_in_range("ransac_iterations", v.ransac_iterations, 1, 100000);
    n.read_in_range("ransac_reprojection_px", v.ransac_reprojection_px, 0.1, 100.0);
    n.read_in_range("ransac_confidence", v.ransac_confidence, 0.5, 0.999999);
    n.read_choice("refiner", v.refiner, {"ceres", "gauss_newton"});
    n.read_in_range("huber_delta", v.huber_delta, 0.1, 100.0);
    n.read_in_range("chi2_threshold", v.chi2_threshold, 0.1, 1000.0);
    n.read_in_range("refine_rounds", v.refine_rounds, 1, 10);
    n.read_in_range("max_iterations", v.max_iterations, 1, 1000);
    n.read("rematch_after_pnp", v.rematch_after_pnp);
    n.read("consensus_first", v.consensus_first);
    n.read_in_range("repeat_sigma_translation_m", v.repeat_sigma_translation_m, 1e-6, 1e3);
    n.read_in_range("repeat_sigma_rotation_rad", v.repeat_sigma_rotation_rad, 1e-7, 3.2);
    n.read_in_range("fallback_covariance_scale", v.fallback_covariance_scale, 1.0, 1e6);
    n.read_in_range("fallback_sigma_translation_m", v.fallback_sigma_translation_m, 0.0, 1e3);
    n.read_in_range("fallback_sigma_rotation_rad", v.fallback_sigma_rotation_rad, 0.0, 3.2);
    n.finish();
  }
  node.finish();
  return c;
}

}  // namespace glmbslam::frontend
