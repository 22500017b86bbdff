// `glmbslam vo`: stereo visual odometry only (ORB frontend + frame-to-frame VO), evaluated against ground
// truth when the dataset has it.
//
// Outputs in --out: vo_trajectory.txt (KITTI format, one pose per frame of the range), vo_frames.csv
// (per-frame status, matches, inliers, timings, diagonal of Q_k), metrics.json (eval blocks of
// eval/report.hpp when ground truth exists, end-point drift, timing of each stage, status counts, the stereo
// pair's row alignment `rectification`: app/pipeline/rectification_check_stage.hpp; the cameras' contrast
// `stereo_photometry`: app/pipeline/stereo_photometry_stage.hpp) and
// vo_features.png (features of both images and the stereo matches on a sample frame), report.html (the
// interactive report, app/run_report.hpp) and ground_truth.txt (app/ground_truth_output.hpp). A frame whose
// images cannot be loaded (missing, corrupt, wrong size) is reported and replaced by the VO's
// constant-velocity fallback, so the trajectory keeps one pose per frame; the command fails only if no frame
// at all can be loaded. The poses are also streamed to vo_trajectory.streaming.txt (one line per frame,
// synced; removed once the final files are written); SIGINT/SIGTERM stop at the next frame and write the
// outputs of the frames done ("interrupted": true in metrics.json), then exit with code 130/143
// (core/interrupt.hpp).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "app/commands.hpp"
#include "app/ground_truth_output.hpp"
#include "app/pipeline/rectification_check_stage.hpp"
#include "app/pipeline/stereo_photometry_stage.hpp"
#include "app/pipeline/trajectory_stream_stage.hpp"
#include "app/run_report.hpp"
#include "app/stereo_config.hpp"
#include "core/atomic_file.hpp"
#include "core/config_node.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/lie.hpp"
#include "core/progress.hpp"
#include "core/stopwatch.hpp"
#include "eval/masked_evaluation.hpp"
#include "eval/report.hpp"
#include "frontend/frontend_config.hpp"
#include "frontend/stereo_frontend.hpp"
#include "frontend/visual_odometry.hpp"
#include "io/stereo_dataset.hpp"
#include "io/trajectory_io.hpp"

