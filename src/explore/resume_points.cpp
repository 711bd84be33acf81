#include "valerant/explore/resume_points.h"

#include <cstring>

namespace valerant {
namespace {

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  if (a.data == b.data && a.size == b.size && a.type() == b.type()) return true;
  if (a.size != b.size || a.type() != b.type()) return false;
  const size_t row_bytes = a.cols * a.elemSize();
  for (int y = 0; y < a.rows; ++y)
    if (std::memcmp(a.ptr(y), b.ptr(y), row_bytes) != 0) return false;
  return true;
}

// The pose and the penetration flags: what the oracle SLAM and the reports read
// besides the depth, which the same pose renders the same.
bool sameTruth(const FrameTruth& a, const FrameTruth& b) {
  return a.camera_to_world.matrix() == b.camera_to_world.matrix() && a.in_solid == b.in_solid &&
         a.floor_z == b.floor_z && a.hull_in_solid == b.hull_in_solid && a.hull_in_clip_only == b.hull_in_clip_only &&
         a.outside_world == b.outside_world;
}

}  // namespace

void ResumePoints::keep(const Rollout& rollout, BranchRun run) {
  const size_t n = run.frames();
  Point point{std::vector<cv::Mat>(rollout.frames.begin(), rollout.frames.begin() + n), {}, std::move(run)};
  if (rollout.truth.size() >= n) point.truth.assign(rollout.truth.begin(), rollout.truth.begin() + n);
  std::lock_guard<std::mutex> lock(mutex_);
  points_.push_back(std::move(point));
}

std::optional<BranchRun> ResumePoints::longestPrefixOf(const Rollout& rollout) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const Point* best = nullptr;
  for (const Point& p : points_) {
    const size_t n = p.frames.size();
    if (n == 0 || n > rollout.frames.size() || (best && n <= best->frames.size())) continue;
    if (p.truth.empty() != (rollout.truth.size() < n)) continue;  // one has ground truth, the other not
    bool same = true;
    for (size_t i = 0; same && i < n; ++i)
      same = sameImage(p.frames[i], rollout.frames[i]) && (p.truth.empty() || sameTruth(p.truth[i], rollout.truth[i]));
    if (same) best = &p;
  }
  if (!best) return std::nullopt;
  return best->run.fork();
}

void ResumePoints::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  points_.clear();
}

size_t ResumePoints::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return points_.size();
}

}  // namespace valerant
