"""Reading (and, for tests, writing) the dataset shards that `valerant_dataset` writes.

A shard is a zip holding meta.json, frames.csv, rgb/%06d.jpg and depth/%06d.png
(16-bit log16 codes, see log16.py). load_shards() checks every entry and raises a
ValueError naming the shard and the entry on anything malformed, so a bad shard
stops training at once instead of silently feeding it garbage."""
import concurrent.futures
import csv
import io
import json
import math
import os
import zipfile

import cv2
import numpy as np

from .log16 import decode_log16, encode_log16

FORMAT = "valerant-dataset-1"
DEPTH_ENCODING = "log16"
FRAME_COLUMNS = ["index", "map", "spawn", "sequence", "step", "kind", "key",
                 "x", "y", "z", "yaw_deg", "pitch_deg", "in_solid"]
KINDS = ("rollout", "rotate", "walk")
INT_COLUMNS = ("spawn", "sequence", "step")
FLOAT_COLUMNS = ("x", "y", "z", "yaw_deg", "pitch_deg")
STR_COLUMNS = ("map", "kind", "key")
# Fields every shard of one data set must agree on: the net is trained for one camera
# at one height over the floor.
CAMERA_KEYS = ("width", "height", "fx", "fy", "cx", "cy", "eye_height_m", "depth_min_m", "depth_max_m")
REQUIRED_META = ("format", "depth_encoding", "maps") + CAMERA_KEYS


def rgb_name(index):
    return "rgb/%06d.jpg" % index


def depth_name(index):
    return "depth/%06d.png" % index


def _read_entry(archive, path, name):
    try:
        return archive.read(name)
    except KeyError:
        raise ValueError("%s: missing entry %s" % (path, name)) from None


def _parse_meta(path, raw):
    try:
        meta = json.loads(raw)
    except ValueError as error:
        raise ValueError("%s: meta.json is not valid JSON (%s)" % (path, error)) from None
    if not isinstance(meta, dict):
        raise ValueError("%s: meta.json is not a JSON object" % path)
    missing = [key for key in REQUIRED_META if key not in meta]
    if missing:
        raise ValueError("%s: meta.json lacks %s" % (path, ", ".join(missing)))
    if meta["format"] != FORMAT:
        raise ValueError("%s: unknown format %r (expected %r)" % (path, meta["format"], FORMAT))
    if meta["depth_encoding"] != DEPTH_ENCODING:
        raise ValueError("%s: unknown depth_encoding %r (expected %r)"
                         % (path, meta["depth_encoding"], DEPTH_ENCODING))
    if not (isinstance(meta["width"], int) and isinstance(meta["height"], int)
            and meta["width"] > 0 and meta["height"] > 0):
        raise ValueError("%s: bad image size %rx%r" % (path, meta["width"], meta["height"]))
    if not 0 < meta["depth_min_m"] < meta["depth_max_m"]:
        raise ValueError("%s: bad depth range [%r, %r]" % (path, meta["depth_min_m"], meta["depth_max_m"]))
    return meta