namespace glmbslam::app {
namespace {

struct VoArgs {
  std::string dataset;
  std::string config;
  std::string format = "auto";
  std::string gt;
  std::string frames;
  std::string out;
  int sample_frame = -1;
};

/// Parses "A:B" (half-open [A, B); either side may be empty) against `n` frames.
std::pair<std::size_t, std::size_t> parse_range(const std::string& s, std::size_t n) {
  if (s.empty()) return {0, n};
  const auto colon = s.find(':');
  if (colon == std::string::npos) throw ConfigError("--frames: expected A:B, got '" + s + "'");
  auto parse = [&](const std::string& t, std::size_t dflt) -> std::size_t {
    if (t.empty()) return dflt;
    try {
      std::size_t pos = 0;
      const long v = std::stol(t, &pos);
      if (pos != t.size() || v < 0) throw std::invalid_argument(t);
      return static_cast<std::size_t>(v);
    } catch (const std::exception&) {
      throw ConfigError("--frames: '" + s + "' is not A:B with non-negative integers");
    }
  };
  const std::size_t a = parse(s.substr(0, colon), 0);
  const std::size_t b = std::min(parse(s.substr(colon + 1), n), n);
  if (a >= b)
    throw ConfigError("--frames: empty range '" + s + "' for a dataset of " + std::to_string(n) + " frames");
  return {a, b};
}

frontend::FrontendConfig load_config(const std::string& path) {
  if (path.empty()) return frontend::FrontendConfig{};
  ConfigNode root = ConfigNode::load_file(path);
  // A full config file holds the other modules' sections too; only `frontend` is read (and checked) here.
  ConfigNode node = root.child("frontend");
  return frontend::load_frontend_config(node);
}

/// The frontend keys the config file leaves out, from the rig's calibration (apply_camera_defaults).
frontend::FrontendConfig with_camera_defaults(const std::string& path, const io::StereoDataset& dataset,
                                              std::size_t first, const frontend::FrontendConfig& config) {
  StereoCalibration calib = dataset.calibration();
  if (calib.width <= 0 || calib.height <= 0) {  // KITTI odometry: the size comes from the images
    const io::StereoFrame probe = dataset.load(first);
    calib.width = probe.left.cols;
    calib.height = probe.left.rows;
  }
  StereoConfig with_rig;
  with_rig.frontend = config;
  apply_camera_defaults(path.empty() ? YAML::Node() : YAML::LoadFile(path), calib, with_rig);
  return with_rig.frontend;
}

cv::Mat draw_features(const cv::Mat& left, const cv::Mat& right, const frontend::StereoFrameFeatures& f) {
  cv::Mat l, r;
  cv::cvtColor(left, l, cv::COLOR_GRAY2BGR);
  cv::cvtColor(right.empty() ? cv::Mat::zeros(left.size(), CV_8U) : right, r, cv::COLOR_GRAY2BGR);
  auto colour = [](int octave) {
    static const cv::Scalar c[] = {{0, 0, 255},   {0, 128, 255}, {0, 255, 255}, {0, 255, 0},
                                   {255, 255, 0}, {255, 0, 0},   {255, 0, 255}, {128, 128, 128}};
    return c[std::clamp(octave, 0, 7)];
  };
  for (const auto& k : f.left.keypoints) cv::circle(l, k.pt, 2 + k.octave, colour(k.octave), 1, cv::LINE_AA);
  for (const auto& k : f.right.keypoints) cv::circle(r, k.pt, 2 + k.octave, colour(k.octave), 1, cv::LINE_AA);
  cv::Mat canvas;
  cv::vconcat(l, r, canvas);
  const float dy = static_cast<float>(left.rows);
  for (std::size_t i = 0; i < f.measurements.size(); i += 1) {
    const auto& m = f.measurements[i];
    const cv::Point2f pl(static_cast<float>(m.z.x()), static_cast<float>(m.z.y()));
    const cv::Point2f pr(static_cast<float>(m.z.z()), static_cast<float>(m.z.y()) + dy);
    // Colour by depth: red near, blue far (log scale 1…80 m).
    const double t = std::clamp(std::log(m.point.z()) / std::log(80.0), 0.0, 1.0);
    const cv::Scalar c(255 * t, 64, 255 * (1 - t));
    if (i % 4 == 0) cv::line(canvas, pl, pr, c, 1, cv::LINE_AA);
    cv::circle(canvas, pl, 3, c, -1, cv::LINE_AA);
    cv::circle(canvas, pr, 3, c, -1, cv::LINE_AA);
  }
  const std::string text = std::to_string(f.left.keypoints.size()) + " / " +
                           std::to_string(f.right.keypoints.size()) + " ORB features, " +
                           std::to_string(f.measurements.size()) +
                           " stereo matches (every 4th joined; colour = depth, red near)";
  cv::putText(canvas, text, {10, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 2, cv::LINE_AA);
  return canvas;
}

void write_png(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<uchar> buf;
  if (!cv::imencode(".png", image, buf)) throw InputError(path.string(), "PNG encoding failed");
  write_text_file_atomically(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
  });
}

nlohmann::json timing_block(const std::string& name, const std::vector<double>& v) {
  const SampleSummary s = summarize(v);
  return {{name + "_ms_median", s.median}, {name + "_ms_p95", s.p95}, {name + "_ms_mean", s.mean}};
}

void run_vo(const VoArgs& a) {
  frontend::FrontendConfig config = load_config(a.config);
  const auto dataset = io::open_stereo_dataset(a.dataset, io::parse_dataset_format(a.format), a.gt);
  const std::filesystem::path out(a.out);
  ensure_writable_directory(out);
  const auto [first, last] = parse_range(a.frames, dataset->size());
  const std::size_t requested = last - first;
  spdlog::info("vo: {} ({} frames, using {}..{})", dataset->name(), dataset->size(), first, last - 1);

  const StereoCalibration& calib = dataset->calibration();
  config = with_camera_defaults(a.config, *dataset, first, config);
  const frontend::StereoFrontend fe(calib, config);
  frontend::RectificationCheck rectification;
  std::vector<double> right_gains;
  frontend::StereoVisualOdometry vo(fe.camera(), config.vo, fe.extractor().scales());
  vo.set_first_frame(first);
  const std::size_t sample =
      a.sample_frame >= 0 ? std::min<std::size_t>(static_cast<std::size_t>(a.sample_frame), requested - 1)
                          : requested / 2;

  PoseList poses;
  poses.reserve(requested);
  StreamedLines streamed(out / kStreamedVoTrajectoryFile);
  set_graceful_interrupts(true);
  Pose3 T = Pose3::Identity();
  std::vector<double> load_ms, frontend_ms, extract_ms, match_ms, vo_ms, total_ms;
  std::vector<frontend::VoEstimate> estimates;
  std::vector<int> measurement_counts;
  std::map<std::string, int> status_counts;
  std::size_t loaded = 0;
  bool png_written = false;
  Stopwatch all;
  ProgressReporter progress(last - first, "vo");
  for (std::size_t i = first; i < last && !interrupt_requested(); ++i) {
    progress.update(i - first);
    Stopwatch sw;
    std::optional<io::StereoFrame> frame;
    try {
      frame = dataset->load(i);
    } catch (const InputError& e) {
      spdlog::warn("vo: frame {}: cannot be loaded ({})", i, e.what());
    }
    load_ms.push_back(sw.elapsed_ms());
    frontend::VoEstimate est;
    int measurements = 0;
    if (frame) {
      ++loaded;
      Stopwatch fsw;
      frontend::StereoFrameFeatures f = fe.process(frame->left, frame->right);
      frontend_ms.push_back(fsw.elapsed_ms());
      extract_ms.push_back(f.extract_ms);
      match_ms.push_back(f.match_ms);
      measurements = static_cast<int>(f.measurements.size());
      est = vo.track(f, frame->timestamp);
      vo_ms.push_back(est.ms);
      rectification.add_frame(i - first, f);
      right_gains.push_back(f.stats.right_gain);
      if (!png_written && i - first >= sample) {  // the sample frame, or the next one that loads
        write_png(out / "vo_features.png", draw_features(frame->left, frame->right, f));
        png_written = true;
      }
    } else {
      est = vo.skip_frame(frontend::VoStatus::kMissingImage, dataset->timestamps()[i]);
    }
    total_ms.push_back(sw.elapsed_ms());
    T = T * est.relative_pose;
    poses.push_back(T);
    streamed.append(io::kitti_pose_line(T));
    estimates.push_back(est);
    measurement_counts.push_back(measurements);
    ++status_counts[frontend::to_string(est.status)];
    spdlog::debug("vo: frame {}: {} measurements, {} matches, {} inliers, {}", i, measurements, est.matches,
                  est.inliers, frontend::to_string(est.status));
  }
  progress.finish();
  const double wall_s = all.elapsed_ms() / 1000.0;
  const std::size_t n = poses.size();
  const bool interrupted = n < requested;
  if (interrupted) {
    spdlog::warn("vo: interrupted after {} of {} frames; writing their outputs", n, requested);
    if (n == 0) return;
  }
  if (loaded == 0) throw InputError(a.dataset, "no frame of the range could be loaded");

  io::write_kitti_poses((out / "vo_trajectory.txt").string(), poses);
  write_text_file_atomically(out / "vo_frames.csv", [&](std::ostream& os) {
    os << "frame,status,measurements,matches,inliers,q_rho_x,q_rho_y,q_rho_z,q_phi_x,q_phi_y,q_phi_z\n";
    for (std::size_t k = 0; k < estimates.size(); ++k) {
      const auto& e = estimates[k];
      os << first + k << ',' << frontend::to_string(e.status) << ',' << measurement_counts[k] << ','
         << e.matches << ',' << e.inliers;
      for (int d = 0; d < 6; ++d) os << ',' << e.covariance(d, d);
      os << '\n';
    }
  });

  nlohmann::json j;
  j["dataset"] = dataset->name();
  j["frames"] = n;
  j["first_frame"] = first;
  j["frames_requested"] = requested;
  j["interrupted"] = interrupted;
  std::optional<PoseList> gt;
  std::optional<eval::TrajectoryEvaluation> evaluation;
  std::vector<char> mask;  // frames with ground truth (empty: all)
  if (dataset->ground_truth()) {
    const PoseList& full = *dataset->ground_truth();
    gt = io::relative_to_first(PoseList(full.begin() + static_cast<std::ptrdiff_t>(first),
                                        full.begin() + static_cast<std::ptrdiff_t>(first + n)));
    if (!dataset->ground_truth_mask().empty()) {
      const auto& m = dataset->ground_truth_mask();
      mask.assign(m.begin() + static_cast<std::ptrdiff_t>(first),
                  m.begin() + static_cast<std::ptrdiff_t>(first + n));
    }
    const eval::TrajectoryEvaluation& e =
        evaluation.emplace(eval::evaluate_trajectory_masked(*gt, poses, mask));
    j["evaluated_frames"] = e.frames;
    j.update(eval::to_json(e));
    const double end_error = (gt->back().translation() - poses.back().translation()).norm();
    j["drift"] = {
        {"end_point_error_m", end_error},
        {"path_length_m", e.path_length_m},
        {"end_point_error_percent", e.path_length_m > 0 ? 100.0 * end_error / e.path_length_m : 0.0}};
    spdlog::info("vo: ATE SE(3) {:.3f} m, end-point error {:.3f} m over {:.1f} m ({:.2f} %)",
                 e.ate.se3_rmse_m, end_error, e.path_length_m,
                 e.path_length_m > 0 ? 100.0 * end_error / e.path_length_m : 0.0);
  }
  // without: removes one of an earlier run
  const bool ground_truth_written = write_ground_truth_file(out, gt ? &*gt : nullptr, mask);
  nlohmann::json timing = {{"fps", static_cast<double>(n) / wall_s}, {"wall_s", wall_s}};
  for (const auto& [name, v] :
       std::vector<std::pair<std::string, const std::vector<double>*>>{{"load", &load_ms},
                                                                       {"frontend", &frontend_ms},
                                                                       {"extract", &extract_ms},
                                                                       {"stereo_match", &match_ms},
                                                                       {"vo", &vo_ms},
                                                                       {"total", &total_ms}}) {
    timing.update(timing_block(name, *v));
    const SampleSummary s = summarize(*v);
    spdlog::info("vo: timing {:<13} median {:7.2f} ms  p95 {:7.2f} ms", name, s.median, s.p95);
  }
  j["timing"] = timing;
  j["vo_status"] = status_counts;
  j["rectification"] = rectification_metrics(rectification.summary());
  j["stereo_photometry"] = stereo_photometry_metrics(right_gains, config.stereo.gain_compensation);
  eval::write_json_file((out / "metrics.json").string(), j);
  VoReportInput report{dataset->name(), first, &poses, &gt, gt ? &*evaluation : nullptr, {}, {}, {}, ""};
  for (std::size_t k = 0; k < estimates.size(); ++k) {
    report.measurements.push_back(measurement_counts[k]);
    report.matches.push_back(estimates[k].matches);
    report.inliers.push_back(estimates[k].inliers);
  }
  if (!a.config.empty()) {
    std::ifstream config(a.config);
    report.config.assign(std::istreambuf_iterator<char>(config), std::istreambuf_iterator<char>());
  }
  write_vo_report((out / "report.html").string(), report, j);
  remove_streamed_trajectories(out);
  // the results summary on stdout, as `run` prints it (kept under --quiet)
  if (evaluation) std::printf("\nVO\n%s", eval::format_table(*evaluation).c_str());
  std::printf("\nframes %zu, %.2f fps (total median %.1f ms)\n", poses.size(),
              static_cast<double>(n) / wall_s, summarize(total_ms).median);
  std::printf(
      "outputs in %s:\n  report       %s  (open in a browser)\n  VO           %s\n  metrics      %s\n"
      "  per frame    %s\n",
      out.string().c_str(), (out / "report.html").string().c_str(),
      (out / "vo_trajectory.txt").string().c_str(), (out / "metrics.json").string().c_str(),
      (out / "vo_frames.csv").string().c_str());
  if (png_written) std::printf("  features     %s\n", (out / "vo_features.png").string().c_str());
  if (ground_truth_written) std::printf("  ground truth %s\n", (out / "ground_truth.txt").string().c_str());
}

}  // namespace

void register_vo_command(CLI::App& app) {
  auto args = std::make_shared<VoArgs>();
  auto* cmd =
      app.add_subcommand("vo", "Stereo visual odometry only: ORB frontend + VO, trajectory and metrics");
  cmd->add_option("dataset", args->dataset,
                  "dataset folder (KITTI odometry sequence, KITTI raw drive or EuRoC MAV sequence)")
      ->required();
  cmd->add_option("--config", args->config, "YAML config; its `frontend` mapping is read");
  cmd->add_option("--format", args->format, "auto, kitti, kitti_raw or euroc")->capture_default_str();
  cmd->add_option("--gt", args->gt, "ground-truth KITTI pose file (overrides the dataset's own)");
  cmd->add_option("--frames", args->frames, "half-open frame range A:B (default: all)");
  cmd->add_option("--sample-frame", args->sample_frame, "frame (within the range) drawn in vo_features.png");
  cmd->add_option("--out", args->out, "output folder")->required();
  cmd->callback([args] { run_vo(*args); });
}

}  // namespace glmbslam::app
