#!/usr/bin/python3
"""record.launch then replay.launch: the bag backend serves the recorded rollouts and
the rest of the graph, unchanged, makes identical decisions. Each launch runs on a ROS
master of its own (a free local port), as a user would run them one after the other."""
import os
import socket
import subprocess
import tempfile
import unittest

import rospy
import rostest

import graph_helpers

BUDGET = 3
TIMEOUT_S = 900
# VALERANT_RECORD_REPLAY_SIZE=320x240 repeats the test at another frame size.
WIDTH, HEIGHT = os.environ.get("VALERANT_RECORD_REPLAY_SIZE", "160x120").split("x")
SIZE = ("width:=" + WIDTH, "height:=" + HEIGHT, "slam:=oracle", "map:=oa_dm1")


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def launch(name, args, log):
    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % port)
    with open(log, "w") as out:
        subprocess.run(["roslaunch", "-p", str(port), "valerant", name] + list(args), env=env, stdout=out,
                       stderr=subprocess.STDOUT, timeout=TIMEOUT_S, check=True)
    # Every node must live to the end: a node that died (map_fusion at 160x120 did)
    # leaves the decisions intact, so they alone would not show it.
    deaths = graph_helpers.node_deaths(log)
    if deaths:
        raise AssertionError("%s: %s (see %s)" % (name, "; ".join(deaths), log))


class RecordReplayTest(unittest.TestCase):
    def test_replay_decides_as_recorded(self):
        out = tempfile.mkdtemp(prefix="valerant_record_")
        bag = os.path.join(out, "episode.bag")
        common = SIZE + ("budget:=%d" % BUDGET,)
        launch("record.launch", common + ("bag:=" + bag, "output_dir:=" + os.path.join(out, "recorded")),
               os.path.join(out, "record.log"))
        self.assertTrue(os.path.isfile(bag), "no bag written")
        recorded = graph_helpers.decisions(os.path.join(out, "recorded", "decisions.jsonl"))
        self.assertEqual(len([d for d in recorded if d["chosen"]]), BUDGET)
        launch("replay.launch", common + ("bag:=" + bag, "output_dir:=" + os.path.join(out, "replayed")),
               os.path.join(out, "replay.log"))
        replayed_path = os.path.join(out, "replayed", "decisions.jsonl")
        self.assertTrue(os.path.isfile(replayed_path), "replay wrote no decisions; see " + os.path.join(out, "replay.log"))
        replayed = graph_helpers.decisions(replayed_path)
        self.assertEqual(replayed, recorded)


if __name__ == "__main__":
    rospy.init_node("test_record_replay")
    rostest.rosrun("valerant", "record_replay", RecordReplayTest)
