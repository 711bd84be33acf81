"""Small helpers shared by the rostest test nodes: an Explore client, the in-process
valerant_explore run with the same settings, and decisions.jsonl without timings."""
import json
import os
import re
import subprocess

import actionlib
import rosnode
import rospy
import roslib.packages
from valerant.msg import ExploreAction, ExploreGoal

TIMING_KEYS = ("seconds", "wall_seconds")


def wait_for_connections(endpoint, timeout_s=60.0):
    """Waits until a rospy Subscriber or Publisher is connected to a peer: a fixed sleep
    is not enough on a loaded 2-core CI machine, and messages sent before the
    connection exists are lost."""
    deadline = rospy.Time.now() + rospy.Duration(timeout_s)
    while endpoint.get_num_connections() == 0:
        if rospy.is_shutdown() or rospy.Time.now() > deadline:
            raise RuntimeError("%s: no connection after %s s" % (endpoint.resolved_name, timeout_s))
        rospy.sleep(0.05)


DIED = re.compile(r"\[([\w./-]+)\] process has died \[pid \d+, exit code (-?\d+)|process has died \[pid \d+, exit code (-?\d+)")


def dead_graph_nodes():
    """The registered nodes that no longer answer (a crashed process stays registered
    with the master, so a ping is the test; the list covers both graph layouts, one
    branch_slam or one per candidate): an empty list when the whole graph is alive."""
    names = [n for n in rosnode.get_node_names() if n not in (rospy.get_name(), "/rosout")]
    if not any(n.endswith("/explorer") for n in names):
        return ["explorer (not registered)"]
    return [n for n in names if not rosnode.rosnode_ping(n, max_count=1, verbose=False)]


def node_deaths(roslaunch_log):
    """Lines of a roslaunch log that report a node ending with an error (a clean exit
    reads 'process has finished cleanly' instead)."""
    with open(roslaunch_log) as f:
        return [line.strip() for line in f if DIED.search(line)]


def explore(budget, output_dir, timeout_s, on_feedback=None):
    """Sends one Explore goal and waits for its result: (state, result)."""
    client = actionlib.SimpleActionClient("explorer/explore", ExploreAction)
    if not client.wait_for_server(rospy.Duration(timeout_s)):
        raise RuntimeError("explorer/explore not available")
    goal = ExploreGoal(world="", spawn=-1, budget=budget, seed=-1, output_dir=output_dir)
    client.send_goal(goal, feedback_cb=on_feedback)
    if not client.wait_for_result(rospy.Duration(timeout_s)):
        raise RuntimeError("Explore did not finish in %s s" % timeout_s)
    return client.get_state(), client.get_result()


def decisions(path):
    """The decisions of a run, without the wall-clock timings (which always differ)."""
    out = []
    with open(path) as f:
        for line in f:
            record = json.loads(line)
            for key in TIMING_KEYS:
                record.pop(key, None)
            out.append(record)
    return out


# The graph's configuration parameters and the keys they override (graph_config.cpp).
PARAMETER_KEYS = (("map", "world.map"), ("spawn", "world.spawn"), ("seed", "world.seed"),
                  ("backend", "world.backend"), ("width", "world.width"), ("height", "world.height"),
                  ("slam", "slam.backend"), ("budget", "policy.budget_steps"), ("policy", "policy.kind"),
                  ("rf", "floor.enabled"), ("col_pc", "collision.pointcloud_enabled"),
                  ("col_depth", "collision.depth_enabled"), ("dp", "dead_pocket.enabled"))


def yaml_text(value):
    return ("true" if value else "false") if isinstance(value, bool) else str(value)


def run_valerant_explore(budget, output_dir):
    """valerant_explore (in process, no ROS) with the graph's configuration: its file and
    the same overrides, skipped where empty, `set` last; returns its decisions."""
    config = rospy.get_param(rospy.search_param("valerant_config"))
    tool = roslib.packages.find_node("valerant", "valerant_explore")
    if not tool:
        raise RuntimeError("valerant_explore is not built")
    command = [tool[0], "--force", "--out", output_dir]
    if config.get("file"):
        command += ["--config", config["file"]]
    for parameter, key in PARAMETER_KEYS:
        if yaml_text(config.get(parameter, "")):
            command += ["--set", "%s=%s" % (key, yaml_text(config[parameter]))]
    command += [arg for assignment in config.get("set", "").split() for arg in ("--set", assignment)]
    command += ["--set", "policy.budget_steps=%d" % budget]  # the goal's budget, as the explorer takes it
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    return decisions(os.path.join(output_dir, "decisions.jsonl"))
