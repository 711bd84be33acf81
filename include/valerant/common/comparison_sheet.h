#pragma once
// A comparison sheet: true frames above generated ones, one row per sequence and one
// column per frame index, labelled, to judge a world model's rollouts at a glance.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace valerant {

struct ComparisonRow {
  std::string label;               // e.g. the candidate
  std::vector<cv::Mat> truth;      // one RGB frame per column; an empty Mat: no such frame
  std::vector<cv::Mat> generated;  // same length as truth
};

// An RGB sheet: a header with `column_labels`, then per row its label and, per column,
// truth above generated (each tile labelled "true" / "model"); missing frames are left
// grey. Every frame must be CV_8UC3 of one size. Throws InputError for rows whose lists
// do not match the columns, frames of other types or sizes, or no frame at all.
cv::Mat makeComparisonSheet(const std::vector<ComparisonRow>& rows, const std::vector<std::string>& column_labels);

}  // namespace valerant
