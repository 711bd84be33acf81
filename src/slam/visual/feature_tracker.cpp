#include "valerant/slam/visual/feature_tracker.h"

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace valerant::visual {

void FeatureTracker::track(const cv::Mat& gray) {
  const cv::Size window(params_.window_px, params_.window_px);
  // A fresh vector: the old pyramid may be shared with other branches.
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(gray, pyramid, window, params_.pyramid_levels);
  if (pyramid_.empty() || tracks_.empty()) {
    pyramid_ = std::move(pyramid);
    return;
  }
  std::vector<cv::Point2f> prev, next, back;
  prev.reserve(tracks_.size());
  for (const Track& t : tracks_) prev.push_back(t.px);
  std::vector<uchar> status, back_status;
  std::vector<float> error;
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, params_.iterations, 0.03);
  cv::calcOpticalFlowPyrLK(pyramid_, pyramid, prev, next, status, error, window, params_.pyramid_levels, stop);
  back = prev;  // initial guess for the backward pass
  cv::calcOpticalFlowPyrLK(pyramid, pyramid_, next, back, back_status, error, window, params_.pyramid_levels,
                           stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  const cv::Rect2f inside(0.f, 0.f, static_cast<float>(gray.cols - 1), static_cast<float>(gray.rows - 1));
  const double max_fb2 = params_.max_forward_backward_px * params_.max_forward_backward_px;
  std::vector<Track> kept;
  kept.reserve(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (!status[i] || !back_status[i] || !inside.contains(next[i])) continue;
    const cv::Point2f d = back[i] - prev[i];
    if (d.dot(d) > max_fb2) continue;
    Track t = tracks_[i];
    t.prev_px = t.px;
    t.px = next[i];
    kept.push_back(t);
  }
  tracks_ = std::move(kept);
  pyramid_ = std::move(pyramid);
}

void FeatureTracker::detect(const cv::Mat& gray, int anchor, bool force) {
  const int have = static_cast<int>(tracks_.size());
  if (!force && have >= params_.redetect_below) return;
  const int wanted = params_.max_features - have;
  if (wanted <= 0) return;
  cv::Mat mask(gray.size(), CV_8U, cv::Scalar(255));
  for (const Track& t : tracks_) cv::circle(mask, t.px, params_.min_distance_px, cv::Scalar(0), cv::FILLED);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(gray, corners, wanted, params_.corner_quality, params_.min_distance_px, mask);
  for (const cv::Point2f& c : corners) {
    Track t;
    t.id = next_id_++;
    t.px = t.prev_px = c;
    t.anchor = anchor;
    t.anchor_px = c;
    tracks_.push_back(t);
  }
}

}  // namespace valerant::visual
