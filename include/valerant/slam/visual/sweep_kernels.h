#pragma once
// The plane sweep's per-pixel loops (plane_sweep.cpp), which are most of its time: the
// source row between two canvas rows, the truncated difference of one reference row
// against it sampled at a uniform scale and shift, and the running summary of every
// pixel's cost curve. Each
// has a plain C++ path and an AVX2 path (8 pixels a step; the gather samples the source
// row). The build targets baseline x86-64, so the AVX2 path is chosen at run time where
// the CPU has it. Both paths do the same float operations in the same order, with no
// fused multiply-add, so their results are equal bit for bit: a run's depths, and so
// its decisions, do not depend on the machine it ran on.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace valerant::visual {

enum class SweepIsa { kPortable, kAvx2 };

// kAvx2 where this CPU has AVX2 (and the build is for x86-64), else kPortable.
SweepIsa fastestSweepIsa();
// Every path this CPU runs, kPortable first (what a test of both paths iterates over).
std::vector<SweepIsa> sweepIsasHere();

// out[u] = top[u] + fy (bottom[u] - top[u]) for u in [0, n): a source row between two
// canvas rows.
void blendRows(const float* top, const float* bottom, float fy, int n, float* out, SweepIsa isa);

// The constants of one source row's truncated differences.
struct RowSampling {
  float scale = 1;        // source column = scale * x + shift
  float shift = 0;
  float max_u = 0;        // a sample is inside the source iff 0 <= column < max_u
  float truncation = 0;   // each difference is capped here ...
  float implausible = 0;  // ... and one this large touched the outside of the source
  float invalid = 0;      // added instead where the sample is outside or implausible
};

// For x in [0, n): out[x] += min(|ref[x] - source(u)|, truncation) with u = scale x + shift
// and source(u) linear between source[floor(u)] and source[floor(u) + 1]; `invalid`
// instead where u is outside [0, max_u) or the difference is at least `implausible`.
// `source` holds at least max_u + 1 values.
void addTruncatedDifferences(const float* ref, const float* source, int n, const RowSampling& sampling, float* out,
                             SweepIsa isa);

// Per pixel, what the winner and its confidence need from the cost curve, updated one
// plane at a time so the cost volume is never stored: the best plane, its neighbours'
// costs (for the sub-plane parabola) and the cheapest cost at least three planes away
// (the strongest rival depth).
class CostCurveTracker {
 public:
  explicit CostCurveTracker(size_t pixels, SweepIsa isa = fastestSweepIsa());

  // Planes come in order 0, 1, 2, ...; costs of `invalid` or more are not scored.
  void add(int plane, const float* cost, float invalid);
  int best(size_t p) const { return best_[p]; }
  float bestCost(size_t p) const { return c1_[p]; }
  float rivalCost(size_t p) const { return std::min(left_[p], right_[p]); }
  float before(size_t p) const { return before_[p]; }
  float after(size_t p) const { return after_[p]; }

 private:
  void addPortable(int plane, const float* cost, float invalid, size_t begin);
  void addAvx2(int plane, const float* cost, float invalid);

  SweepIsa isa_;
  // c1: best cost; left / right: cheapest cost at least three planes before / after the
  // best; before / after: the best's neighbours; lag_min: cheapest of planes 0 .. plane-3;
  // prev1..3: the last three planes' costs.
  std::vector<float> c1_, left_, right_, before_, after_, lag_min_, prev1_, prev2_, prev3_;
  std::vector<int> best_;
};

}  // namespace valerant::visual
