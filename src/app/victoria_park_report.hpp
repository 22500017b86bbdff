#pragma once
// report.html of `glmbslam run` on Victoria Park (eval/html_report.hpp): the estimated path and map
// (coloured by existence) over the GPS fixes, the error against GPS over time, ESS and time per step, the
// metrics; with --refine ml the refined path, map and error beside the filter's.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "io/pcd_writer.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {

struct VictoriaParkReportInput {
  const std::vector<io::GpsFix>* gps = nullptr;       ///< the fixes the error is measured against
  std::vector<double> x, y;                           ///< estimated laser position per step
  const std::vector<io::MapPoint>* map = nullptr;     ///< final map (z = 0)
  const std::vector<double>* error_time_s = nullptr;  ///< scan time of each GPS comparison
  const std::vector<double>* error_m = nullptr;       ///< ‖p̂ − p_gps‖ of each
  const std::vector<double>* ess = nullptr;           ///< ESS / N per step
  const std::vector<double>* ms = nullptr;            ///< time per step [ms]
  // --refine ml: the RFS-ML refinement beside the filter (refined_map null without it)
  std::vector<double> refined_x, refined_y;
  const std::vector<io::MapPoint>* refined_map = nullptr;
  const std::vector<double>* refined_error_time_s = nullptr;
  const std::vector<double>* refined_error_m = nullptr;
};

void write_victoria_park_report(const std::string& path, const VictoriaParkReportInput& input,
                                const nlohmann::json& metrics);

}  // namespace glmbslam::app
