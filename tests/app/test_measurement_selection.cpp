// Selection of the stereo measurements handed to the backend (src/app/measurement_selection.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <vector>

#include "app/measurement_selection.hpp"

namespace glmbslam::app {
namespace {

frontend::StereoMeasurement at(double u, double v, double depth, float response) {
  frontend::StereoMeasurement m;
  m.z = Eigen::Vector3d(u, v, u - 10.0);
  m.point = Eigen::Vector3d(0.0, 0.0, depth);
  m.response = response;
  return m;
}

// Two cells (left and right half of a 2×1 grid), three measurements in each, one out of the depth range.
frontend::StereoMeasurementList two_cells() {
  return {at(10, 10, 5, 30),  at(20, 20, 5, 20),  at(30, 30, 5, 10),     // cell 0
          at(110, 10, 5, 35), at(120, 20, 5, 25), at(130, 30, 90, 99)};  // cell 1 (index 5: too deep)
}

SelectionGrid grid2x1() {
  SelectionGrid g;
  g.columns = 2;
  g.rows = 1;
  g.width = 200.0;
  g.height = 100.0;
  return g;
}

SelectionRules rules(int max_count) {
  SelectionRules r;
  r.min_depth = 1.0;
  r.max_depth = 40.0;
  r.max_octave = 1;
  r.max_count = max_count;
  return r;
}

TEST(MeasurementSelection, TakesTheStrongestOfEachCellInTurnWithinTheDepthRange) {
  const auto chosen = select_measurements(two_cells(), grid2x1(), rules(3));
  EXPECT_EQ(chosen, (std::vector<int>{0, 3, 1}));
  const auto all = select_measurements(two_cells(), grid2x1(), rules(100));
  EXPECT_EQ(std::set<int>(all.begin(), all.end()), (std::set<int>{0, 1, 2, 3, 4}));  // never index 5
}

TEST(MeasurementSelection, PreferredMeasurementsComeFirstInTheirCell) {
  std::vector<char> preferred(6, 0);
  preferred[2] = 1;  // the weakest of cell 0
  preferred[5] = 1;  // out of the depth range: preference does not override the range
  const auto chosen = select_measurements(two_cells(), grid2x1(), rules(4), preferred);
  EXPECT_EQ(chosen, (std::vector<int>{2, 3, 0, 4}));
  // No flags and all-zero flags select the same.
  EXPECT_EQ(select_measurements(two_cells(), grid2x1(), rules(4), std::vector<char>(6, 0)),
            select_measurements(two_cells(), grid2x1(), rules(4)));
}

TEST(MeasurementSelection, SkipsKeypointsAboveTheHighestPyramidLevel) {
  auto list = two_cells();
  list[0].octave = 2;  // the strongest of cell 0: located to σ·1.2², coarser than the model's σ
  list[3].octave = 1;
  const auto chosen = select_measurements(list, grid2x1(), rules(100));
  EXPECT_EQ(std::set<int>(chosen.begin(), chosen.end()), (std::set<int>{1, 2, 3, 4}));
  SelectionRules level0 = rules(100);
  level0.max_octave = 0;
  const auto only0 = select_measurements(list, grid2x1(), level0);
  EXPECT_EQ(std::set<int>(only0.begin(), only0.end()), (std::set<int>{1, 2, 4}));
}

// The VO's frame-to-frame matches (previous_measurement) carry the previous frame's flags forward.
TEST(MeasurementSelection, TrackedFromFollowsTheVoMatches) {
  const std::vector<int> previous_measurement{2, -1, 0, 7, 1};  // 7: beyond the previous frame's list
  const std::vector<char> previous_selected{1, 0, 1};
  EXPECT_EQ(tracked_from(previous_measurement, previous_selected), (std::vector<char>{1, 0, 1, 0, 0}));
  EXPECT_EQ(tracked_from({}, previous_selected), std::vector<char>{});
}

// The control leaves out only what the backend's landmarks carry: "tracked" excludes the measurements handed
// over now whose previous-frame match was handed over too; a newly handed measurement stays in the control.
TEST(MeasurementSelection, ControlExclusionModes) {
  const std::vector<char> selected{1, 1, 0, 1, 0};
  const std::vector<char> tracked_selected{1, 0, 1, 1, 0};  // index 2: tracked but not handed over now
  EXPECT_EQ(control_exclusion("tracked", selected, tracked_selected), (std::vector<char>{1, 0, 0, 1, 0}));
  EXPECT_EQ(control_exclusion("selected", selected, tracked_selected), selected);
  EXPECT_EQ(control_exclusion("none", selected, tracked_selected), (std::vector<char>(5, 0)));
  EXPECT_THROW(control_exclusion("all", selected, tracked_selected), std::invalid_argument);
}

}  // namespace
}  // namespace glmbslam::app
