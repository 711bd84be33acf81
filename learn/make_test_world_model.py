#!/usr/bin/python3
"""Writes the tiny ONNX models of the learned world backend's tests
(test/unit/test_world_model_net.cpp, test/unit/test_learned_world.cpp, the explore smoke
tests) into test/data:

world_model_shift.onnx has the world model's interface for K = 4 context frames of
128 x 96 (input "frames_and_motion" float32 [1,16,96,128]: 4 RGB frames in [0,1],
oldest first, then the planes forward_units, strafe_units, yaw_deg, pitch_deg; output
"warp_and_fill" float32 [1,6,96,128]). Its output is a 1x1 convolution with hand-chosen
weights, so the tests work the next frame out by hand:

  dx   = -yaw_deg    (turning left one degree moves the picture one pixel right)
  dy   =  pitch_deg  (looking down one degree moves it one pixel up)
  mask =  1 - strafe_units  (no strafe: everything is the warped newest frame; one unit of
                            strafe: everything is the fill; the candidates never strafe)
  fill =  the newest frame (channels 9..11), so a strafe of 1 returns the newest frame
          as the net read it: a check of the input's frame order and RGB planes

world_model_five_channels.onnx is the same without the last fill channel: a wrong
output shape.

world_model_anchor.onnx has the rotation_anchor warp's interface (input [1,20,96,128]: the
16 planes above, then the newest frame turned by the commanded rotation, R, G, B, and its
in-view mask): flow 0, mask = 1 - strafe_units, fill = the turned newest frame (channels
16..18). So a turn without strafe is the rotation warp alone, worked out by hand in the
tests, and a strafe of 1 returns the turned frame as the net read it.

world_model_pose.onnx is world_model_anchor.onnx for the pose_anchor warp: the same
weights over the same planes (the newest frame moved by the commanded turn and
translation through its depth, and that warp's in-view mask), its input named
"frames_motion_and_pose_warp" as a pose_anchor model's is.

Uses only onnx (Debian python3-onnx), no torch. Opset 11, as the real model's export.

  /usr/bin/python3 learn/make_test_world_model.py [--out-dir test/data]"""
import argparse
import os

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

INPUT_NAME = "frames_and_motion"
POSE_ANCHOR_INPUT_NAME = "frames_motion_and_pose_warp"
OUTPUT_NAME = "warp_and_fill"
HEIGHT, WIDTH = 96, 128
CONTEXT_FRAMES = 4
OPSET = 11
IN_CHANNELS = 3 * CONTEXT_FRAMES + 4
FORWARD, STRAFE, YAW, PITCH = range(3 * CONTEXT_FRAMES, IN_CHANNELS)
ANCHOR_IN_CHANNELS = IN_CHANNELS + 4
TURNED = IN_CHANNELS  # first channel of the turned newest frame
NEWEST = 3 * (CONTEXT_FRAMES - 1)  # first channel of the newest frame


def weights_and_biases():
    """Rows: output channels (dx, dy, mask, fill R, G, B); columns: input channels."""
    weights = np.zeros((6, IN_CHANNELS), dtype=np.float32)
    biases = np.zeros(6, dtype=np.float32)
    weights[0, YAW] = -1.0
    weights[1, PITCH] = 1.0
    weights[2, STRAFE] = -1.0
    biases[2] = 1.0
    for c in range(3):
        weights[3 + c, NEWEST + c] = 1.0
    return weights, biases


def anchor_weights_and_biases():
    """world_model_anchor.onnx's rows (dx, dy, mask, fill R, G, B) over its 20 input channels."""
    weights = np.zeros((6, ANCHOR_IN_CHANNELS), dtype=np.float32)
    biases = np.zeros(6, dtype=np.float32)
    weights[2, STRAFE] = -1.0
    biases[2] = 1.0
    for c in range(3):
        weights[3 + c, TURNED + c] = 1.0
    return weights, biases


def build_model(channels, weights_and_biases=weights_and_biases, name="world_model_shift", input_name=INPUT_NAME):
    """The 1x1 convolution's first `channels` output channels, reading the input `input_name`."""
    weights, biases = weights_and_biases()
    inputs = weights.shape[1]
    weight = numpy_helper.from_array(weights[:channels].reshape(channels, inputs, 1, 1), "conv_weight")
    bias = numpy_helper.from_array(biases[:channels], "conv_bias")
    conv = helper.make_node("Conv", [input_name, "conv_weight", "conv_bias"], [OUTPUT_NAME],
                            kernel_shape=[1, 1])
    graph = helper.make_graph(
        [conv], name,
        [helper.make_tensor_value_info(input_name, TensorProto.FLOAT, [1, inputs, HEIGHT, WIDTH])],
        [helper.make_tensor_value_info(OUTPUT_NAME, TensorProto.FLOAT, [1, channels, HEIGHT, WIDTH])],
        initializer=[weight, bias])
    model = helper.make_model(graph, producer_name="valerant make_test_world_model.py",
                              opset_imports=[helper.make_opsetid("", OPSET)])
    onnx.checker.check_model(model)
    return model


def main():
    default_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test", "data"))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out-dir", default=default_dir, help="folder the models are written to")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    for name, model in (("world_model_shift.onnx", build_model(6)),
                        ("world_model_five_channels.onnx", build_model(5)),
                        ("world_model_anchor.onnx", build_model(6, anchor_weights_and_biases, "world_model_anchor")),
                        ("world_model_pose.onnx", build_model(6, anchor_weights_and_biases, "world_model_pose",
                                                              POSE_ANCHOR_INPUT_NAME))):
        path = os.path.join(args.out_dir, name)
        onnx.save(model, path)
        print("wrote %s (%d bytes)" % (path, os.path.getsize(path)))


if __name__ == "__main__":
    main()
