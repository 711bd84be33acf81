#pragma once
// Sparse feature tracks for the visual SLAM: Shi-Tomasi corners followed from frame to
// frame by pyramidal KLT with a forward-backward check. A track carries the data
// association the rest of the SLAM needs (its map point, the keyframe it was first
// seen in, the pixel in the current two-view reference). The tracker is a value: a
// copy is an independent branch. Its pyramid images are shared between copies and
// never written in place.
#include <opencv2/core.hpp>
#include <vector>

#include "valerant/config/visual_slam_config.h"

namespace valerant::visual {

struct Track {
  int id = 0;
  cv::Point2f px;        // in the current frame
  cv::Point2f prev_px;   // in the previous frame
  int point = -1;        // map point id, -1 = not triangulated yet
  int anchor = -1;       // keyframe index it was seen in first, -1 = none yet
  cv::Point2f anchor_px;
  bool referenced = false;  // seen in the two-view reference frame, at reference_px
  cv::Point2f reference_px;
};

class FeatureTracker {
 public:
  explicit FeatureTracker(const FeatureTrackerParams& params) : params_(params) {}

  // Follows every track into `gray` (CV_8U); tracks that fail KLT or the
  // forward-backward check are dropped. The first call only stores the image.
  void track(const cv::Mat& gray);
  // Adds corners of the current image away from existing tracks, up to max_features,
  // anchored at keyframe `anchor` (-1 = none). Only when fewer than redetect_below
  // tracks remain, unless `force`.
  void detect(const cv::Mat& gray, int anchor, bool force = false);

  std::vector<Track>& tracks() { return tracks_; }
  const std::vector<Track>& tracks() const { return tracks_; }

 private:
  FeatureTrackerParams params_;
  std::vector<cv::Mat> pyramid_;  // of the last tracked image
  std::vector<Track> tracks_;
  int next_id_ = 0;
};

}  // namespace valerant::visual
