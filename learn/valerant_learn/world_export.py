"""Export of the world model to ONNX for OpenCV's DNN module, and its verification:
opset 11 from a BatchNorm-folded copy, patched for OpenCV 4.6
(onnx_export.inline_initializer_identities), checked, then run in cv2.dnn, whose
output must match torch's."""
import copy
import inspect
import io

import cv2
import numpy as np
import onnx
import torch

from .depth_net import fold_batchnorm
from .onnx_export import OPSET, inline_initializer_identities, save_checked
from .world_net import OUTPUT_NAME, input_channels, input_name

FORMAT_VERSION = "valerant-world-model-1"
# Largest |cv2.dnn - torch| accepted on any output channel (flow in pixels, the rest in [0,1]).
TOLERANCE = 1e-3


def _torch_export(model, channels):
    options = {}
    # torch >= 2.9 defaults to the dynamo exporter, which cannot write opset 11.
    if "dynamo" in inspect.signature(torch.onnx.export).parameters:
        options["dynamo"] = False
    buffer = io.BytesIO()
    torch.onnx.export(model, torch.zeros(1, channels, model.height, model.width), buffer, opset_version=OPSET,
                      input_names=[input_name(model.warp)], output_names=[OUTPUT_NAME], do_constant_folding=True,
                      **options)
    return onnx.load_model_from_string(buffer.getvalue())


def verify_with_opencv(path, model, inputs):
    """Runs the file in cv2.dnn and the model in torch on each input (float32
    [N, input_channels(model), H, W], one at a time as the backend does); raises RuntimeError beyond
    TOLERANCE. Returns the largest difference."""
    reference = copy.deepcopy(model).cpu().float().eval()
    net = cv2.dnn.readNetFromONNX(str(path))
    worst = 0.0
    for single in inputs:
        single = np.ascontiguousarray(single[None], dtype=np.float32)
        with torch.no_grad():
            expected = reference(torch.from_numpy(single)).numpy()
        net.setInput(single)
        actual = net.forward()
        if actual.shape != expected.shape:
            raise RuntimeError("cv2.dnn output shape %s, torch %s" % (actual.shape, expected.shape))
        worst = max(worst, float(np.abs(actual - expected).max()))
    if not worst <= TOLERANCE:
        raise RuntimeError("cv2.dnn disagrees with torch on %s: max |difference| %.3g > %g" % (path, worst, TOLERANCE))
    return {"max_abs_diff": worst, "inputs": int(len(inputs))}


def export_world_onnx(model, path, inputs, metadata):
    """Writes the model to path as ONNX (batch 1) and verifies it in cv2.dnn on
    `inputs`. metadata: extra key/values for the file's metadata_props."""
    folded = fold_batchnorm(model)
    channels = input_channels(model)
    extra = {"last_frame": "", "rotation_anchor": ", then the newest frame turned by the commanded rotation (RGB) "
             "and that rotation's in-view mask",
             "pose_anchor": ", then the newest frame sampled where the commanded turn and translation send each "
             "pixel through its depth (RGB) and the in-view mask"}[model.warp]
    proto = _torch_export(folded, channels)
    removed = inline_initializer_identities(proto.graph)
    properties = {
        "format": FORMAT_VERSION,
        "input": "%s: float32 [1,%d,%d,%d]: %d RGB frames in [0,1], oldest first, then 4 constant planes of "
                 "the motion (forward_units, strafe_units, yaw_deg, pitch_deg)%s"
                 % (input_name(model.warp), channels, model.height, model.width, model.context, extra),
        "output": "%s: float32 [1,6,%d,%d]: dx, dy (pixels), mask, fill RGB; next = mask * warped + (1 - mask) "
                  "* fill, warped as world_warp.py's %s warp says" % (OUTPUT_NAME, model.height, model.width,
                                                                     model.warp),
        "context_frames": model.context,
        "warp": model.warp,
        "input_width": model.width,
        "input_height": model.height,
    }
    properties.update(metadata)
    save_checked(proto, path, properties)
    report = verify_with_opencv(path, model, inputs)
    report["identity_nodes_inlined"] = removed
    report["opset"] = OPSET
    return report
