#include "valerant/explore/topdown_image.h"

#include <opencv2/imgproc.hpp>

namespace valerant {

cv::Mat drawTopdown(const std::vector<FusedPoint>& points, const CoverageGrid& grid,
                    const std::vector<Eigen::Isometry3d>& trajectory, const std::vector<StepRecord>& history,
                    const FailedRegionMemory& failed, const CollisionConfig& bands, int pixels_per_cell) {
  const int side = grid.size() * pixels_per_cell;
  const double scale = pixels_per_cell / grid.cellSize();  // pixels per map unit
  cv::Mat image(side, side, CV_8UC3, cv::Scalar(24, 24, 32));
  // u (the start heading) points up the image, v (left of it) points left.
  auto pixel = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector2d uv = grid.floorCoordinates(p);
    return cv::Point(static_cast<int>(side / 2 - uv.y() * scale), static_cast<int>(side / 2 - uv.x() * scale));
  };
  cv::Rect drawn;
  auto touch = [&](const cv::Point& p) { drawn |= cv::Rect(p.x - 2, p.y - 2, 5, 5); };

  for (const Cell& c : failed.cells()) {
    const cv::Point centre = pixel(grid.cellCentre(c));
    const cv::Rect box(centre.x - pixels_per_cell / 2, centre.y - pixels_per_cell / 2, pixels_per_cell, pixels_per_cell);
    cv::rectangle(image, box, cv::Scalar(110, 30, 30), cv::FILLED);
    touch(centre);
  }
  for (const auto& p : points) {
    const cv::Point q = pixel(p.position.cast<double>());
    if (q.x < 0 || q.y < 0 || q.x >= side || q.y >= side) continue;
    cv::Vec3b colour;
    if (std::abs(p.h) < bands.height_low) {
      colour = cv::Vec3b(p.rgb[0] / 2 + 60, p.rgb[1] / 2 + 60, p.rgb[2] / 2 + 60);
    } else if (p.h <= bands.height_high) {
      colour = cv::Vec3b(170, 40, 40);
    } else {
      continue;  // overhead structure would hide the floor
    }
    image.at<cv::Vec3b>(q) = colour;
    touch(q);
  }
  for (const StepRecord& step : history) {
    for (size_t i = 0; i < step.candidates.size(); ++i) {
      const CandidateRecord& c = step.candidates[i];
      cv::Scalar colour(80, 200, 80);
      if (c.verdict.predictsCollision()) colour = cv::Scalar(230, 60, 60);
      else if (c.verdict.enters_failed || c.verdict.rewound_before) colour = cv::Scalar(240, 150, 40);
      else if (c.verdict.slam_lost) colour = cv::Scalar(128, 128, 128);
      for (size_t k = 1; k < c.centres.size(); ++k) {
        cv::line(image, pixel(c.centres[k - 1]), pixel(c.centres[k]), colour, 1, cv::LINE_AA);
        touch(pixel(c.centres[k]));
      }
    }
  }
  for (size_t k = 1; k < trajectory.size(); ++k)
    cv::line(image, pixel(trajectory[k - 1].translation()), pixel(trajectory[k].translation()),
             cv::Scalar(250, 220, 40), 2, cv::LINE_AA);
  if (!trajectory.empty()) {
    cv::circle(image, pixel(trajectory.front().translation()), 5, cv::Scalar(60, 120, 255), cv::FILLED);
    cv::circle(image, pixel(trajectory.back().translation()), 4, cv::Scalar(255, 255, 255), cv::FILLED);
    touch(pixel(trajectory.front().translation()));
  }
  const int margin = 2 * pixels_per_cell;
  drawn = cv::Rect(drawn.x - margin, drawn.y - margin, drawn.width + 2 * margin, drawn.height + 2 * margin) &
          cv::Rect(0, 0, side, side);
  return drawn.area() > 0 ? image(drawn).clone() : image;
}

}  // namespace valerant
