#pragma once
// Branch runs kept at chosen frames of one step's rollouts, so that a later candidate
// of the same step whose frames begin with the same frames continues from there
// instead of tracking them again: a short translation (policy.short_translation_frames)
// is the first 32 or 16 frames of uw, jw or lw, a short turn the first 28 of jq or lq,
// and a longer open turn continues jq or lq. A rollout resumes only where its frames
// are byte for byte those the kept run tracked (and its ground truth, where both have
// it, the same poses), so the result is the one tracking them again gives
// (branch_run.h). Valid for one committed state: the pipeline clears it on commit and
// restore. Thread-safe: the candidates' threads keep runs while the next round looks.
#include <mutex>
#include <optional>
#include <vector>

#include "valerant/explore/branch_run.h"
#include "valerant/world/world_model.h"

namespace valerant {

class ResumePoints {
 public:
  // Keeps `run` as the state after the first run.frames() frames of `rollout`.
  void keep(const Rollout& rollout, BranchRun run);
  // A fork of the kept run with the most frames that `rollout` begins with (at most
  // all of them), or nothing.
  std::optional<BranchRun> longestPrefixOf(const Rollout& rollout) const;
  void clear();
  size_t size() const;

 private:
  struct Point {
    std::vector<cv::Mat> frames;     // shared with the rollout, not copied
    std::vector<FrameTruth> truth;   // same length, or empty without ground truth
    BranchRun run;
  };
  mutable std::mutex mutex_;
  std::vector<Point> points_;
};

}  // namespace valerant
