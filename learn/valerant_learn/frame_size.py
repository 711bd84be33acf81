"""The net's frame sizes from shards rendered at another size.

A net whose input is `input_scale` times its output reads its frames at that larger
size and is scored on depth at the output size. Both come from one rendering: colour
resized as the deployed prior resizes the camera frame (cv2.INTER_AREA,
common/depth_prior.cpp), depth by nearest neighbour as `valerant_bench depth` resizes
the truth (an average would invent depths across a wall's edge). The intrinsics follow
the output size: the shards' principal point is in edge coordinates (cx = width / 2),
so all four scale by the same ratio."""
import cv2
import numpy as np


def parse_size(text):
    """'WxH' -> (W, H), both positive; ValueError naming the text otherwise."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise ValueError("size %r is not WIDTHxHEIGHT" % text) from None
    if width < 1 or height < 1:
        raise ValueError("size %r is not positive" % text)
    return width, height


def _resize_each(images, size, interpolation):
    return np.stack([cv2.resize(image, size, interpolation=interpolation) for image in images])


def resize_frames(data, output_size, input_scale, source="the shards"):
    """A load_shards() result with its colour at input_scale x output_size (W, H),
    its depth and intrinsics at output_size. Returns data itself when nothing
    changes. Raises ValueError naming `source` when the colour would be enlarged
    or a size does not keep the shards' aspect ratio."""
    meta = data["meta"]
    width, height = meta["width"], meta["height"]
    output_width, output_height = output_size
    input_size = (output_width * input_scale, output_height * input_scale)
    if input_size[0] > width or input_size[1] > height:
        raise ValueError("%s are %dx%d: too small for a net input of %dx%d (rendered smaller than read)"
                         % (source, width, height, input_size[0], input_size[1]))
    if output_width * height != output_height * width:
        raise ValueError("%s are %dx%d: an output of %dx%d has another aspect ratio"
                         % (source, width, height, output_width, output_height))
    if input_size == (width, height) and output_size == (width, height):
        return data
    out = dict(data)
    if input_size != (width, height):
        out["rgb"] = _resize_each(data["rgb"], input_size, cv2.INTER_AREA)
    if output_size != (width, height):
        out["depth"] = _resize_each(data["depth"], output_size, cv2.INTER_NEAREST)
    ratio = output_width / width
    out["meta"] = dict(meta, width=output_width, height=output_height,
                       **{key: meta[key] * ratio for key in ("fx", "fy", "cx", "cy")})
    return out
