#pragma once
// [ours] The coverage grid's surface layer (policy.max_cell_rise > 0; docs/whole_level.md):
// where the walkable surface of each cell lies, so that the whole-level goal's paths
// climb stairs and ramps to other storeys instead of taking every rise for a wall. The
// flat layers (observed floor, obstacle points) judge each point by its height over its
// own keyframe's floor, so a stair tread is an obstacle and a floor on another storey
// is none of the agent's business.
//
// Heights are normalised (eye heights) over the grid's anchor floor, in bins of
// kBinHeight from kLowestHeight. A cell records the heights of the map points in it
// that lay below the obstacle band's top over their keyframe's floor (no ceilings or
// storeys overhead), and the floor height where the agent stood in it. Then:
//  - seen: some bin holds min_points points;
//  - top run: from the highest such bin down, the bins reached through gaps of at most
//    kRunGap without such a bin;
//  - height: the floor the agent stood on (the lowest where it stood at several), else
//    the top of the top run when the run spans at most max_rise (a surface: a floor,
//    a tread with its riser, a ramp's stretch), else none (a face: a wall's points
//    reach down to the floor within the cell);
//  - a step from one cell to a neighbour: both have a height and the second rises at
//    most max_rise over the first (stairs rise at most 0.64 a cell of one metre; a wall
//    more); any drop is a step, as a player walking off a ledge falls to the floor below
//    (most of the floor a player reaches from a spawn lies on lower storeys).
// Free-space carving ([ours], policy.surface_carving_ratio > 0; off by default): the
// rays from each keyframe's eye to its points pass through cells on their way, and a
// bin a ray crossed (addPass) was empty when that keyframe looked. A bin then takes part
// in the runs above only while its points number at least carving_ratio times the rays
// that crossed it. Visual depth scatters a wall's points into the room before it, and
// hundreds of keyframes fill every bin of a floor cell up to the body band's top (a
// face); the many rays to the far walls cross those bins and carve them away, while a
// real wall ends most of the rays that reach it (what OctoMap's hits and misses do,
// in one column a cell). `seen` counts points alone: a cell carved empty was seen.
// Counts saturate by halving a cell's bins (points and passes together), which keeps
// their ratios.
// Cells are indices of the owning grid; only cells that received a point are stored.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>

namespace valerant {

class SurfaceLayer {
 public:
  static constexpr double kBinHeight = 0.1;
  static constexpr double kLowestHeight = -12.8;  // 256 bins: +-12.8 eye heights (+-640 game units)
  static constexpr int kBins = 256;
  // Points of a wall seen from afar lie a few bins apart; two storeys lie many apart.
  static constexpr double kRunGap = 0.3;

  SurfaceLayer(double max_rise, int min_points, double carving_ratio = 0)
      : max_rise_(max_rise), min_points_(min_points), carving_ratio_(carving_ratio) {}

  void addPoint(size_t cell, double height);
  void addStand(size_t cell, double floor_height);
  // A ray crossed the cell between these heights (either order); ignored without carving.
  void addPass(size_t cell, double height_a, double height_b);
  bool carving() const { return carving_ratio_ > 0; }
  bool seen(size_t cell) const;
  std::optional<double> height(size_t cell) const;
  bool step(size_t from, size_t to) const;

 private:
  using Counts = std::array<uint16_t, kBins>;
  struct Bins {
    Counts counts{};               // points
    std::optional<double> stood;  // lowest floor the agent stood on here
  };
  static int binOf(double height);
  // Whether bin `bin` of a cell takes part in its runs: min_points points, and with
  // carving at least carving_ratio times the rays that crossed it.
  bool dense(size_t cell, const Counts& counts, int bin) const;
  void halve(size_t cell);

  double max_rise_;
  int min_points_;
  double carving_ratio_;
  std::unordered_map<size_t, Bins> cells_;
  std::unordered_map<size_t, Counts> passes_;  // with carving only
};

}  // namespace valerant
