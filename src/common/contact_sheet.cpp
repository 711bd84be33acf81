#include "valerant/common/contact_sheet.h"

#include <opencv2/imgproc.hpp>

namespace valerant {

cv::Mat makeContactSheet(const std::vector<cv::Mat>& frames, const std::string& title, int tiles,
                         int columns) {
  if (frames.empty()) return {};
  const int n = std::min<int>(tiles, frames.size());
  const int rows = (n + columns - 1) / columns;
  const int w = frames[0].cols, h = frames[0].rows;
  cv::Mat sheet(rows * h, std::min(n, columns) * w, CV_8UC3, cv::Scalar::all(0));
  for (int i = 0; i < n; ++i) {
    // Spread the tiles over the whole sequence, always including the last frame.
    const size_t index = n == 1 ? 0 : static_cast<size_t>(i) * (frames.size() - 1) / (n - 1);
    cv::Mat tile = sheet(cv::Rect((i % columns) * w, (i / columns) * h, w, h));
    frames[index].copyTo(tile);
    const std::string label = title + " #" + std::to_string(index);
    cv::putText(tile, label, {5, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar::all(0), 3);
    cv::putText(tile, label, {5, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar::all(255), 1);
  }
  return sheet;
}

}  // namespace valerant
