#pragma once
// The keyframe map of the visual SLAM. Keyframes and points are immutable once made
// and held by shared_ptr<const>: branches and snapshots share them, and a change (a
// bundle-adjusted pose or position, a new observation) replaces the changed object in
// the branch's own vector only (copy-on-write). Images and depth never change and are
// shared even between the old and new version of a keyframe.
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace valerant::visual {

// Descriptors of map points seen in one image.
struct PointDescriptors {
  cv::Mat descriptors;      // CV_8U, one row per point
  std::vector<int> points;  // map point id of each row
};

struct KeyframeImages {
  int frame = 0;           // index of the tracked frame
  cv::Mat rgb;             // CV_8UC3, full size
  cv::Mat sweep;           // CV_32F grey at plane-sweep resolution
  cv::Mat depth;           // CV_32F full size, map units at creation, NaN = unknown
  cv::Mat confidence;      // CV_32F full size
  std::vector<int> points; // map points observed when the keyframe was made
  PointDescriptors described;  // for relocalisation (relocalizer.h)
};

struct Keyframe {
  int index = 0;
  Eigen::Isometry3d camera_to_map = Eigen::Isometry3d::Identity();
  std::shared_ptr<const KeyframeImages> images;
};

struct Observation {
  int keyframe = 0;
  Eigen::Vector2d px;
};

struct MapPoint {
  Eigen::Vector3d position;
  std::array<uint8_t, 3> rgb{};
  std::vector<Observation> observations;
};

// Vectors indexed by keyframe index / point id; a culled point is a null pointer.
struct SlamMap {
  std::vector<std::shared_ptr<const Keyframe>> keyframes;
  std::vector<std::shared_ptr<const MapPoint>> points;
};

}  // namespace valerant::visual
