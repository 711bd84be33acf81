#include "valerant/explore/goal_map_image.h"

#include <opencv2/imgproc.hpp>

namespace valerant {

cv::Mat drawGoalMap(const CoverageGrid& grid, const FrontierDistance& goal, const FailedRegionMemory& failed,
                    const Cell& agent, int pixels_per_cell) {
  const int n = grid.size(), side = n * pixels_per_cell;
  cv::Mat image(side, side, CV_8UC3, cv::Scalar(24, 24, 32));
  cv::Rect drawn;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Cell c{i, j};
      cv::Scalar colour;
      if (c == agent) colour = cv::Scalar(255, 255, 255);
      else if (goal.isGoalFrontier(c)) colour = cv::Scalar(60, 220, 230);
      else if (failed.contains(c)) colour = cv::Scalar(200, 40, 40);
      else if (grid.walkable(c)) {
        const bool reaches = goal.at(c) != FrontierDistance::kUnreachable;
        colour = reaches ? cv::Scalar(70, 150, 70) : cv::Scalar(110, 110, 110);
        if (grid.visited(c)) colour += cv::Scalar(50, 50, 50);
      } else if (grid.obstacle(c)) colour = cv::Scalar(110, 30, 30);
      else if (!grid.unknown(c)) colour = cv::Scalar(60, 60, 70);  // seen, neither walkable nor obstacle
      else continue;
      // Rows run against u (the start heading up), columns against v (left): as drawTopdown.
      const cv::Rect box((n - 1 - j) * pixels_per_cell, (n - 1 - i) * pixels_per_cell, pixels_per_cell, pixels_per_cell);
      cv::rectangle(image, box, colour, cv::FILLED);
      drawn |= box;
    }
  if (drawn.empty()) return image(cv::Rect(0, 0, pixels_per_cell, pixels_per_cell)).clone();
  const int margin = 2 * pixels_per_cell;
  drawn = cv::Rect(drawn.x - margin, drawn.y - margin, drawn.width + 2 * margin, drawn.height + 2 * margin) &
          cv::Rect(0, 0, side, side);
  return image(drawn).clone();
}

}  // namespace valerant
