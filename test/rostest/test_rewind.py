#!/usr/bin/python3
"""A dead pocket rewinds (config: rotation_only_steps 1): the map and the committed
trajectory return to what they were at the rewind checkpoint, the failed-region
memory gets cells, and the whole episode decides as valerant_explore does."""
import os
import tempfile
import unittest

import rospy
import rostest
from actionlib_msgs.msg import GoalStatus
from valerant.msg import Decision, MapUpdate

import graph_helpers

BUDGET = 3
TIMEOUT_S = 900


class RewindTest(unittest.TestCase):
    def test_rewind_restores_map_and_marks_failed_cells(self):
        updates, decisions = [], []
        for subscriber in (rospy.Subscriber("map_update", MapUpdate, updates.append, queue_size=100),
                           rospy.Subscriber("decision", Decision, decisions.append, queue_size=100)):
            graph_helpers.wait_for_connections(subscriber)
        out = tempfile.mkdtemp(prefix="valerant_rewind_")
        state, result = graph_helpers.explore(BUDGET, os.path.join(out, "graph"), TIMEOUT_S)
        self.assertEqual(state, GoalStatus.SUCCEEDED, result.error)
        self.assertGreaterEqual(result.rewinds, 1)
        rospy.sleep(1.0)
        rewind = next(d for d in decisions if d.rewind)
        # The map as it stood when the rewind's checkpoint was taken: the update of the
        # step before the one that took that checkpoint (step 0 = the start).
        anchor_step = next(d.step for d in decisions if d.checkpoint_id == rewind.rewind_to)
        before = next(u for u in updates if u.step == anchor_step - 1)
        after = next(u for u in updates if u.step == rewind.step)
        self.assertEqual(len(after.keyframes), len(before.keyframes))
        self.assertEqual([k.data for k in after.keyframes], [k.data for k in before.keyframes])
        self.assertEqual([p.m for p in after.trajectory], [p.m for p in before.trajectory])
        self.assertEqual(len(before.failed_cells), 0)
        self.assertGreater(len(after.failed_cells), 0)
        graph = graph_helpers.decisions(os.path.join(out, "graph", "decisions.jsonl"))
        in_process = graph_helpers.run_valerant_explore(BUDGET, os.path.join(out, "in_process"))
        self.assertEqual(graph, in_process)
        self.assertEqual(graph_helpers.dead_graph_nodes(), [])


if __name__ == "__main__":
    rospy.init_node("test_rewind")
    rostest.rosrun("valerant", "rewind", RewindTest)
