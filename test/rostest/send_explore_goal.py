#!/usr/bin/python3
"""rates.test helper: starts one Explore episode (~budget steps into ~output_dir) so the
graph's periodic topics have a committed camera to publish, then stays up."""
import actionlib
import rospy
from valerant.msg import ExploreAction, ExploreGoal

if __name__ == "__main__":
    rospy.init_node("send_explore_goal")
    client = actionlib.SimpleActionClient("explorer/explore", ExploreAction)
    client.wait_for_server()
    client.send_goal(ExploreGoal(world="", spawn=-1, budget=rospy.get_param("~budget"), seed=-1,
                                 output_dir=rospy.get_param("~output_dir")))
    rospy.spin()
