// A step's record as decisions.jsonl writes it: each candidate's ground-truth fields.
#include <gtest/gtest.h>

#include "valerant/explore/episode_json.h"

using namespace valerant;

TEST(EpisodeJson, CandidateTruthCountsInSolidFramesAndTheRise) {
  // Floors under the true path 50, 66, 82, 66 (two 16-unit stairs up, one down), one
  // frame in solid: rise 82 - 50 = 32, not the last floor's 16.
  CandidateRecord climb;
  climb.verdict.candidate = "uw";
  for (const double z : {50.0, 66.0, 82.0, 66.0}) {
    FrameTruth f;
    f.floor_z = z;
    f.in_solid = z == 82.0;
    climb.truth.push_back(f);
  }
  // A drop: 50 then -94: no rise.
  CandidateRecord drop;
  drop.verdict.candidate = "jw";
  for (const double z : {50.0, -94.0}) {
    FrameTruth f;
    f.floor_z = z;
    drop.truth.push_back(f);
  }
  StepRecord record;
  record.candidates = {climb, drop};
  record.chosen = 0;
  const nlohmann::json j = toJson(record);
  EXPECT_EQ(j["verdicts"][0]["truth_in_solid_frames"], 1);
  EXPECT_DOUBLE_EQ(j["verdicts"][0]["truth_rise_units"].get<double>(), 32.0);
  EXPECT_DOUBLE_EQ(j["verdicts"][1]["truth_rise_units"].get<double>(), 0.0);
  EXPECT_EQ(j["committed_in_solid_frames"], 1);
  // Frame by frame: the camera in solid at the third frame only; the hull never.
  EXPECT_EQ(j["verdicts"][0]["truth_in_solid_mask"], "0010");
  EXPECT_EQ(j["verdicts"][0]["truth_hull_in_solid_mask"], "0000");
  // Without ground truth (a learned world): neither field.
  record.candidates[1].truth.clear();
  EXPECT_FALSE(toJson(record)["verdicts"][1].contains("truth_rise_units"));
}

// The stagnant-pocket rule's signals and its rewinds are in the record (docs/pockets.md).
TEST(EpisodeJson, PocketSignalsAndStagnantRewinds) {
  StepRecord record;
  record.new_floor_cells = 7;
  record.drop = true;
  record.rewind = true;
  record.rewind_stagnant = true;
  record.rewind_to = 12;
  const nlohmann::json j = toJson(record);
  EXPECT_EQ(j["new_floor_cells"], 7);
  EXPECT_EQ(j["drop"], true);
  EXPECT_EQ(j["ended_in_start_cell"], false);
  record.ended_in_start_cell = true;
  EXPECT_EQ(toJson(record)["ended_in_start_cell"], true);
  EXPECT_EQ(j["rewind_stagnant"], true);
  EXPECT_EQ(j["rewind_to"], 12);
  EXPECT_EQ(toJson(StepRecord{})["rewind_stagnant"], false);
  record.failed_forgotten = 9;
  EXPECT_EQ(toJson(record)["failed_forgotten"], 9);
  EXPECT_EQ(toJson(StepRecord{})["failed_forgotten"], 0);
  record.way_back_freed = 4;
  EXPECT_EQ(toJson(record)["way_back_freed"], 4);
  EXPECT_EQ(toJson(StepRecord{})["way_back_freed"], 0);
  record.rewind_reached_past = 2;
  EXPECT_EQ(toJson(record)["rewind_reached_past"], 2);
  EXPECT_EQ(toJson(StepRecord{})["rewind_reached_past"], 0);
  record.goal_frontiers = 12;
  record.goal_distance = -1;
  record.goal_distance_without_failed = 3.5;
  EXPECT_EQ(toJson(record)["goal_frontiers"], 12);
  EXPECT_EQ(toJson(record)["goal_distance"], -1.0);
  EXPECT_EQ(toJson(record)["goal_distance_without_failed"], 3.5);
}
