// glmbslam: stereo δ-GLMB-SLAM 2.0 with its frontend, evaluation, renderer and the papers' baselines.
#include <cstdio>
#include <exception>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "app/commands.hpp"
#include "app/global_options.hpp"
#include "app/passive_openmp.hpp"
#include "core/blas_threads.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/logging.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"

int main(int argc, char** argv) {
  glmbslam::app::ensure_passive_openmp(argv);  // before any parallel region: see passive_openmp.hpp
  glmbslam::fix_blas_thread_count();
  CLI::App app{
      "glmbslam: stereo visual SLAM with δ-GLMB-SLAM 2.0 (labelled random-finite-set maps in a "
      "Rao-Blackwellised particle filter), its stereo frontend, KITTI evaluation and the papers' baselines."};
  app.require_subcommand(1);
  std::string log_level = "info";
  int threads = 0;
  bool quiet = false;
  auto* log_level_option = app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")
                               ->capture_default_str();
  app.add_flag("--quiet", quiet,
               "for scripts: no progress bar and no info lines (log level warn unless --log-level is given); "
               "warnings, errors and the results summary stay");
  auto* threads_option =
      app.add_option(
             "--threads", threads,
             "worker threads (0 = all cores; overrides a config's threads:); the sparse Cholesky of the "
             "refinement adds 2 BLAS threads of its own (core/blas_threads.hpp)")
          ->check(CLI::Range(0, 1024))
          ->capture_default_str();
  app.parse_complete_callback([&] {
    glmbslam::set_log_level(quiet && log_level_option->count() == 0 ? "warn" : log_level);
    if (quiet) glmbslam::ProgressReporter::set_enabled(false);
    glmbslam::set_thread_count(threads);
    if (threads_option->count() > 0) glmbslam::app::global_options().threads = threads;
  });

  glmbslam::app::register_run_command(app);
  glmbslam::app::register_eval_command(app);
  glmbslam::app::register_render_command(app);
  glmbslam::app::register_vo_command(app);
  glmbslam::app::register_sim_command(app);

  // SIGINT/SIGTERM stop a run at its next frame boundary; it writes what it has and exits 130/143.
  glmbslam::install_interrupt_handlers();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const glmbslam::InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const glmbslam::ConfigError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return glmbslam::interrupt_exit_code();
}
