#include "valerant/geometry/surface_layer.h"

#include <algorithm>
#include <cmath>

namespace valerant {

int SurfaceLayer::binOf(double height) {
  const int bin = static_cast<int>(std::floor((height - kLowestHeight) / kBinHeight));
  return std::clamp(bin, 0, kBins - 1);
}

void SurfaceLayer::addPoint(size_t cell, double height) {
  uint16_t& count = cells_[cell].counts[binOf(height)];
  if (count == UINT16_MAX) halve(cell);
  ++count;
}

void SurfaceLayer::addPass(size_t cell, double height_a, double height_b) {
  if (!carving()) return;
  Counts& passes = passes_[cell];
  const int a = binOf(height_a), b = binOf(height_b);  // std::minmax of temporaries would dangle
  const int low = std::min(a, b), high = std::max(a, b);
  for (int bin = low; bin <= high; ++bin) {
    if (passes[bin] == UINT16_MAX) halve(cell);
    ++passes[bin];
  }
}

void SurfaceLayer::halve(size_t cell) {
  if (const auto it = cells_.find(cell); it != cells_.end())
    for (uint16_t& n : it->second.counts) n /= 2;
  if (const auto it = passes_.find(cell); it != passes_.end())
    for (uint16_t& n : it->second) n /= 2;
}

bool SurfaceLayer::dense(size_t cell, const Counts& counts, int bin) const {
  if (counts[bin] < min_points_) return false;
  if (!carving()) return true;
  const auto it = passes_.find(cell);
  return it == passes_.end() || counts[bin] >= carving_ratio_ * it->second[bin];
}

void SurfaceLayer::addStand(size_t cell, double floor_height) {
  std::optional<double>& stood = cells_[cell].stood;
  stood = stood ? std::min(*stood, floor_height) : floor_height;
}

bool SurfaceLayer::seen(size_t cell) const {
  const auto it = cells_.find(cell);
  if (it == cells_.end()) return false;
  const auto& counts = it->second.counts;
  return std::any_of(counts.begin(), counts.end(), [&](uint16_t n) { return n >= min_points_; });
}

std::optional<double> SurfaceLayer::height(size_t cell) const {
  const auto it = cells_.find(cell);
  if (it == cells_.end()) return std::nullopt;
  if (it->second.stood) return it->second.stood;
  const auto& counts = it->second.counts;
  int top = kBins - 1;
  while (top >= 0 && !dense(cell, counts, top)) --top;
  if (top < 0) return std::nullopt;
  // Walk down the top run; a gap of more than kRunGap without a seen bin ends it.
  const int max_gap_bins = static_cast<int>(std::lround(kRunGap / kBinHeight));
  int bottom = top;
  for (int bin = top - 1, gap = 0; bin >= 0 && gap <= max_gap_bins; --bin) {
    if (dense(cell, counts, bin)) {
      bottom = bin;
      gap = 0;
    } else {
      ++gap;
    }
  }
  if ((top - bottom) * kBinHeight > max_rise_ + 1e-9) return std::nullopt;  // a face
  return kLowestHeight + (top + 1) * kBinHeight;  // the top of the top bin
}

bool SurfaceLayer::step(size_t from, size_t to) const {
  const auto a = height(from), b = height(to);
  return a && b && *b - *a <= max_rise_ + 1e-9;
}

}  // namespace valerant
