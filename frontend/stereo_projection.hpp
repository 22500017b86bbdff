#pragma once
// The rectified stereo projection model z = π(p) = (u_L, v, u_R), triangulation and their Jacobians
// (pose Jacobians in the right-perturbation convention of core/lie.hpp). The maths lives in
// core/stereo_camera.hpp so that the backend shares it; this header makes it part of the frontend's API.
#include "core/stereo_camera.hpp"

namespace glmbslam::frontend {

using glmbslam::Matrix36d;
using glmbslam::StereoCamera;

}  // namespace glmbslam::frontend
