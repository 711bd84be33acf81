#!/usr/bin/python3
"""Writes the tiny ONNX models of DepthPrior's unit tests (test/unit/test_depth_prior.cpp)
into test/data:

depth_prior_linear.onnx has the depth prior's interface (input "rgb" float32
[1,3,96,128] RGB in [0,1]; output "depth_and_scale" float32 [1,2,96,128]); its output
is a 1x1 convolution with hand-chosen weights, so the tests check numbers by hand:

  channel 0, ln(depth in metres) = ln 2 + 1.0 R + 0.5 G + 0.25 B
  channel 1, ln(b)               = -1 + 0.5 B

depth_prior_one_channel.onnx is the same without channel 1: a wrong output shape.

depth_prior_linear_x2.onnx is the same convolution at stride 2 over an input of twice the
size ([1,3,192,256] in, [1,2,96,128] out): a net that reads frames larger than its output.

Uses only onnx (Debian python3-onnx), no torch. Opset 11, as the real model's export.

  /usr/bin/python3 learn/make_test_depth_model.py [--out-dir test/data]"""
import argparse
import math
import os

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

INPUT_NAME = "rgb"
OUTPUT_NAME = "depth_and_scale"
HEIGHT, WIDTH = 96, 128
OPSET = 11
# Rows: output channels (ln depth, ln b); columns: input channels (R, G, B).
WEIGHTS = np.array([[1.0, 0.5, 0.25],
                    [0.0, 0.0, 0.5]], dtype=np.float32)
BIASES = np.array([math.log(2.0), -1.0], dtype=np.float32)


def build_model(channels, stride=1):
    """The 1x1 convolution's first `channels` output channels, over an input of
    stride x the output size."""
    weight = numpy_helper.from_array(WEIGHTS[:channels].reshape(channels, 3, 1, 1), "conv_weight")
    bias = numpy_helper.from_array(BIASES[:channels], "conv_bias")
    conv = helper.make_node("Conv", [INPUT_NAME, "conv_weight", "conv_bias"], [OUTPUT_NAME],
                            kernel_shape=[1, 1], **({} if stride == 1 else {"strides": [stride, stride]}))
    graph = helper.make_graph(
        [conv], "depth_prior_linear",
        [helper.make_tensor_value_info(INPUT_NAME, TensorProto.FLOAT, [1, 3, stride * HEIGHT, stride * WIDTH])],
        [helper.make_tensor_value_info(OUTPUT_NAME, TensorProto.FLOAT, [1, channels, HEIGHT, WIDTH])],
        initializer=[weight, bias])
    model = helper.make_model(graph, producer_name="valerant make_test_depth_model.py",
                              opset_imports=[helper.make_opsetid("", OPSET)])
    onnx.checker.check_model(model)
    return model


def main():
    default_dir = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test", "data"))
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out-dir", default=default_dir, help="folder the models are written to")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    for name, channels, stride in (("depth_prior_linear.onnx", 2, 1), ("depth_prior_one_channel.onnx", 1, 1),
                                   ("depth_prior_linear_x2.onnx", 2, 2)):
        path = os.path.join(args.out_dir, name)
        onnx.save(build_model(channels, stride), path)
        print("wrote %s (%d bytes)" % (path, os.path.getsize(path)))


if __name__ == "__main__":
    main()
