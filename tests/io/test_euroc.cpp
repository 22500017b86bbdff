// EuRoC ASL reader: the parsers on small trees written here (malformed variants included), pairing of unequal
// camera lists, the rectified calibration, ground truth expressed like KITTI's, and the real euroc_micro
// slice.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/lie.hpp"
#include "fake_kitti.hpp"
#include "io/euroc.hpp"
#include "io/stereo_dataset.hpp"
#include "support/test_data.hpp"

namespace glmbslam::test {
namespace {

using io::EurocDataset;

constexpr const char* kTbsCam0 =
    "[0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,\n"
    "   0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,\n"
    "  -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,\n"
    "   0.0, 0.0, 0.0, 1.0]";
constexpr const char* kTbsCam1 =
    "[0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556,\n"
    "   0.999598781151, 0.0130119051815, 0.0251588363115, 0.0453689425024,\n"
    "  -0.0253898008918, 0.0179005838253, 0.999517347078, 0.00786212447038,\n"
    "   0.0, 0.0, 0.0, 1.0]";

std::string sensor_yaml(const std::string& tbs, const std::string& intrinsics, const std::string& distortion,
                        const std::string& resolution = "[64, 48]") {
  return "%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\ncomment: VI-Sensor\n\nT_BS:\n  "
         "cols: 4\n"
         "  rows: 4\n  data: " +
         tbs + "\n\nrate_hz: 20\nresolution: " + resolution +
         "\ncamera_model: pinhole\nintrinsics: " + intrinsics +
         " #fu, fv, cu, cv\n"
         "distortion_model: radial-tangential\ndistortion_coefficients: " +
         distortion + "\n";
}

/// A small ASL tree: cam0 with `left` frames, cam1 with `right` (timestamps 1e9 + 5e7·i ns), ground truth
/// every 5 ms moving 1 m/s along the body x axis.
fs::path write_asl(const fs::path& root, int left, int right) {
  const fs::path mav = root / "mav0";
  for (int c = 0; c < 2; ++c) {
    const fs::path cam = mav / ("cam" + std::to_string(c));
    const int n = c == 0 ? left : right;
    std::string csv = "#timestamp [ns],filename\n";
    for (int i = 0; i < n; ++i) {
      const std::string t = std::to_string(1000000000LL + 50000000LL * i);
      csv += t + "," + t + ".png\n";
      write_image(cam / "data" / (t + ".png"), 64, 48, i);
    }
    write_text(cam / "data.csv", csv);
    write_text(cam / "sensor.yaml", sensor_yaml(c == 0 ? kTbsCam0 : kTbsCam1, "[45.8, 45.7, 32.2, 24.3]",
                                                "[-0.28, 0.07, 0.0002, 0.00002]"));
  }
  std::string gt =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []\n";
  for (int k = 0; k < 400; ++k) {
    const long long t = 999000000LL + 5000000LL * k;
    gt += std::to_string(t) + "," + std::to_string(1.0 + (t - 1000000000LL) * 1e-9) +
          ",2.0,0.5,1.0,0.0,0.0,0.0\n";
  }
  write_text(mav / "state_groundtruth_estimate0" / "data.csv", gt);
  return root;
}

TEST(EurocFiles, ParsersReadTheAslFiles) {
  const fs::path root = write_asl(fresh_temp_dir("euroc"), 3, 3);
  const auto images = io::read_euroc_camera_csv((root / "mav0/cam0/data.csv").string());
  ASSERT_EQ(images.size(), 3u);
  EXPECT_EQ(images[1].timestamp_ns, 1050000000LL);
  EXPECT_EQ(images[1].filename, "1050000000.png");
  const auto s = io::read_euroc_sensor_yaml((root / "mav0/cam0/sensor.yaml").string());
  EXPECT_DOUBLE_EQ(s.fu, 45.8);
  EXPECT_DOUBLE_EQ(s.cv, 24.3);
  EXPECT_EQ(s.width, 64);
  EXPECT_EQ(s.height, 48);
  ASSERT_EQ(s.distortion.size(), 4u);
  EXPECT_DOUBLE_EQ(s.distortion[0], -0.28);
  EXPECT_NEAR(s.T_BS.translation().y(), -0.064676986768, 1e-12);
  EXPECT_NEAR((s.T_BS.linear().transpose() * s.T_BS.linear() - Eigen::Matrix3d::Identity()).norm(), 0.0,
              1e-12);
  const auto gt =
      io::read_euroc_groundtruth_csv((root / "mav0/state_groundtruth_estimate0/data.csv").string());
  ASSERT_EQ(gt.size(), 400u);
  EXPECT_NEAR(gt[1].T_WB.translation().x(), 1.0 - 0.001 + 0.005, 1e-9);
}

TEST(EurocFiles, MalformedFilesAreOneLineErrorsNamingTheFile) {
  const fs::path dir = fresh_temp_dir("euroc_bad");
  const fs::path csv = dir / "data.csv";
  auto camera_csv = [&](const std::string& text, const std::string& problem, const std::string& where) {
    write_text(csv, text);
    expect_input_error([&] { io::read_euroc_camera_csv(csv.string()); }, where, problem);
  };
  camera_csv("#timestamp [ns],filename\n", "lists no image", csv.string());
  camera_csv("#h\n100,100.png\n90,90.png\n", "not strictly increasing", csv.string() + ":3");
  camera_csv("#h\n100\n", "expected 'timestamp_ns,filename'", csv.string() + ":2");
  camera_csv("#h\n1e5,1.png\n", "not a non-negative integer", csv.string() + ":2");
  camera_csv("#h\n100,../x.png\n", "bad image file name", csv.string() + ":2");
  expect_input_error([&] { io::read_euroc_camera_csv((dir / "none.csv").string()); }, "none.csv",
                     "not found");

  const fs::path yaml = dir / "sensor.yaml";
  auto sensor = [&](const std::string& text, const std::string& problem) {
    write_text(yaml, text);
    expect_input_error([&] { io::read_euroc_sensor_yaml(yaml.string()); }, yaml.string(), problem);
  };
  const std::string good =
      sensor_yaml(kTbsCam0, "[45.8, 45.7, 32.2, 24.3]", "[-0.28, 0.07, 0.0002, 0.00002]");
  write_text(yaml, good);
  EXPECT_NO_THROW(io::read_euroc_sensor_yaml(yaml.string()));
  sensor(sensor_yaml(kTbsCam0, "[45.8, 45.7, 32.2]", "[0, 0, 0, 0]"),
         "'intrinsics' has 3 values, expected 4");
  sensor(sensor_yaml(kTbsCam0, "[45.8, -1, 32.2, 24.3]", "[0, 0, 0, 0]"), "focal lengths must be positive");
  sensor(sensor_yaml(kTbsCam0, "[45.8, 45.7, 99.0, 24.3]", "[0, 0, 0, 0]"), "principal point");
  sensor(sensor_yaml(kTbsCam0, "[45.8, 45.7, 32.2, 24.3]", "[0, x, 0, 0]"), "not a finite number");
  sensor(sensor_yaml("[1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]", "[45.8, 45.7, 32.2, 24.3]",
                     "[0, 0, 0, 0]"),
         "T_BS is not a rigid transform");
  sensor(sensor_yaml(kTbsCam0, "[45.8, 45.7, 32.2, 24.3]", "[0, 0, 0, 0]", "[64]"),
         "'resolution' has 1 values");
  std::string no_model = good;
  no_model.replace(no_model.find("camera_model"), 12, "camera_mode");
  sensor(no_model, "missing key 'camera_model'");
  sensor("%YAML:1.0\nT_BS: [unclosed\n", "not valid YAML");

  const fs::path gt = dir / "gt.csv";
  auto ground_truth = [&](const std::string& text, const std::string& problem, const std::string& where) {
    write_text(gt, text);
    expect_input_error([&] { io::read_euroc_groundtruth_csv(gt.string()); }, where, problem);
  };
  ground_truth("#h\n100,1,2,3,1,0,0\n", "expected at least 8", gt.string() + ":2");
  ground_truth("#h\n100,1,2,3,0,0,0,0\n", "quaternion has zero norm", gt.string() + ":2");
  ground_truth("#h\n100,1,2,nan,1,0,0,0\n", "column 4 is not a finite number", gt.string() + ":2");
  ground_truth("#h\n100,1,2,3,1,0,0,0\n100,1,2,3,1,0,0,0\n", "not strictly increasing", gt.string() + ":3");
}

TEST(EurocDataset, PairsUnequalListsRectifiesAndExpressesGroundTruthLikeKitti) {
  const fs::path root = write_asl(fresh_temp_dir("euroc_ds"), 6, 8);
  EXPECT_EQ(io::detect_dataset_format(root.string()), io::DatasetFormat::kEuroc);
  EXPECT_EQ(io::detect_dataset_format((root / "mav0").string()), io::DatasetFormat::kEuroc);
  const auto ds = io::open_stereo_dataset(root.string());
  ASSERT_EQ(ds->size(), 6u);  // the two extra right images are dropped
  EXPECT_NEAR(ds->timestamps()[5], 0.25, 1e-12);
  const StereoCalibration& c = ds->calibration();
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  EXPECT_NEAR(c.baseline, 0.110, 0.002);  // the EuRoC rig's baseline
  const io::StereoFrame f = ds->load(2);
  EXPECT_EQ(f.left.cols, 64);
  EXPECT_EQ(f.right.rows, 48);
  ASSERT_TRUE(ds->ground_truth().has_value());
  EXPECT_TRUE(ds->ground_truth_mask().empty());
  const PoseList& gt = *ds->ground_truth();
  EXPECT_LT((gt[0].matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-12);
  // the body moves 0.05 m a frame; the camera (rotated, offset) moves the same distance
  EXPECT_NEAR(gt[4].translation().norm(), 0.20, 1e-6);
  EXPECT_LT(rotation_angle(gt[4].linear()), 1e-6);  // acos resolves angles near 0 to ~sqrt(eps)
}

TEST(EurocDataset, FramesOutsideTheGroundTruthAreMaskedAndBrokenGroundTruthIsIgnored) {
  const fs::path root = write_asl(fresh_temp_dir("euroc_gt"), 6, 6);
  const fs::path gt = root / "mav0/state_groundtruth_estimate0/data.csv";
  // records only up to 1.12 s: frames 0..2 (1.00, 1.05, 1.10 s) have ground truth, 3..5 not
  std::string text = "#h\n";
  for (int k = 0; k < 25; ++k) {
    const long long t = 1000000000LL + 5000000LL * k;
    text += std::to_string(t) + "," + std::to_string((t - 1000000000LL) * 1e-9) + ",0,0,1,0,0,0\n";
  }
  write_text(gt, text);
  {
    EurocDataset ds(root.string());
    ASSERT_TRUE(ds.ground_truth().has_value());
    ASSERT_EQ(ds.ground_truth_mask().size(), 6u);
    EXPECT_EQ(ds.ground_truth_mask(), (std::vector<char>{1, 1, 1, 0, 0, 0}));
  }
  write_text(gt, "#h\n100,1,2,3\n");
  EurocDataset broken(root.string());  // the images still run
  EXPECT_FALSE(broken.ground_truth().has_value());
  EXPECT_EQ(broken.size(), 6u);
}

TEST(EurocDataset, MissingImagesAndSensorsAreErrors) {
  const fs::path root = write_asl(fresh_temp_dir("euroc_missing"), 3, 3);
  fs::remove(root / "mav0/cam1/data/1050000000.png");
  expect_input_error([&] { EurocDataset{root.string()}; }, "1050000000.png", "not found");
  const fs::path root2 = write_asl(fresh_temp_dir("euroc_nocam"), 3, 3);
  fs::remove(root2 / "mav0/cam1/sensor.yaml");
  // a mav0/ folder is taken for EuRoC, and its reader names the missing file
  EXPECT_EQ(io::detect_dataset_format(root2.string()), io::DatasetFormat::kEuroc);
  expect_input_error([&] { io::open_stereo_dataset(root2.string(), io::DatasetFormat::kAuto, ""); },
                     "missing: " + (root2 / "mav0/cam1/sensor.yaml").string(), "not an EuRoC folder");
  const fs::path root3 = fresh_temp_dir("euroc_none");
  expect_input_error([&] { io::detect_dataset_format(root3.string()); }, root3.string(),
                     "unknown dataset layout");
}

TEST(EurocDataset, RealMicroSlice) {
  GLMBSLAM_REQUIRE_DATA(dir, "euroc_micro");
  const auto ds = io::open_stereo_dataset(dir.string());
  EXPECT_EQ(ds->size(), 95u);  // cam0 lists 95 frames, cam1 99: paired by timestamp
  const StereoCalibration& c = ds->calibration();
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_NEAR(c.baseline, 0.110, 0.001);
  EXPECT_GT(c.fx, 400.0);
  EXPECT_LT(c.fx, 470.0);
  ASSERT_TRUE(ds->ground_truth().has_value());
  // the drone hovers: the ground truth moves a few millimetres
  for (const Pose3& T : *ds->ground_truth()) EXPECT_LT(T.translation().norm(), 0.01);
  const io::StereoFrame f = ds->load(0);
  EXPECT_EQ(f.left.cols, 752);
  EXPECT_EQ(f.right.rows, 480);
  EXPECT_NEAR(ds->timestamps()[1], 0.05, 1e-6);
}

}  // namespace
}  // namespace glmbslam::test
