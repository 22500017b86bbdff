#pragma once
// The outputs of `glmbslam run` on Victoria Park (listed in victoria_park_run.cpp's header): metrics.json,
// trajectory, map and GPS errors of the filter (and of the refinement with --refine ml), trajectory.png,
// report.html, and the one-line summary on stdout.
#include <filesystem>
#include <vector>

#include "app/run_options.hpp"
#include "app/victoria_park_config.hpp"
#include "app/victoria_park_record.hpp"
#include "io/victoria_park.hpp"

namespace glmbslam::app {

/// Writes every output of the run into `out` (created if needed), evaluated against `gps` (the filtered
/// fixes; the raw ones come from `data`) at the scan `times`.
void write_victoria_park_outputs(const std::filesystem::path& out, const VictoriaParkConfig& cfg,
                                 const RunOptions& options, const io::VictoriaParkData& data,
                                 const std::vector<io::GpsFix>& gps, const std::vector<double>& times,
                                 const VpRunRecord& rec, const io::GpsFilterResult& filt);

}  // namespace glmbslam::app
