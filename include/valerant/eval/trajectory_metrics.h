#pragma once
// Accuracy of a SLAM run against ground truth (engine world only): absolute
// trajectory error after a Sim(3) alignment (Umeyama), as a share of the path length,
// rotation error, and depth AbsRel on confident pixels after one median scale for the
// whole sequence (monocular depth has an arbitrary scale).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

namespace valerant {

// truth ~ scale * rotation * estimate + translation
struct Sim3 {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
};

// Least-squares Sim(3) between matched points (Eigen::umeyama). Throws InputError for
// different lengths, fewer than 3 points, or estimate points that do not spread (no
// scale can be fitted).
Sim3 alignSim3(const std::vector<Eigen::Vector3d>& estimate, const std::vector<Eigen::Vector3d>& truth);

// The Sim(3) of a path whose camera centres lie on a line: positions fix the line's
// direction, scale and offset, but not the roll about it (Umeyama picks it from noise,
// and a floor can end up as a wall). The rotation is then the cameras' mean relative
// orientation (chordal L2), scale and translation the least squares given it; nullopt
// when that scale is not positive (the path runs against the orientations). Throws
// InputError as alignSim3 does.
std::optional<Sim3> alignSim3ByOrientation(const std::vector<Eigen::Isometry3d>& estimate, const std::vector<Eigen::Isometry3d>& truth);

struct TrajectoryError {
  int frames = 0;
  double path_length = 0;        // of the truth, in its units
  bool aligned = false;          // false: the estimate did not translate, no Sim(3)
  Sim3 alignment;
  double ate_rmse = 0;           // truth units; without alignment: spread of the truth
  double ate_percent = 0;        // ate_rmse / path_length * 100 (NaN when path_length ~ 0)
  double rotation_rmse_deg = 0;  // after the best rotation between the two trajectories
};

// Camera poses (camera_to_world) of the same frames; aligned by alignSim3, or by
// alignSim3ByOrientation when the estimated centres are collinear (their second
// principal extent under a tenth of the first) and it gives a positive scale. Throws InputError for different
// lengths or an empty trajectory.
TrajectoryError trajectoryError(const std::vector<Eigen::Isometry3d>& estimate,
                                const std::vector<Eigen::Isometry3d>& truth);

// Roll and pitch error per frame, degrees: the angle between the world's `up` (in the
// truth frame) as the true camera sees it and as the estimated camera sees it once
// rotated into the truth frame by `rotation` (an alignment's). A heading error leaves it
// unchanged. Throws InputError for different lengths.
std::vector<double> tiltErrorsDeg(const std::vector<Eigen::Isometry3d>& estimate,
                                  const std::vector<Eigen::Isometry3d>& truth, const Eigen::Matrix3d& rotation,
                                  const Eigen::Vector3d& up);

struct DepthError {
  double abs_rel = 0;             // mean |s d - d*| / d* over confident pixels (NaN: none)
  double scale = 0;               // s: median of d* / d over confident pixels
  double confident_fraction = 0;  // confident pixels / pixels with finite truth
  long confident_pixels = 0;
  long truth_pixels = 0;
};

// Per-frame estimated depth (CV_32F, any units, NaN unknown) and confidence, truth depth
// (CV_32F metres, NaN unknown); frames with empty estimates count as unconfident.
// Throws InputError when the lists or image sizes disagree.
DepthError depthError(const std::vector<cv::Mat>& estimate, const std::vector<cv::Mat>& confidence,
                      const std::vector<cv::Mat>& truth, double min_confidence);

}  // namespace valerant
