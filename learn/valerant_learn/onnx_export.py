"""Export of the depth net to ONNX for OpenCV's DNN module, and its verification.

The graph is written with opset 11 from a BatchNorm-folded copy, then patched for
OpenCV 4.6 (see inline_initializer_identities), checked with onnx.checker, and
finally loaded in cv2.dnn, whose output must match torch's."""
import copy
import inspect
import io

import cv2
import numpy as np
import onnx
import torch

from .depth_net import INPUT_NAME, OUTPUT_NAME, LOG_SCALE_MIN, LOG_SCALE_MAX, fold_batchnorm

FORMAT_VERSION = "valerant-depth-prior-1"
OPSET = 11
# Largest |cv2.dnn - torch| accepted on ln(depth): 1e-3 is 0.1 % in depth.
LOG_DEPTH_TOLERANCE = 1e-3


def inline_initializer_identities(graph):
    """Removes every Identity node fed by an initializer, giving each consumer of
    its output an initializer copy of its own. torch 1.13 deduplicates equal
    initializers (e.g. the Resize scales) into Identity nodes, which OpenCV 4.6's
    importer rejects because it expects those inputs to be constants.
    Returns the number of nodes removed."""
    initializers = {tensor.name: tensor for tensor in graph.initializer}
    outputs = {output.name for output in graph.output}
    removable = [node for node in graph.node if node.op_type == "Identity"
                 and node.input[0] in initializers and node.output[0] not in outputs]
    for node in removable:
        source = initializers[node.input[0]]
        copies = 0
        for consumer in graph.node:
            for position, name in enumerate(consumer.input):
                if name == node.output[0]:
                    tensor = copy.deepcopy(source)
                    tensor.name = "%s_copy%d" % (node.output[0], copies)
                    graph.initializer.append(tensor)
                    consumer.input[position] = tensor.name
                    copies += 1
        graph.node.remove(node)
    used = {name for node in graph.node for name in node.input}
    for tensor in [tensor for tensor in graph.initializer if tensor.name not in used]:
        graph.initializer.remove(tensor)
    return len(removable)


def save_checked(proto, path, properties):
    """Replaces the model's metadata_props by `properties` (values as strings), runs
    onnx.checker and writes the file."""
    del proto.metadata_props[:]
    for key, value in properties.items():
        entry = proto.metadata_props.add()
        entry.key, entry.value = key, str(value)
    onnx.checker.check_model(proto)
    onnx.save(proto, str(path))


def _torch_export(model, height, width):
    options = {}
    # torch >= 2.9 defaults to the dynamo exporter, which cannot write opset 11.
    if "dynamo" in inspect.signature(torch.onnx.export).parameters:
        options["dynamo"] = False
    buffer = io.BytesIO()
    torch.onnx.export(model, torch.zeros(1, 3, height, width), buffer, opset_version=OPSET,
                      input_names=[INPUT_NAME], output_names=[OUTPUT_NAME],
                      dynamic_axes={INPUT_NAME: {0: "batch"}, OUTPUT_NAME: {0: "batch"}},
                      do_constant_folding=True, **options)
    return onnx.load_model_from_string(buffer.getvalue())


def torch_forward(model, rgb):
    """The float32 CPU eval-mode output of a copy of the model for a numpy batch."""
    model = copy.deepcopy(model).cpu().float().eval()
    with torch.no_grad():
        return model(torch.from_numpy(rgb)).numpy()


def opencv_forward(path, rgb):
    net = cv2.dnn.readNetFromONNX(str(path))
    net.setInput(np.ascontiguousarray(rgb, dtype=np.float32))
    return net.forward()


def verify_with_opencv(path, model, rgb):
    """Runs the ONNX file in cv2.dnn and the torch model on the same batch
    (float32 [N,3,H,W] in [0,1]); raises RuntimeError if ln depth differs by more
    than LOG_DEPTH_TOLERANCE. Returns the largest differences."""
    expected = torch_forward(model, rgb)
    actual = opencv_forward(path, rgb)
    if actual.shape != expected.shape:
        raise RuntimeError("cv2.dnn output shape %s, torch %s" % (actual.shape, expected.shape))
    diff = np.abs(actual - expected)
    report = {"max_abs_diff_log_depth": float(diff[:, 0].max()),
              "max_abs_diff_log_scale": float(diff[:, 1].max()), "batch": int(rgb.shape[0])}
    if not report["max_abs_diff_log_depth"] <= LOG_DEPTH_TOLERANCE:
        raise RuntimeError("cv2.dnn disagrees with torch on %s: max |ln depth difference| %.3g > %g"
                           % (path, report["max_abs_diff_log_depth"], LOG_DEPTH_TOLERANCE))
    return report


def export_onnx(model, path, rgb, metadata):
    """Writes the model to path as ONNX and verifies it in cv2.dnn on the batch
    rgb (float32 [N,3,H,W]). metadata: extra string-able key/values stored in the
    file's metadata_props next to the fixed description. Returns a report."""
    folded = fold_batchnorm(model)
    height, width = folded.height, folded.width
    input_height, input_width = folded.input_height, folded.input_width
    proto = _torch_export(folded, input_height, input_width)
    removed = inline_initializer_identities(proto.graph)
    properties = {
        "format": FORMAT_VERSION,
        "input": "%s: float32 [N,3,%d,%d] RGB in [0,1]" % (INPUT_NAME, input_height, input_width),
        "output": "%s: float32 [N,2,%d,%d]; channel 0 = ln(depth in metres, along the optical axis), "
                  "channel 1 = ln(b), b the Laplace scale of the ln-depth error, clamped to [%g, %g]"
                  % (OUTPUT_NAME, height, width, LOG_SCALE_MIN, LOG_SCALE_MAX),
        "input_width": input_width,
        "input_height": input_height,
        "output_width": width,
        "output_height": height,
    }
    properties.update(metadata)
    save_checked(proto, path, properties)
    report = verify_with_opencv(path, model, rgb)
    report["identity_nodes_inlined"] = removed
    report["opset"] = OPSET
    return report
