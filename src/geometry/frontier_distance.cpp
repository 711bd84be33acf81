#include "valerant/geometry/frontier_distance.h"

#include <cmath>
#include <functional>
#include <queue>
#include <utility>

namespace valerant {

FrontierDistance::FrontierDistance(const CoverageGrid& grid, std::set<Cell> blocked, std::set<Cell> no_goals)
    : grid_(grid), blocked_(std::move(blocked)), no_goals_(std::move(no_goals)) {
  const int n = grid.size();
  distance_.assign(static_cast<size_t>(n) * n, kUnreachable);
  auto index = [n](const Cell& c) { return static_cast<size_t>(c.first) * n + c.second; };
  using Entry = std::pair<double, Cell>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (isGoalFrontier({i, j})) {
        ++goal_frontier_cells_;
        distance_[index({i, j})] = 0;
        open.push({0.0, {i, j}});
      }
  static const double kDiagonal = std::sqrt(2.0);
  while (!open.empty()) {
    const auto [d, c] = open.top();
    open.pop();
    if (d > distance_[index(c)]) continue;  // a stale entry
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        if (di == 0 && dj == 0) continue;
        const Cell next{c.first + di, c.second + dj};
        if (!passable(next, c)) continue;  // D spreads from the frontiers: the agent walks next -> c
        const double through = d + (di != 0 && dj != 0 ? kDiagonal : 1.0);
        if (through < distance_[index(next)]) {
          distance_[index(next)] = through;
          open.push({through, next});
        }
      }
  }
}

bool FrontierDistance::passable(const Cell& from, const Cell& to) const {
  return grid_.walkable(from) && !blocked_.count(from) && grid_.traversable(from, to) && !blocked_.count(to);
}

bool FrontierDistance::isGoalFrontier(const Cell& c) const {
  if (!grid_.seenWalkable(c) || blocked_.count(c) || no_goals_.count(c)) return false;
  const Cell neighbours[] = {{c.first + 1, c.second}, {c.first - 1, c.second},
                             {c.first, c.second + 1}, {c.first, c.second - 1}};
  for (const Cell& n : neighbours)
    if (grid_.unknown(n)) return true;
  return false;
}

double FrontierDistance::at(const Cell& c) const {
  if (!grid_.inside(c)) return kUnreachable;
  return distance_[static_cast<size_t>(c.first) * grid_.size() + c.second];
}

std::vector<Cell> FrontierDistance::path(const Cell& start, double max_cells) const {
  std::vector<Cell> cells;
  if (!std::isfinite(at(start))) return cells;
  Cell c = start;
  double walked = 0;
  while (at(c) > 0 && walked < max_cells) {
    Cell next = c;
    double step = 0;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const Cell n{c.first + di, c.second + dj};
        if (at(n) < at(next)) next = n, step = (di != 0 && dj != 0) ? std::sqrt(2.0) : 1.0;
      }
    if (next == c) break;  // no descent: impossible on a Dijkstra field, but never loop
    c = next;
    walked += step;
    cells.push_back(c);
  }
  return cells;
}

std::optional<Cell> FrontierDistance::waypoint(const Cell& start, double max_cells) const {
  const std::vector<Cell> cells = path(start, max_cells);
  const Cell c = cells.empty() ? start : cells.back();
  if (std::isfinite(at(c)) && at(c) == 0) {
    const Cell beyond[] = {{c.first + 1, c.second}, {c.first - 1, c.second}, {c.first, c.second + 1},
                           {c.first, c.second - 1}};
    for (const Cell& n : beyond)
      if (grid_.unknown(n)) return n;
  }
  if (cells.empty()) return std::nullopt;
  return c;
}

double FrontierDistance::goalTerm(const Cell& start, const Cell& end) const {
  const double from = at(start);
  const double to = grid_.unknown(end) ? 0.0 : at(end);
  if (!std::isfinite(from) || !std::isfinite(to)) return 0.0;
  return (from - to) / grid_.cellsPerForwardAction();
}

}  // namespace valerant
