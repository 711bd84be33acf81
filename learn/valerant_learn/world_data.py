"""Training windows for the world model from valerant_dataset shards rendered with
`--every 1` (consecutive frames).

A sequence is the run of rows of one (map, sequence) with consecutive steps. The
motion that produced frame t is recovered exactly from the poses, because the
engine's camera kinematics (camera_kinematics.cpp) apply the yaw first and then
translate along the new heading, and never stop at walls:

  yaw   = wrap(yaw_t - yaw_{t-1}) to (-180, 180]      (left positive)
  pitch = pitch_t - pitch_{t-1}
  d     = xy_t - xy_{t-1} (game units, 32 a metre)
  forward = d . (cos yaw_t, sin yaw_t)    strafe = d . (sin yaw_t, -cos yaw_t)

which are MotionStep's four fields, the commanded motion the C++ backend feeds."""
import numpy as np

UNITS_PER_METRE = 32.0
MOTION_FIELDS = ("forward_units", "strafe_units", "yaw_deg", "pitch_deg")


def wrap_degrees(angle):
    """Angle(s) in degrees wrapped to (-180, 180]."""
    wrapped = np.mod(np.asarray(angle, dtype=np.float64) + 180.0, 360.0) - 180.0
    return np.where(wrapped == -180.0, 180.0, wrapped)


def motion_between(previous, current):
    """The MotionStep that moves pose `previous` to pose `current`; a pose is a dict with
    x, y (metres), yaw_deg, pitch_deg. Returns float32 [4] in MOTION_FIELDS order."""
    yaw = float(wrap_degrees(current["yaw_deg"] - previous["yaw_deg"]))
    heading = np.radians(current["yaw_deg"])
    dx = (current["x"] - previous["x"]) * UNITS_PER_METRE
    dy = (current["y"] - previous["y"]) * UNITS_PER_METRE
    forward = dx * np.cos(heading) + dy * np.sin(heading)
    strafe = dx * np.sin(heading) - dy * np.cos(heading)
    return np.array([forward, strafe, yaw, current["pitch_deg"] - previous["pitch_deg"]], dtype=np.float32)


def split_sequences(frames):
    """Index arrays of the consecutive runs in `frames` (the columns dict of
    shards.load_shards): rows of one map and sequence whose steps follow one
    another. A gap (a frame the dataset left out) starts a new run."""
    maps, sequences, steps = frames["map"], np.asarray(frames["sequence"]), np.asarray(frames["step"])
    runs, start = [], 0
    for i in range(1, len(steps) + 1):
        if (i == len(steps) or maps[i] != maps[i - 1] or sequences[i] != sequences[i - 1]
                or steps[i] != steps[i - 1] + 1):
            runs.append(np.arange(start, i))
            start = i
    return runs


def sequence_motions(frames, run):
    """float32 [len(run), 4]: the motion into each frame of `run` (row 0: zeros, the start)."""
    motions = np.zeros((len(run), 4), dtype=np.float32)
    for j in range(1, len(run)):
        previous = {key: float(frames[key][run[j - 1]]) for key in ("x", "y", "yaw_deg", "pitch_deg")}
        current = {key: float(frames[key][run[j]]) for key in ("x", "y", "yaw_deg", "pitch_deg")}
        motions[j] = motion_between(previous, current)
    return motions


class WorldWindows:
    """Every training window of the sequences: K context frames, then `unroll` frames
    to predict with their motions. A window may start at a sequence's first frame;
    its context is then that frame repeated, as the backend starts from one
    screenshot. rgb: uint8 N x H x W x 3 (load_shards)."""

    def __init__(self, rgb, frames, context, min_length=2):
        self.rgb = rgb
        self.context = context
        self.runs = [run for run in split_sequences(frames) if len(run) >= min_length]
        self.motions = [sequence_motions(frames, run) for run in self.runs]
        self.kinds = [frames["kind"][run[0]] for run in self.runs]
        self.maps = [frames["map"][run[0]] for run in self.runs]

    def frame_count(self):
        return sum(len(run) for run in self.runs)

    def starts(self, unroll):
        """(run, t) pairs: the window predicts frames t+1 .. t+unroll of run."""
        return [(r, t) for r, run in enumerate(self.runs) for t in range(len(run) - unroll)]

    def window(self, run_index, t, unroll):
        """(context uint8 [K,H,W,3], targets uint8 [unroll,H,W,3], motions float32 [unroll,4])."""
        run = self.runs[run_index]
        positions = [max(0, t - self.context + 1 + k) for k in range(self.context)]
        context = self.rgb[run[positions]]
        targets = self.rgb[run[t + 1:t + 1 + unroll]]
        return context, targets, self.motions[run_index][t + 1:t + 1 + unroll]

    def batch(self, picks, unroll):
        """Stacks windows [(run, t), ...] into arrays with a leading batch axis."""
        parts = [self.window(r, t, unroll) for r, t in picks]
        return tuple(np.stack([part[i] for part in parts]) for i in range(3))
