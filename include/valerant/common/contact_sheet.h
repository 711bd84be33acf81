#pragma once
// A contact sheet: evenly spaced frames of a sequence tiled into one labelled image,
// to see a whole rollout at a glance.
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace valerant {

// `frames` are RGB; returns an RGB sheet of at most `tiles` frames, `columns` wide,
// each labelled "<title> #<index>". Empty input gives an empty Mat.
cv::Mat makeContactSheet(const std::vector<cv::Mat>& frames, const std::string& title, int tiles = 12,
                         int columns = 4);

}  // namespace valerant
