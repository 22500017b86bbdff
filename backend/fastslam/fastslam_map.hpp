#pragma once
// The landmark map of one FastSLAM particle: one EKF per landmark, sorted by landmark id. Immutable once
// built and shared between particles through shared_ptr<const FastSlamMap>.
#include <algorithm>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::backend {

template <class Meas>
struct FastSlamLandmark {
  std::int64_t id = 0;  ///< the true landmark label ("known" association) or the order of creation ("ml")
  typename Meas::Landmark mean;
  typename Meas::LandmarkCovariance cov;
  int detections = 0;  ///< measurements associated so far
  double score = 0.0;  ///< detections minus p_D per in-view miss (FastSlamConfig::remove_unconfirmed)
  EIGEN_MAKE_ALIGNED_OPERATOR_NEW
};

template <class Meas>
struct FastSlamMap {
  using LandmarkType = FastSlamLandmark<Meas>;
  std::vector<LandmarkType, Eigen::aligned_allocator<LandmarkType>> landmarks;  ///< sorted by id
  std::int64_t next_id = 0;  ///< the id of the next landmark created by "ml" association

  /// Index of the landmark with this id, or −1.
  int find(std::int64_t id) const {
    const auto it = std::lower_bound(landmarks.begin(), landmarks.end(), id,
                                     [](const LandmarkType& l, std::int64_t v) { return l.id < v; });
    return it != landmarks.end() && it->id == id ? static_cast<int>(it - landmarks.begin()) : -1;
  }
  /// Inserts a landmark keeping the order by id (appends when its id is the largest).
  void insert(const LandmarkType& l) {
    const auto it = std::lower_bound(landmarks.begin(), landmarks.end(), l.id,
                                     [](const LandmarkType& a, std::int64_t v) { return a.id < v; });
    landmarks.insert(it, l);
    next_id = std::max(next_id, l.id + 1);
  }
};

}  // namespace glmbslam::backend