def _parse_frames(path, raw, maps):
    try:
        rows = list(csv.reader(io.StringIO(raw.decode("utf-8"))))
    except UnicodeDecodeError:
        raise ValueError("%s: frames.csv is not UTF-8" % path) from None
    if not rows or rows[0] != FRAME_COLUMNS:
        raise ValueError("%s: frames.csv header is %r, expected %r"
                         % (path, rows[0] if rows else None, ",".join(FRAME_COLUMNS)))
    columns = {name: [] for name in FRAME_COLUMNS}
    for line, row in enumerate(rows[1:], start=2):
        where = "%s: frames.csv line %d" % (path, line)
        if len(row) != len(FRAME_COLUMNS):
            raise ValueError("%s has %d fields, expected %d" % (where, len(row), len(FRAME_COLUMNS)))
        record = dict(zip(FRAME_COLUMNS, row))
        try:
            index = int(record["index"])
            ints = [int(record[name]) for name in INT_COLUMNS]
            floats = [float(record[name]) for name in FLOAT_COLUMNS]
            in_solid = int(record["in_solid"])
        except ValueError as error:
            raise ValueError("%s: %s" % (where, error)) from None
        if index != line - 2:
            raise ValueError("%s: index %d, expected %d" % (where, index, line - 2))
        if record["kind"] not in KINDS:
            raise ValueError("%s: unknown kind %r" % (where, record["kind"]))
        if record["map"] not in maps:
            raise ValueError("%s: map %r is not in meta.json's maps" % (where, record["map"]))
        if in_solid not in (0, 1):
            raise ValueError("%s: in_solid must be 0 or 1" % where)
        columns["index"].append(index)
        for name, value in zip(INT_COLUMNS, ints):
            columns[name].append(value)
        for name, value in zip(FLOAT_COLUMNS, floats):
            columns[name].append(value)
        for name in STR_COLUMNS:
            columns[name].append(record[name])
        columns["in_solid"].append(bool(in_solid))
    if not columns["index"]:
        raise ValueError("%s: frames.csv lists no frames" % path)
    return columns


def _decode_frame(path, width, height, meta, index, jpg, png):
    rgb = cv2.imdecode(np.frombuffer(jpg, np.uint8), cv2.IMREAD_COLOR)
    if rgb is None:
        raise ValueError("%s: %s is not a readable image" % (path, rgb_name(index)))
    if rgb.shape != (height, width, 3):
        raise ValueError("%s: %s is %dx%d, meta.json says %dx%d"
                         % (path, rgb_name(index), rgb.shape[1], rgb.shape[0], width, height))
    code = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_UNCHANGED)
    if code is None:
        raise ValueError("%s: %s is not a readable image" % (path, depth_name(index)))
    if code.dtype != np.uint16 or code.shape != (height, width):
        raise ValueError("%s: %s must be a %dx%d 16-bit single-channel PNG, is %s %s"
                         % (path, depth_name(index), width, height, code.dtype, code.shape))
    depth = decode_log16(code, meta["depth_min_m"], meta["depth_max_m"])
    return cv2.cvtColor(rgb, cv2.COLOR_BGR2RGB), depth


def _read_index(path):
    """(meta, columns) of a shard: its meta.json and frames.csv, checked."""
    if not os.path.isfile(path):
        raise ValueError("%s: no such shard" % path)
    try:
        with zipfile.ZipFile(path) as archive:
            meta = _parse_meta(path, _read_entry(archive, path, "meta.json"))
            columns = _parse_frames(path, _read_entry(archive, path, "frames.csv"), set(meta["maps"]))
    except zipfile.BadZipFile as error:
        raise ValueError("%s: not a zip file (%s)" % (path, error)) from None
    return meta, columns


def _decode_shard(path, meta, columns, pool, rgb_out, depth_out):
    """Decodes the shard's frames into rgb_out and depth_out (one row a frame, in
    frames.csv order)."""
    try:
        with zipfile.ZipFile(path) as archive:
            blobs = [(i, _read_entry(archive, path, rgb_name(i)), _read_entry(archive, path, depth_name(i)))
                     for i in columns["index"]]
    except zipfile.BadZipFile as error:
        raise ValueError("%s: not a zip file (%s)" % (path, error)) from None
    width, height = meta["width"], meta["height"]

    def decode(row):
        rgb_out[row], depth_out[row] = _decode_frame(path, width, height, meta, *blobs[row])

    list(pool.map(decode, range(len(blobs))))


def check_same_camera(first_path, first, path, meta):
    """Raises a ValueError naming both sources if two metas differ in CAMERA_KEYS."""
    for key in CAMERA_KEYS:
        if not math.isclose(first[key], meta[key], rel_tol=1e-6):
            raise ValueError("%s: %s is %r but %s has %r" % (path, key, meta[key], first_path, first[key]))


