#include "valerant/common/comparison_sheet.h"

#include <opencv2/imgproc.hpp>

#include "valerant/common/error.h"

namespace valerant {
namespace {

constexpr int kHeaderPx = 22, kLabelPx = 44, kGapPx = 4;
const cv::Scalar kBackground = cv::Scalar::all(32), kMissing = cv::Scalar::all(96);

void label(cv::Mat& image, const std::string& text, cv::Point at) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar::all(0), 3);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar::all(255), 1);
}

// The size every frame shares; throws for a frame of another size or type, or none.
cv::Size tileSize(const std::vector<ComparisonRow>& rows, size_t columns) {
  cv::Size size;
  for (const ComparisonRow& row : rows) {
    if (row.truth.size() != columns || row.generated.size() != columns)
      throw InputError("comparison row '" + row.label + "'",
                       "needs " + std::to_string(columns) + " true and generated frames, got " +
                           std::to_string(row.truth.size()) + " and " + std::to_string(row.generated.size()));
    for (const auto* frames : {&row.truth, &row.generated})
      for (const cv::Mat& f : *frames) {
        if (f.empty()) continue;
        if (f.type() != CV_8UC3 || (!size.empty() && f.size() != size))
          throw InputError("comparison row '" + row.label + "'", "frames must be CV_8UC3 of one size");
        size = f.size();
      }
  }
  if (size.empty()) throw InputError("comparison sheet", "has no frame");
  return size;
}

void placeTile(cv::Mat& sheet, const cv::Mat& frame, cv::Rect where, const std::string& text) {
  cv::Mat tile = sheet(where);
  if (frame.empty()) {
    tile.setTo(kMissing);
    return;
  }
  frame.copyTo(tile);
  label(tile, text, {3, 12});
}

}  // namespace

cv::Mat makeComparisonSheet(const std::vector<ComparisonRow>& rows, const std::vector<std::string>& column_labels) {
  const cv::Size tile = tileSize(rows, column_labels.size());
  const int cell_w = tile.width + kGapPx, cell_h = 2 * tile.height + kGapPx;
  cv::Mat sheet(kHeaderPx + static_cast<int>(rows.size()) * cell_h,
                kLabelPx + static_cast<int>(column_labels.size()) * cell_w, CV_8UC3, kBackground);
  for (size_t c = 0; c < column_labels.size(); ++c)
    label(sheet, column_labels[c], {kLabelPx + static_cast<int>(c) * cell_w + 3, kHeaderPx - 7});
  for (size_t r = 0; r < rows.size(); ++r) {
    const int top = kHeaderPx + static_cast<int>(r) * cell_h;
    label(sheet, rows[r].label, {4, top + tile.height + 4});
    for (size_t c = 0; c < column_labels.size(); ++c) {
      const int left = kLabelPx + static_cast<int>(c) * cell_w;
      placeTile(sheet, rows[r].truth[c], cv::Rect(left, top, tile.width, tile.height), "true");
      placeTile(sheet, rows[r].generated[c], cv::Rect(left, top + tile.height, tile.width, tile.height), "model");
    }
  }
  return sheet;
}

}  // namespace valerant
