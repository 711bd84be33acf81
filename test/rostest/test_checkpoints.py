#!/usr/bin/python3
"""Synchronised checkpoints and bad input, talking to the nodes directly:
- after a branch is rolled out and committed, restoring the checkpoint leaves the world
  model and every branch SLAM exactly at the checkpoint (same state digests);
- an unknown candidate, a stale checkpoint id, a NaN pose, an empty keyframe cloud and
  a corrupt bag get an error result or a logged error, and every node keeps serving."""
import math
import unittest

import actionlib
import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from valerant.msg import CandidateResult, FloorSample, Isometry, RolloutAction, RolloutGoal, SlamFrame, Verdict
from valerant.srv import (Checkpoint, Commit, FloorAt, FloorContext, Reset, Restore, SelectBranch,
                          TrackContext)

import graph_helpers

CANDIDATES = ("uw", "jw", "lw", "jq", "lq")
TIMEOUT_S = 300


class Results(object):
    """Collects branch/<c>/result from before a rollout is sent (results come fast)."""

    def __init__(self, candidate):
        self.received = []
        self.subscriber = rospy.Subscriber("branch/%s/result" % candidate, CandidateResult, self.received.append)
        graph_helpers.wait_for_connections(self.subscriber)

    def wait(self, rollout_id):
        deadline = rospy.Time.now() + rospy.Duration(TIMEOUT_S)
        while rospy.Time.now() < deadline and not rospy.is_shutdown():
            for r in self.received:
                if r.key.rollout_id == rollout_id:
                    return r
            rospy.sleep(0.05)
        raise AssertionError("no result for rollout %d" % rollout_id)


def service(name, kind):
    rospy.wait_for_service(name, TIMEOUT_S)
    return rospy.ServiceProxy(name, kind)


class CheckpointTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.rollout = actionlib.SimpleActionClient("world_model/rollout", RolloutAction)
        assert cls.rollout.wait_for_server(rospy.Duration(TIMEOUT_S))
        cls.wm = {n: service("world_model/" + n, k) for n, k in
                  (("reset", Reset), ("checkpoint", Checkpoint), ("restore", Restore), ("commit", Commit))}
        cls.slam = {c: {n: service("branch/%s/slam/%s" % (c, n), k) for n, k in
                        (("track_context", TrackContext), ("checkpoint", Checkpoint), ("restore", Restore),
                         ("commit", Commit))} for c in CANDIDATES}
        cls.floor_context = service("floor_estimator/floor_context", FloorContext)
        cls.floor = {n: service("floor_estimator/" + n, k) for n, k in
                     (("checkpoint", Checkpoint), ("restore", Restore), ("commit", Commit))}
        cls.floor_at = service("floor_estimator/floor_at", FloorAt)

    def start_episode(self):
        self.assertTrue(self.wm["reset"]().ok)
        tracked = [self.slam[c]["track_context"]() for c in CANDIDATES]
        for t in tracked:
            self.assertTrue(t.ok, t.error)
        self.assertTrue(self.floor_context(frames=tracked[0].frames).ok)

    def checkpoint_all(self):
        wm = self.wm["checkpoint"](checkpoint_id=0)
        self.assertTrue(wm.ok, wm.error)
        slams = {c: self.slam[c]["checkpoint"](checkpoint_id=wm.checkpoint_id) for c in CANDIDATES}
        for c, s in slams.items():
            self.assertTrue(s.ok, "%s: %s" % (c, s.error))
        # The floor estimator is a checkpoint participant too: branches start from it.
        floor = self.floor["checkpoint"](checkpoint_id=wm.checkpoint_id)
        self.assertTrue(floor.ok, floor.error)
        return wm, slams

    def roll_out(self, checkpoint_id, candidate):
        self.rollout.send_goal(RolloutGoal(checkpoint_id=checkpoint_id, candidate=candidate))
        self.assertTrue(self.rollout.wait_for_result(rospy.Duration(TIMEOUT_S)))
        return self.rollout.get_state(), self.rollout.get_result()

    def test_restore_after_branch_returns_to_checkpoint(self):
        self.start_episode()
        wm, slams = self.checkpoint_all()
        results = Results("uw")
        state, result = self.roll_out(wm.checkpoint_id, "uw")
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.status)
        # The branch went through SLAM, floor and collision before it is committed.
        judged = results.wait(result.rollout_id)
        self.assertEqual(judged.error, "")
        committed = self.wm["commit"](rollout_id=result.rollout_id, candidate="uw")
        self.assertTrue(committed.ok, committed.error)
        self.assertGreater(committed.state.frames, wm.state.frames)
        for c in CANDIDATES:  # the winner adopts its branch, the others replay it
            done = self.slam[c]["commit"](rollout_id=result.rollout_id, candidate="uw")
            self.assertTrue(done.ok, "%s: %s" % (c, done.error))
            self.assertEqual(done.state.frames, slams[c].state.frames + result.frames)
        floor_done = self.floor["commit"](rollout_id=result.rollout_id, candidate="uw")
        self.assertTrue(floor_done.ok, floor_done.error)
        restored = self.wm["restore"](checkpoint_id=wm.checkpoint_id)
        self.assertTrue(restored.ok, restored.error)
        self.assertEqual(restored.state, wm.state)
        for c in CANDIDATES:
            back = self.slam[c]["restore"](checkpoint_id=wm.checkpoint_id)
            self.assertTrue(back.ok, back.error)
            self.assertEqual(back.state, slams[c].state)
            self.assertEqual(back.state, slams["uw"].state)  # every SLAM at the same state
        floor_back = self.floor["restore"](checkpoint_id=wm.checkpoint_id)
        self.assertTrue(floor_back.ok, floor_back.error)

    def test_bad_input_gets_errors_and_nodes_keep_serving(self):
        self.start_episode()
        wm, _ = self.checkpoint_all()
        state, result = self.roll_out(wm.checkpoint_id, "xx")
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn("unknown", result.status)
        state, result = self.roll_out(wm.checkpoint_id + 1000, "uw")
        self.assertEqual(state, GoalStatus.ABORTED)
        self.assertIn("stale", result.status)
        stale = self.wm["restore"](checkpoint_id=wm.checkpoint_id + 1000)
        self.assertFalse(stale.ok)
        self.assertIn("unknown", stale.error)
        for c in CANDIDATES:
            self.assertFalse(self.slam[c]["restore"](checkpoint_id=wm.checkpoint_id + 1000).ok)
        self.assertFalse(self.slam["jw"]["commit"](rollout_id=987654, candidate="jw").ok)
        nan_pose = Isometry(m=[math.nan] * 12)
        at = self.floor_at(camera_to_map=nan_pose)
        self.assertFalse(at.ok)
        self.assertIn("NaN", at.error)
        arbiter = service("policy_arbiter/select_branch", SelectBranch)
        unnamed = arbiter(verdicts=[Verdict()], step_seed=0)
        self.assertFalse(unnamed.ok)
        self.assertIn("candidate", unnamed.error)
        # A keyframe with an empty cloud and a NaN pose on a branch stream: the floor
        # estimator propagates or reports, and the collision checker reports an error.
        lq_results = Results("lq")
        publisher = rospy.Publisher("branch/lq/tracked", SlamFrame, queue_size=4)
        graph_helpers.wait_for_connections(publisher)
        frame = SlamFrame(state="tracking", camera_to_map=nan_pose, keyframe=True)
        frame.key.checkpoint_id = wm.checkpoint_id
        frame.key.rollout_id = 424242
        frame.key.candidate = "lq"
        frame.key.count = 1
        publisher.publish(frame)
        judged = lq_results.wait(424242)
        self.assertIn("NaN", judged.error)
        # Every node still answers.
        jq_results = Results("jq")
        state, result = self.roll_out(wm.checkpoint_id, "jq")
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.status)
        judged = jq_results.wait(result.rollout_id)
        self.assertEqual(judged.error, "")
        self.assertTrue(self.floor_at(camera_to_map=Isometry(m=[1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0])).ok)

    def test_corrupt_bag_is_reported_and_served_as_errors(self):
        corrupt = service("corrupt/world_model/checkpoint", Checkpoint)
        answer = corrupt(checkpoint_id=0)
        self.assertFalse(answer.ok)
        self.assertIn("bag", answer.error)
        self.assertFalse(corrupt(checkpoint_id=0).ok)  # and again: still serving


if __name__ == "__main__":
    rospy.init_node("test_checkpoints")
    rostest.rosrun("valerant", "checkpoints", CheckpointTest)
