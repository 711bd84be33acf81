#pragma once
// When a run writes the snapshot of its committed steps (episode_outputs.h): the first
// time it is asked, then once the time since the last write ended is at least
// (1 / max_share - 1) times that write's duration, so writing takes at most `max_share`
// of the run's time. The snapshot once held the whole map in one file, and writing it
// after every step grew a long run with the square of its steps; it is now written in
// parts (map/run_snapshot.h) and a write costs what the map gained, a fraction of a step,
// so in practice the run writes after every step and this cap is a guard.
namespace valerant {

class SnapshotSchedule {
 public:
  explicit SnapshotSchedule(double max_share = 0.1) : wait_factor_(1 / max_share - 1) {}
  // Whether a snapshot is due at `now_s` (seconds on any steady clock).
  bool due(double now_s) const { return !written_ || now_s - last_end_s_ >= wait_factor_ * (last_end_s_ - last_start_s_); }
  void written(double start_s, double end_s) {
    written_ = true;
    last_start_s_ = start_s;
    last_end_s_ = end_s;
  }

 private:
  double wait_factor_;
  bool written_ = false;
  double last_start_s_ = 0, last_end_s_ = 0;
};

}  // namespace valerant
