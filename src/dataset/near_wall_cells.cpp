#include "valerant/dataset/near_wall_cells.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace valerant::dataset {
namespace {

int64_t columnKey(int64_t ix, int64_t iy) { return (ix << 32) ^ (iy & 0xffffffffLL); }

}  // namespace

std::vector<size_t> nearWallCells(const std::vector<Eigen::Vector3f>& cells, const NearWallParams& params) {
  // The lowest reachable floor of every column: a column is open from z when it is
  // at most z + step_height.
  std::unordered_map<int64_t, float> lowest;
  auto index = [&](float v) { return static_cast<int64_t>(std::lround(v / params.cell_size)); };
  for (const Eigen::Vector3f& c : cells) {
    const int64_t key = columnKey(index(c.x()), index(c.y()));
    auto [it, fresh] = lowest.emplace(key, c.z());
    if (!fresh && c.z() < it->second) it->second = c.z();
  }
  static const int kDirections[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  std::vector<size_t> out;
  for (size_t i = 0; i < cells.size(); ++i) {
    const int64_t ix = index(cells[i].x()), iy = index(cells[i].y());
    bool near = false;
    for (const auto& d : kDirections) {
      for (int k = 1; k <= params.max_cells && !near; ++k) {
        const auto it = lowest.find(columnKey(ix + k * d[0], iy + k * d[1]));
        near = it == lowest.end() || it->second > cells[i].z() + params.step_height;
      }
      if (near) break;
    }
    if (near) out.push_back(i);
  }
  return out;
}

}  // namespace valerant::dataset
