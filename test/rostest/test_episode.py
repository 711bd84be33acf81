#!/usr/bin/python3
"""The whole graph runs a short episode: Explore reports the committed steps and a
non-empty map, feedback arrives per step, and the decisions equal valerant_explore's
for the same map, spawn, seed and configuration (one code path)."""
import os
import tempfile
import unittest

import rospy
import rostest
from actionlib_msgs.msg import GoalStatus

import graph_helpers

BUDGET = 3
TIMEOUT_S = 900


class EpisodeTest(unittest.TestCase):
    def test_episode_matches_valerant_explore(self):
        out = tempfile.mkdtemp(prefix="valerant_episode_")
        feedback = []
        state, result = graph_helpers.explore(BUDGET, os.path.join(out, "graph"), TIMEOUT_S, feedback.append)
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.error if result else "no result")
        self.assertEqual(result.error, "")
        self.assertEqual(result.committed_steps, BUDGET)
        self.assertGreater(result.map_points, 0)
        self.assertEqual(len(feedback), result.steps)
        for name in ("map.ply", "map.pcd", "map.bt", "grid.pgm", "topdown.png", "view.png", "report.json"):
            self.assertTrue(os.path.isfile(os.path.join(out, "graph", name)), name)
        graph = graph_helpers.decisions(os.path.join(out, "graph", "decisions.jsonl"))
        in_process = graph_helpers.run_valerant_explore(BUDGET, os.path.join(out, "in_process"))
        self.assertEqual([d["chosen"] for d in graph], [d["chosen"] for d in in_process])
        self.assertEqual(graph, in_process)
        # Same decisions, so the same final view, pixel for pixel (PNG bytes).
        views = [open(os.path.join(out, d, "view.png"), "rb").read() for d in ("graph", "in_process")]
        self.assertEqual(views[0], views[1])
        self.assertEqual(graph_helpers.dead_graph_nodes(), [])


if __name__ == "__main__":
    rospy.init_node("test_episode")
    rostest.rosrun("valerant", "episode", EpisodeTest)