def load_shards(paths, workers=1):
    """Loads shards into memory. Returns a dict of per-frame numpy arrays
    ('rgb' uint8 N×H×W×3 RGB, 'depth' float32 N×H×W metres with NaN for sky,
    'shard', 'index' and every frames.csv column) plus 'meta': the camera and
    depth-encoding fields the shards share, 'maps' (sorted, as present in
    frames) and 'shards' (the paths). Every shard's index is read and checked
    first; the frames are then decoded straight into arrays of their final size, so
    a data set takes its own size in memory and one shard's compressed bytes more."""
    paths = list(paths)
    if not paths:
        raise ValueError("no shards given")
    indices = [(path,) + _read_index(path) for path in paths]
    first_path, first_meta = indices[0][0], indices[0][1]
    for path, meta, _ in indices[1:]:
        check_same_camera(first_path, first_meta, path, meta)
    counts = [len(columns["index"]) for _, _, columns in indices]
    total, width, height = sum(counts), first_meta["width"], first_meta["height"]
    rgb = np.empty((total, height, width, 3), np.uint8)
    depth = np.empty((total, height, width), np.float32)
    with concurrent.futures.ThreadPoolExecutor(max(1, workers)) as pool:
        start = 0
        for (path, meta, columns), count in zip(indices, counts):
            _decode_shard(path, meta, columns, pool, rgb[start:start + count], depth[start:start + count])
            start += count
    data = {name: np.concatenate([np.asarray(columns[name]) for _, _, columns in indices]) for name in FRAME_COLUMNS}
    data["shard"] = np.concatenate([np.full(count, path) for (path, _, _), count in zip(indices, counts)])
    data["rgb"], data["depth"] = rgb, depth
    meta = {key: first_meta[key] for key in ("format", "depth_encoding") + CAMERA_KEYS}
    meta["maps"] = sorted(set(data["map"].tolist()))
    meta["shards"] = paths
    data["meta"] = meta
    return data


def write_shard(path, rgb, depth, frames, meta):
    """Writes a shard in the format above (for tests and synthetic data).
    rgb: N×H×W×3 uint8 RGB; depth: N×H×W metres, NaN for sky; frames: N dicts with
    the frames.csv columns except 'index'; meta: at least fx, fy, cx, cy,
    depth_min_m, depth_max_m (format, encoding, size and maps are filled in)."""
    rgb = np.asarray(rgb)
    depth = np.asarray(depth)
    count, height, width = depth.shape
    if rgb.shape != (count, height, width, 3) or rgb.dtype != np.uint8 or len(frames) != count:
        raise ValueError("write_shard: rgb, depth and frames disagree")
    full_meta = {"format": FORMAT, "width": width, "height": height, "depth_encoding": DEPTH_ENCODING,
                 "maps": sorted({frame["map"] for frame in frames})}
    full_meta.update(meta)
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(FRAME_COLUMNS)
    for index, frame in enumerate(frames):
        writer.writerow([index] + [frame[name] for name in FRAME_COLUMNS[1:]])
    codes = encode_log16(depth, full_meta["depth_min_m"], full_meta["depth_max_m"])
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("meta.json", json.dumps(full_meta, indent=1))
        archive.writestr("frames.csv", text.getvalue())
        for index in range(count):
            ok_rgb, jpg = cv2.imencode(".jpg", cv2.cvtColor(rgb[index], cv2.COLOR_RGB2BGR),
                                       [cv2.IMWRITE_JPEG_QUALITY, 95])
            ok_depth, png = cv2.imencode(".png", codes[index])
            if not (ok_rgb and ok_depth):
                raise ValueError("write_shard: could not encode frame %d" % index)
            # Images are compressed already: store them.
            archive.writestr(rgb_name(index), jpg.tobytes(), zipfile.ZIP_STORED)
            archive.writestr(depth_name(index), png.tobytes(), zipfile.ZIP_STORED)
