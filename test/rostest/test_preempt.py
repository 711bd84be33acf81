#!/usr/bin/python3
"""Cancelling Explore stops after the current step and still writes the map."""
import os
import tempfile
import unittest

import actionlib
import rospy
import rostest

import graph_helpers
from actionlib_msgs.msg import GoalStatus
from valerant.msg import ExploreAction, ExploreGoal

BUDGET = 15
TIMEOUT_S = 900


class PreemptTest(unittest.TestCase):
    def test_cancel_saves_the_map(self):
        client = actionlib.SimpleActionClient("explorer/explore", ExploreAction)
        self.assertTrue(client.wait_for_server(rospy.Duration(TIMEOUT_S)))
        out = tempfile.mkdtemp(prefix="valerant_preempt_")
        steps = []
        client.send_goal(ExploreGoal(world="", spawn=-1, budget=BUDGET, seed=-1, output_dir=out),
                         feedback_cb=lambda f: (steps.append(f.step), client.cancel_goal()))
        self.assertTrue(client.wait_for_result(rospy.Duration(TIMEOUT_S)))
        self.assertEqual(client.get_state(), GoalStatus.PREEMPTED)
        result = client.get_result()
        self.assertTrue(result.preempted)
        self.assertEqual(result.error, "")
        self.assertLess(result.committed_steps, BUDGET)
        self.assertGreater(result.map_points, 0)
        for name in ("map.ply", "map.bt", "grid.pgm", "decisions.jsonl", "report.json"):
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        with open(os.path.join(out, "decisions.jsonl")) as f:
            self.assertEqual(len(f.readlines()), result.steps)
        self.assertEqual(graph_helpers.dead_graph_nodes(), [])


if __name__ == "__main__":
    rospy.init_node("test_preempt")
    rostest.rosrun("valerant", "preempt", PreemptTest)
