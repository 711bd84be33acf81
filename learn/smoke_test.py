#!/usr/bin/env python3
"""CPU smoke test of the depth-prior training code (one core, well under 90 s).

Unit tests (log16 coding, metrics, loss, shard checks) and an end-to-end run of
train_depth.py on two tiny synthetic shards of different maps, whose ONNX output
must load in cv2.dnn and match torch.

  smoke_test.py [--xml PATH]   # PATH: JUnit XML for scripts/count_test_results"""
import contextlib
import glob
import io
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest
import zipfile

import cv2
import numpy as np
import onnx
import torch

import error_by_depth
import pack_parts
import train_depth
from valerant_learn.depth_net import ColumnContext, DepthNet, GlobalContext, count_parameters, scaled_channels
from valerant_learn.floor_prior import floor_log_depth
from valerant_learn.frame_size import parse_size, resize_frames
from valerant_learn.junit import run_smoke_test
from valerant_learn.log16 import decode_log16, encode_log16
from valerant_learn.losses import decoupled_loss, gradient_matching_loss, laplace_nll, training_loss
from valerant_learn.metrics import frame_calibration, frame_metrics
from valerant_learn.onnx_export import verify_with_opencv
from valerant_learn.shards import load_shards, write_shard
from valerant_learn.weight_average import WeightAverage

HERE = os.path.dirname(os.path.abspath(__file__))
WIDTH, HEIGHT = 128, 96
EYE_HEIGHT_M = 1.5625
# 90 degrees horizontal field of view, square pixels, centred principal point.
CAMERA = {"fx": 64.0, "fy": 64.0, "cx": 63.5, "cy": 47.5, "depth_min_m": 0.05, "depth_max_m": 200.0,
          "seed": 0, "units_per_metre": 32, "eye_height_m": EYE_HEIGHT_M}
TRAIN_MAP, VAL_MAP, SELECT_MAP = "synth_train", "synth_val", "synth_select"


def scaled_camera(scale):
    """CAMERA for frames of scale x WIDTH x HEIGHT (the same field of view)."""
    return dict(CAMERA, **{key: CAMERA[key] * scale for key in ("fx", "fy")},
                **{key: (CAMERA[key] + 0.5) * scale - 0.5 for key in ("cx", "cy")})


def synthetic_frame(rng, scale=1):
    """A level camera at eye height over a checkered floor, facing a striped wall
    at a random distance and of random height, sky above it, in a frame of scale x
    WIDTH x HEIGHT. Floor depth follows from the fixed eye height: z = h * fy / (v - cy)."""
    camera, width, height = scaled_camera(scale), WIDTH * scale, HEIGHT * scale
    u = np.arange(width)[None, :] - camera["cx"]
    v = np.arange(height)[:, None] - camera["cy"]
    down = np.broadcast_to(v / camera["fy"], (height, width))
    right = np.broadcast_to(u / camera["fx"], (height, width))
    wall_m, wall_height_m = rng.uniform(4, 30), rng.uniform(1, 8)
    with np.errstate(divide="ignore"):
        floor = np.where(down > 0, EYE_HEIGHT_M / down, np.inf)
    on_wall = (down * wall_m <= EYE_HEIGHT_M) & (EYE_HEIGHT_M - down * wall_m <= wall_height_m)
    depth = np.minimum(floor, np.where(on_wall, wall_m, np.inf))
    sky = ~np.isfinite(depth)
    depth = np.where(sky, np.nan, depth)
    x = right * np.where(sky, 0, depth)
    checker = (np.floor(x) + np.floor(np.where(sky, 0, depth))) % 2
    stripes = np.floor(x * 2) % 2
    floor_colour, wall_colour = rng.uniform(0.2, 0.9, 3), rng.uniform(0.2, 0.9, 3)
    rgb = np.where((depth < floor - 1e-6)[..., None], wall_colour * (0.7 + 0.3 * stripes[..., None]),
                   floor_colour * (0.6 + 0.4 * checker[..., None]))
    rgb = np.where(sky[..., None], np.array([0.5, 0.7, 1.0]), rgb)
    return (rgb * 255).astype(np.uint8), depth.astype(np.float32)


def synthetic_shard(path, map_name, count, seed, scale=1):
    rng = np.random.default_rng(seed)
    frames, rgbs, depths = [], [], []
    for index in range(count):
        rgb, depth = synthetic_frame(rng, scale)
        rgbs.append(rgb)
        depths.append(depth)
        kind = ("rollout", "rotate", "walk")[index % 3]
        frames.append({"map": map_name, "spawn": 0, "sequence": index // 4, "step": index % 4, "kind": kind,
                       "key": "" if index % 4 == 0 else {"rollout": "w", "rotate": "l", "walk": "jw"}[kind],
                       "x": 0.5 * index, "y": 0.0, "z": EYE_HEIGHT_M, "yaw_deg": 10.0 * index,
                       "pitch_deg": 0.0, "in_solid": 0})
    write_shard(path, np.stack(rgbs), np.stack(depths), frames, scaled_camera(scale))


def rewrite_zip(source, target, changes):
    """Copies a zip, replacing entries by changes[name] (bytes) or dropping them (None)."""
    with zipfile.ZipFile(source) as old, zipfile.ZipFile(target, "w") as new:
        for name in old.namelist():
            data = changes.get(name, old.read(name))
            if data is not None:
                new.writestr(name, data)


def setUpModule():
    global WORK, TRAIN_SHARD, VAL_SHARD, SELECT_SHARD, TRAIN_SHARD_X2, VAL_SHARD_X2
    WORK = tempfile.mkdtemp(prefix="valerant_learn_smoke_")
    TRAIN_SHARD = os.path.join(WORK, "train.zip")
    VAL_SHARD = os.path.join(WORK, "val.zip")
    SELECT_SHARD = os.path.join(WORK, "select.zip")
    synthetic_shard(TRAIN_SHARD, TRAIN_MAP, 24, seed=1)
    synthetic_shard(VAL_SHARD, VAL_MAP, 8, seed=2)
    synthetic_shard(SELECT_SHARD, SELECT_MAP, 6, seed=4)
    # The same scenes rendered at twice the size, for nets that read frames larger than their output.
    TRAIN_SHARD_X2 = os.path.join(WORK, "train_x2.zip")
    VAL_SHARD_X2 = os.path.join(WORK, "val_x2.zip")
    synthetic_shard(TRAIN_SHARD_X2, TRAIN_MAP, 24, seed=1, scale=2)
    synthetic_shard(VAL_SHARD_X2, VAL_MAP, 8, seed=2, scale=2)


def tearDownModule():
    shutil.rmtree(WORK, ignore_errors=True)


class Log16Test(unittest.TestCase):
    def test_hand_computed_codes(self):
        decoded = decode_log16(np.array([0, 1, 65535], np.uint16), 0.05, 200.0)
        self.assertTrue(math.isnan(decoded[0]))
        self.assertAlmostEqual(float(decoded[1]), 0.05, places=6)
        self.assertAlmostEqual(float(decoded[2]), 200.0, places=3)
        # 1 m: 1 + ln(1/0.05) / ln(200/0.05) * 65534 = 1 + 2.995732 / 8.294050 * 65534 = 23671.26
        self.assertEqual(int(encode_log16(np.array([1.0]), 0.05, 200.0)[0]), 23671)

    def test_round_trip_within_half_a_code(self):
        depth = np.array([0.05, 0.1, 0.7, 1.0, 3.3, 12.0, 80.0, 199.0, 200.0])
        back = decode_log16(encode_log16(depth, 0.05, 200.0), 0.05, 200.0)
        half_step = math.log(4000.0) / 65534 / 2
        self.assertLessEqual(np.abs(np.log(back) - np.log(depth)).max(), half_step * 1.01)

    def test_sky_and_clipping(self):
        codes = encode_log16(np.array([np.nan, np.inf, 0.0, 0.01, 500.0]), 0.05, 200.0)
        self.assertEqual(codes.tolist(), [0, 0, 0, 1, 65535])


class MetricsTest(unittest.TestCase):
    def test_hand_worked_example(self):
        figures = frame_metrics(np.array([[[1.0, 2.0]]]), np.array([[[1.0, 4.0]]]))
        self.assertAlmostEqual(figures["abs_rel"][0], 0.25)    # (0/1 + 2/4) / 2
        self.assertAlmostEqual(figures["delta1"][0], 0.5)      # 1 < 1.25, 2 is not
        self.assertAlmostEqual(figures["rmse_log"][0], math.log(2) / math.sqrt(2))

    def test_sky_left_out_and_depth_clipped(self):
        figures = frame_metrics(np.array([[[80.0, 5.0]], [[1.0, 1.0]]]),
                                np.array([[[100.0, np.nan]], [[np.nan, np.nan]]]))
        self.assertAlmostEqual(figures["abs_rel"][0], 0.0)     # 100 m is clipped to 80 m
        self.assertEqual(figures["pixels"].tolist(), [1.0, 0.0])
        self.assertTrue(math.isnan(figures["abs_rel"][1]))

    def test_hand_worked_calibration(self):
        # Both pixels predict 2 m; truths 1 m and 4 m: |e| = ln 2 = 0.693147 at both.
        # b = 0.5: |e|/b = 1.386294, not within; b = 4: 0.173287, within; sky left out.
        log_depth = torch.full((1, 1, 3), math.log(2.0))
        log_scale = torch.tensor([[[math.log(0.5), math.log(4.0), 0.0]]])
        figures = frame_calibration(log_depth, log_scale, torch.tensor([[[1.0, 4.0, float("nan")]]]))
        self.assertAlmostEqual(figures["scaled_error"][0], (1.386294 + 0.173287) / 2, places=5)
        self.assertAlmostEqual(figures["within_scale"][0], 0.5)


class LossTest(unittest.TestCase):
    def test_hand_worked_laplace_nll(self):
        output = torch.zeros(1, 2, 1, 2)
        output[0, 0] = math.log(2.0)          # predicts 2 m everywhere
        output[0, 1, 0, 1] = math.log(2.0)    # b = 2 at the second pixel
        depth = torch.tensor([[[1.0, float("nan")]]])  # 1 m, then sky (80 m)
        # pixel 1: |ln 2 - ln 1| / 1 + 0 = 0.693147
        # pixel 2: |ln 2 - ln 80| / 2 + ln 2 = 3.688879 / 2 + 0.693147 = 2.537587
        self.assertAlmostEqual(float(laplace_nll(output, depth)), (0.693147 + 2.537587) / 2, places=5)

    def test_hand_worked_decoupled_loss(self):
        output = torch.zeros(1, 2, 1, 2)
        output[0, 0] = math.log(2.0)          # predicts 2 m everywhere
        output[0, 1, 0, 1] = math.log(2.0)    # b = 2 at the second pixel
        depth = torch.tensor([[[1.0, float("nan")]]])  # 1 m, then sky (80 m)
        # pixel 1: e = ln 2: depth |e| + |2/1 - 1| = 0.693147 + 1 = 1.693147; scale 0.693147 / 1 + 0
        # pixel 2 (sky, no AbsRel): e = ln 2 - ln 80 = -3.688879: depth 3.688879;
        #   scale 3.688879 / 2 + ln 2 = 2.537587
        expected = (1.693147 + 0.693147 + 3.688879 + 2.537587) / 2
        self.assertAlmostEqual(float(decoupled_loss(output, depth)), expected, places=5)

    def test_decoupled_depth_gradient_ignores_the_scale(self):
        """The depth's gradient is the same whatever ln b: no pixel can be given up."""
        depth = torch.tensor([[[1.0, 3.0]]])
        gradients = []
        for log_scale in (-6.0, 3.0):
            output = torch.full((1, 2, 1, 2), log_scale)
            output[0, 0] = torch.tensor([math.log(2.0), math.log(1.5)])
            output.requires_grad_(True)
            decoupled_loss(output, depth).backward()
            gradients.append(output.grad[0, 0].clone())
        # d/de (|e| + |exp(e) - 1|) / 2 pixels: (1 + 2) / 2 = 1.5 too far; (-1 - 0.5) / 2 = -0.75 too near.
        self.assertTrue(torch.allclose(gradients[0], torch.tensor([[1.5, -0.75]])), gradients[0])
        self.assertTrue(torch.equal(gradients[0], gradients[1]))

    def test_abs_rel_term_capped(self):
        # e = 5 (148 times too far): the AbsRel term stops at e = 3: exp(3) - 1 = 19.085537.
        output = torch.zeros(1, 2, 1, 1)
        output[0, 0] = 5.0
        self.assertAlmostEqual(float(decoupled_loss(output, torch.ones(1, 1, 1))), 5 + 19.085537 + 5, places=4)

    def test_hand_worked_gradient_matching(self):
        depth = torch.ones(1, 2, 2)  # 1 m everywhere: e = mu
        output = torch.zeros(1, 2, 2, 2)
        output[0, 0, 0, 1] = 1.0     # e = [[0, 1], [0, 0]]
        # scale 0: across |1 - 0| and |0 - 0|, mean 0.5; down |0 - 0| and |0 - 1|, mean 0.5: 1.0
        # scale 1 (every 2nd pixel): one pixel, no neighbours: 0. Mean over the 2 scales: 0.5
        self.assertAlmostEqual(float(gradient_matching_loss(output, depth, scales=2)), 0.5, places=6)
        # A prediction off by one global factor has the true shape: no cost.
        self.assertAlmostEqual(float(gradient_matching_loss(torch.full((1, 2, 2, 2), 0.7), depth, scales=2)), 0.0,
                               places=6)

    def test_gradient_matching_sky_at_80_m(self):
        # Row [1 m, sky]: predicting 80 m at the sky pixel and 1 m beside it is exact.
        depth = torch.tensor([[[1.0, float("nan")]]])
        output = torch.zeros(1, 2, 1, 2)
        output[0, 0, 0, 1] = math.log(80.0)
        self.assertAlmostEqual(float(gradient_matching_loss(output, depth, scales=1)), 0.0, places=5)
        output[0, 0, 0, 1] = 0.0  # sky predicted at 1 m: the step ln 80 = 4.382027 is missed
        self.assertAlmostEqual(float(gradient_matching_loss(output, depth, scales=1)), 4.382027, places=5)

    def test_unknown_loss(self):
        with self.assertRaises(ValueError) as caught:
            training_loss("l2")
        self.assertIn("unknown loss 'l2'", str(caught.exception))

    def test_floor_scene_loss_decreases(self):
        torch.manual_seed(0)
        data = load_shards([TRAIN_SHARD])
        rgb = train_depth.as_input(torch.from_numpy(data["rgb"][:8]))
        depth = torch.from_numpy(data["depth"][:8])
        model = DepthNet(HEIGHT, WIDTH)
        optimizer = torch.optim.AdamW(model.parameters(), lr=3e-3)
        losses = []
        for _ in range(8):
            loss = laplace_nll(model(rgb), depth)
            optimizer.zero_grad()
            loss.backward()
            optimizer.step()
            losses.append(float(loss))
        self.assertLess(losses[-1], 0.8 * losses[0], losses)


class GlobalContextTest(unittest.TestCase):
    def test_every_position_sees_the_whole_frame(self):
        """A change at the far corner of the stride-32 grid reaches the opposite
        corner, which a 1x1 layer alone could not do."""
        torch.manual_seed(0)
        context = GlobalContext(8, 3, 4).eval()
        features = torch.rand(1, 8, 3, 4)
        changed = features.clone()
        changed[0, :, 2, 3] += 5
        with torch.no_grad():
            difference = (context(features) - context(changed))[0, :, 0, 0].abs().max()
        self.assertGreater(float(difference), 1e-3)
        self.assertEqual(tuple(context(features).shape), (1, 8, 3, 4))


class ColumnContextTest(unittest.TestCase):
    def hand_set_context(self):
        """A ColumnContext of one channel whose summary layer passes the column
        mean on unchanged and whose mix keeps only the summary (eval-mode
        BatchNorm at its initial statistics divides by sqrt(1 + 1e-5))."""
        context = ColumnContext(1, 3, summary_channels=1).eval()
        with torch.no_grad():
            context.summary[0].weight.fill_(1.0)
            context.summary[0].bias.zero_()
            context.mix[0].weight.copy_(torch.tensor([0.0, 1.0]).view(1, 2, 1, 1))
        return context

    def test_hand_worked_column_means(self):
        # columns 0..3 of a 3-row grid: means (1+3+5)/3 = 3, (2+4+0)/3 = 2, (3+5+1)/3 = 3, (4+6+2)/3 = 4
        features = torch.tensor([[1.0, 2.0, 3.0, 4.0],
                                 [3.0, 4.0, 5.0, 6.0],
                                 [5.0, 0.0, 1.0, 2.0]]).view(1, 1, 3, 4)
        with torch.no_grad():
            output = self.hand_set_context()(features)[0, 0]
        expected = torch.tensor([3.0, 2.0, 3.0, 4.0]).expand(3, 4) / math.sqrt(1 + 1e-5)
        self.assertTrue(torch.allclose(output, expected, atol=1e-6), output)

    def test_a_column_sees_only_itself(self):
        """A change in one row of column 2 reaches every row of column 2 and no
        other column."""
        torch.manual_seed(0)
        context = ColumnContext(8, 3).eval()
        features = torch.rand(1, 8, 3, 4)
        changed = features.clone()
        changed[0, :, 0, 2] += 5
        with torch.no_grad():
            difference = (context(features) - context(changed))[0].abs().amax(0)
        self.assertGreater(float(difference[2, 2]), 1e-3)
        self.assertEqual(float(difference[:, [0, 1, 3]].max()), 0.0)
        self.assertEqual(tuple(context(features).shape), (1, 8, 3, 4))


class WidthMultiplierTest(unittest.TestCase):
    def test_hand_worked_widths(self):
        # 16 x 1.25 = 20 = 2.5 eights -> 3 eights (halves round up); 24 x 1.25 = 30 -> 3.75 -> 4 eights;
        # 160 x 1.25 = 200 exactly; 16 x 0.25 = 4 -> 0.5 -> 1 eight; 8 x 0.1 -> never below 8
        self.assertEqual([scaled_channels(c, 1.25) for c in (16, 24, 160)], [24, 32, 200])
        self.assertEqual([scaled_channels(16, 0.25), scaled_channels(8, 0.1), scaled_channels(96, 1.0)], [8, 8, 96])

    def test_widened_net_runs_and_grows(self):
        net = DepthNet(HEIGHT, WIDTH, column_context=True, width_multiplier=1.25).eval()
        with torch.no_grad():
            output = net(torch.rand(2, 3, HEIGHT, WIDTH))
        self.assertEqual(tuple(output.shape), (2, 2, HEIGHT, WIDTH))
        self.assertEqual(net.stem[0].out_channels, 24)
        self.assertGreater(count_parameters(net), count_parameters(DepthNet(HEIGHT, WIDTH, column_context=True)))

    def test_deep_blocks_join_the_two_coarsest_stages(self):
        plain, deep = DepthNet(HEIGHT, WIDTH), DepthNet(HEIGHT, WIDTH, deep_blocks=2)
        self.assertEqual([len(stage) for stage in plain.stages], [1, 2, 3, 5, 3])
        self.assertEqual([len(stage) for stage in deep.stages], [1, 2, 3, 7, 5])
        with torch.no_grad():
            self.assertEqual(tuple(deep.eval()(torch.rand(1, 3, HEIGHT, WIDTH)).shape), (1, 2, HEIGHT, WIDTH))
        for bad in (-1, 1.5):
            with self.assertRaisesRegex(ValueError, "whole number of deep blocks"):
                DepthNet(HEIGHT, WIDTH, deep_blocks=bad)

    def test_bad_multiplier(self):
        for multiplier in (0.0, -1.0, float("nan")):
            with self.assertRaisesRegex(ValueError, "positive width multiplier"):
                DepthNet(HEIGHT, WIDTH, width_multiplier=multiplier)


class InputScaleTest(unittest.TestCase):
    def test_reads_twice_the_size_and_outputs_the_same(self):
        net = DepthNet(HEIGHT, WIDTH, input_scale=2).eval()
        self.assertEqual((net.input_width, net.input_height), (2 * WIDTH, 2 * HEIGHT))
        with torch.no_grad():
            self.assertEqual(tuple(net(torch.rand(1, 3, 2 * HEIGHT, 2 * WIDTH)).shape), (1, 2, HEIGHT, WIDTH))
        # The stem's conv reads the input stem's 8 features and 2 coordinates instead of RGB and 2.
        self.assertEqual((net.input_stem.conv[0].in_channels, net.stem[0].in_channels), (5, 10))
        # The last decoder stage's depthwise conv sees the upsampled 24 channels and the 8 of the skip.
        self.assertEqual(net.decoder[-1].conv[0][0].in_channels, 24 + 8)
        with self.assertRaisesRegex(ValueError, "input scale among"):
            DepthNet(HEIGHT, WIDTH, input_scale=3)


class FrameSizeTest(unittest.TestCase):
    def data(self):
        # Two frames of 4 x 2: colour rising along each row, depth its column index + 1 (the
        # second frame's first pixel sky).
        rgb = np.stack([np.tile(np.arange(0, 80, 20, dtype=np.uint8)[None, :, None], (2, 1, 3))] * 2)
        depth = np.tile(np.arange(1, 5, dtype=np.float32), (2, 2, 1))
        depth[1, 0, 0] = np.nan
        meta = {"width": 4, "height": 2, "fx": 2.0, "fy": 2.0, "cx": 2.0, "cy": 1.0}
        return {"rgb": rgb, "depth": depth, "map": np.array(["a", "b"]), "meta": meta}

    def test_hand_worked_halving(self):
        out = resize_frames(self.data(), (2, 1), 1)
        # Colour: each 2 x 2 block's mean, (0 + 20) / 2 = 10 and (40 + 60) / 2 = 50.
        self.assertEqual(out["rgb"][0, :, :, 0].tolist(), [[10, 50]])
        # Depth: the block's first pixel (columns 0 and 2), sky kept as sky.
        self.assertEqual(out["depth"][0].tolist(), [[1.0, 3.0]])
        self.assertTrue(np.isnan(out["depth"][1, 0, 0]))
        self.assertEqual({key: out["meta"][key] for key in ("width", "height", "fx", "fy", "cx", "cy")},
                         {"width": 2, "height": 1, "fx": 1.0, "fy": 1.0, "cx": 1.0, "cy": 0.5})
        self.assertEqual(out["map"].tolist(), ["a", "b"])

    def test_input_scale_keeps_the_colour(self):
        data = self.data()
        out = resize_frames(data, (2, 1), 2)
        self.assertIs(out["rgb"], data["rgb"])
        self.assertEqual(out["depth"].shape, (2, 1, 2))
        self.assertIs(resize_frames(data, (4, 2), 1), data)

    def test_refused_sizes(self):
        with self.assertRaisesRegex(ValueError, "the val shards are 4x2: too small for a net input of 8x4"):
            resize_frames(self.data(), (4, 2), 2, "the val shards")
        with self.assertRaisesRegex(ValueError, "an output of 2x2 has another aspect ratio"):
            resize_frames(self.data(), (2, 2), 1)

    def test_parse_size(self):
        self.assertEqual(parse_size("128x96"), (128, 96))
        for bad in ("128", "ax96", "0x96", "128x96x3"):
            with self.assertRaisesRegex(ValueError, "size '%s'" % bad):
                parse_size(bad)


class PackPartsTest(unittest.TestCase):
    def test_hand_worked_first_fit_decreasing(self):
        # largest first into the first bin with room, limit 10: 7 -> A; 5 -> B; 4 -> B (9);
        # 3 -> A (10); 2 fits neither (12, 11) -> C
        self.assertEqual(pack_parts.first_fit_decreasing([5, 7, 3, 2, 4], 10), [[1, 2], [0, 4], [3]])
        with self.assertRaisesRegex(ValueError, "exceeds the limit"):
            pack_parts.first_fit_decreasing([11], 10)

    def test_parts_hold_every_frame_once_under_the_limit(self):
        root = os.path.join(WORK, "pack")
        for name, shard in (("train_x", TRAIN_SHARD), ("eval", VAL_SHARD)):
            os.makedirs(os.path.join(root, name), exist_ok=True)
            shutil.copy(shard, os.path.join(root, name))
        # A third of the limit is 0.4 of the training shard: it is cut into 3 pieces.
        limit_mib = 1.2 * os.path.getsize(TRAIN_SHARD) / 2 ** 20
        out = os.path.join(root, "parts")
        self.assertEqual(pack_parts.main([os.path.join(root, "train_x"), os.path.join(root, "eval"),
                                          "--limit-mib", repr(limit_mib), "--out", out]), 0)
        parts = sorted(glob.glob(os.path.join(out, "p[0-9][0-9]")))
        self.assertGreaterEqual(len(parts), 2)
        for part in parts:
            size = sum(os.path.getsize(f) for f in glob.glob(os.path.join(part, "*", "*.zip")))
            self.assertLessEqual(size, limit_mib * 2 ** 20)
        train = sorted(glob.glob(os.path.join(out, "p[0-9][0-9]", "train_x", "*.zip")))
        self.assertEqual(len(train), 3)
        frames = load_shards(train)
        self.assertEqual(sorted(zip(frames["sequence"], frames["step"])),
                         sorted(zip(load_shards([TRAIN_SHARD])["sequence"], load_shards([TRAIN_SHARD])["step"])))
        self.assertEqual(len(load_shards(glob.glob(os.path.join(out, "p[0-9][0-9]", "eval", "*.zip")))["kind"]), 8)
        self.assertFalse(os.path.exists(os.path.join(out, "pieces")))  # the links keep the cut shards' bytes

    def test_hand_worked_part_limit(self):
        # a 40 MiB tree: 64 - 40 - 4 = 20 MiB a part
        self.assertEqual(pack_parts.part_limit_mib(40 * 2 ** 20), 20.0)

    def test_default_limit_leaves_room_for_the_tree(self):
        tree = pack_parts.tracked_bytes(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
        self.assertGreater(tree, 0)
        self.assertAlmostEqual(pack_parts.part_limit_mib(tree) + tree / 2 ** 20, 60.0)

    def test_bad_limit(self):
        with self.assertRaisesRegex(SystemExit, "must be positive"):
            pack_parts.main([os.path.join(WORK, "train_x"), "--limit-mib", "0", "--out", os.path.join(WORK, "bad")])

    def test_bad_folders(self):
        with self.assertRaisesRegex(SystemExit, "train_\\* or eval"):
            pack_parts.main([WORK, "--limit-mib", "1", "--out", os.path.join(WORK, "bad")])
        with self.assertRaisesRegex(SystemExit, "is not a folder"):
            pack_parts.main([os.path.join(WORK, "train_missing"), "--limit-mib", "1", "--out", os.path.join(WORK, "bad")])


class ErrorByDepthTest(unittest.TestCase):
    def test_hand_worked_groups(self):
        # floor plane at 2 m under every pixel but the last (at the horizon: 80 m, no floor)
        floor_depth = np.array([[[2.0, 2.0, 2.0, 2.0, 2.0, 80.0]]])
        depth = np.array([[[2.0, 1.0, 5.0, np.nan, 30.0, 80.0]]])
        groups = error_by_depth.pixel_groups(depth, floor_depth)
        self.assertEqual(groups.tolist(), [[[0, 1, 2, -1, 4, 4]]])
        pred = np.array([[[2.0, 3.0, 5.0, 1.0, 15.0, 80.0]]])
        result = error_by_depth.summarize_groups(pred, np.zeros_like(pred), depth, groups)
        # AbsRel: 0, |3-1|/1 = 2, 0, (sky), |15-30|/30 = 0.5, 0: sum 2.5 over 5 pixels
        self.assertAlmostEqual(result["abs_rel"], 0.5)
        near = result["groups"]["other 0-3 m"]
        self.assertEqual((near["pixel_share"], near["abs_rel"], near["over_twice_too_far"]), (0.2, 2.0, 1.0))
        self.assertAlmostEqual(near["abs_rel_share"], 0.8)
        self.assertAlmostEqual(result["groups"]["other 20-inf m"]["abs_rel"], 0.25)
        self.assertIsNone(result["groups"]["other 8-20 m"])

    def test_missing_shard(self):
        with self.assertRaises(SystemExit) as caught:
            error_by_depth.main(["model.onnx", os.path.join(WORK, "absent.zip")])
        self.assertIn("absent.zip: no such shard", caught.exception.code)


class WeightAverageTest(unittest.TestCase):
    def test_hand_worked_average(self):
        model = torch.nn.Sequential(torch.nn.Linear(1, 1, bias=False), torch.nn.BatchNorm1d(1))
        with torch.no_grad():
            model[0].weight.fill_(0.0)
        average = WeightAverage(model, 0.9)
        with torch.no_grad():
            model[0].weight.fill_(1.0)
        model[1].num_batches_tracked.fill_(7)
        average.update(model)    # step 0: decay min(0.9, 1/10) = 0.1: 0.1 * 0 + 0.9 * 1 = 0.9
        self.assertAlmostEqual(float(average.model[0].weight), 0.9, places=6)
        self.assertEqual(int(average.model[1].num_batches_tracked), 7)
        average.update(model)    # step 1: decay min(0.9, 2/11) = 0.181818: 0.181818 * 0.9 + 0.818182 = 0.981818
        self.assertAlmostEqual(float(average.model[0].weight), 0.981818, places=5)
        for _ in range(200):     # the decay reaches 0.9 and the average the weight
            average.update(model)
        self.assertAlmostEqual(float(average.model[0].weight), 1.0, places=5)
        self.assertEqual(float(model[0].weight), 1.0)  # the trained model is untouched

    def test_bad_decay(self):
        with self.assertRaises(ValueError) as caught:
            WeightAverage(torch.nn.Linear(1, 1), 1.0)
        self.assertIn("--ema must be between 0 and 1, got 1.0", str(caught.exception))


class FloorPriorTest(unittest.TestCase):
    def test_hand_worked_rows(self):
        prior = torch.exp(floor_log_depth(HEIGHT, WIDTH, CAMERA, 80.0))
        self.assertEqual(tuple(prior.shape), (HEIGHT, WIDTH))
        # eye_height_m * fy = 1.5625 * 64 = 100, cy = 47.5:
        expected = {95: 100 / 47.5,     # 2.105263 m, the bottom row
                    57: 100 / 9.5,      # 10.526316 m
                    49: 100 / 1.5,      # 66.666667 m
                    48: 80.0,           # 100 / 0.5 = 200 m is beyond far
                    47: 80.0, 0: 80.0}  # at and above the horizon
        for row, depth in expected.items():
            self.assertAlmostEqual(float(prior[row, 0]), depth, places=4, msg="row %d" % row)
            self.assertEqual(float(prior[row].min()), float(prior[row].max()), "row %d is not constant" % row)

    def test_bad_camera(self):
        with self.assertRaises(ValueError) as caught:
            floor_log_depth(HEIGHT, WIDTH, {"fy": 64.0, "cy": 47.5}, 80.0)
        self.assertIn("lacks eye_height_m", str(caught.exception))
        with self.assertRaises(ValueError) as caught:
            floor_log_depth(HEIGHT, WIDTH, dict(CAMERA, fy=0.0), 80.0)
        self.assertIn("fy 0.0", str(caught.exception))

    def test_untrained_net_predicts_the_floor(self):
        """The depth head starts at zero, so a floor-relative net predicts every
        floor pixel's depth (under 80 m) before any training."""
        rgb, depth = synthetic_frame(np.random.default_rng(3))
        model = DepthNet(HEIGHT, WIDTH, CAMERA).eval()
        with torch.no_grad():
            predicted = torch.exp(model(train_depth.as_input(torch.from_numpy(rgb[None])))[0, 0]).numpy()
        rows = np.arange(HEIGHT)[:, None] - CAMERA["cy"]
        with np.errstate(divide="ignore"):
            floor = np.broadcast_to(np.where(rows > 0, EYE_HEIGHT_M * CAMERA["fy"] / rows, np.inf), depth.shape)
        on_floor = np.isclose(depth, floor, rtol=1e-5) & (floor < 80)
        self.assertGreater(on_floor.sum(), 1000)
        self.assertLess(np.abs(predicted[on_floor] / floor[on_floor] - 1).max(), 1e-5)


class ShardTest(unittest.TestCase):
    def test_round_trip(self):
        data = load_shards([TRAIN_SHARD, VAL_SHARD])
        self.assertEqual(data["rgb"].shape, (32, HEIGHT, WIDTH, 3))
        self.assertEqual(data["rgb"].dtype, np.uint8)
        self.assertEqual(data["depth"].dtype, np.float32)
        self.assertEqual(data["meta"]["maps"], [TRAIN_MAP, VAL_MAP])
        self.assertEqual(data["kind"][:3].tolist(), ["rollout", "rotate", "walk"])
        self.assertEqual(data["key"][:2].tolist(), ["", "l"])
        rng = np.random.default_rng(1)
        rgb, depth = synthetic_frame(rng)
        self.assertTrue(np.array_equal(np.isnan(data["depth"][0]), np.isnan(depth)))
        known = ~np.isnan(depth)
        self.assertLess(np.abs(np.log(data["depth"][0][known] / depth[known])).max(), 1e-4)
        # JPEG blurs the sharp synthetic edges; swapped red and blue would be ~45 off.
        self.assertLess(np.abs(data["rgb"][0].astype(int) - rgb).mean(), 8)

    def assert_rejected(self, changes, *words):
        bad = os.path.join(WORK, "bad.zip")
        rewrite_zip(VAL_SHARD, bad, changes)
        with self.assertRaises(ValueError) as caught:
            load_shards([bad])
        for word in (bad,) + words:
            self.assertIn(word, str(caught.exception))

    def test_missing_entry(self):
        self.assert_rejected({"depth/000003.png": None}, "missing entry depth/000003.png")

    def test_unknown_format(self):
        meta = json.loads(zipfile.ZipFile(VAL_SHARD).read("meta.json"))
        meta["format"] = "valerant-dataset-0"
        self.assert_rejected({"meta.json": json.dumps(meta)}, "unknown format", "valerant-dataset-0")

    def test_wrong_size(self):
        meta = json.loads(zipfile.ZipFile(VAL_SHARD).read("meta.json"))
        meta["width"] = 64
        self.assert_rejected({"meta.json": json.dumps(meta)}, "rgb/000000.jpg", "128x96", "64x96")

    def test_eight_bit_depth(self):
        png = cv2.imencode(".png", np.zeros((HEIGHT, WIDTH), np.uint8))[1].tobytes()
        self.assert_rejected({"depth/000002.png": png}, "depth/000002.png", "16-bit")

    def test_bad_header_and_unknown_kind(self):
        csv_text = zipfile.ZipFile(VAL_SHARD).read("frames.csv").decode()
        self.assert_rejected({"frames.csv": csv_text.replace("yaw_deg", "yaw")}, "header")
        self.assert_rejected({"frames.csv": csv_text.replace("rotate", "spin", 1)}, "line 3", "unknown kind 'spin'")

    def test_not_a_shard(self):
        for path, words in ((os.path.join(WORK, "absent.zip"), "no such shard"),
                            (os.path.join(HERE, "smoke_test.py"), "not a zip file")):
            with self.assertRaises(ValueError) as caught:
                load_shards([path])
            self.assertIn(path, str(caught.exception))
            self.assertIn(words, str(caught.exception))


class TrainDepthTest(unittest.TestCase):
    def run_main_expecting_error(self, argv):
        with self.assertRaises(SystemExit) as caught:
            train_depth.main(argv + ["--out", os.path.join(WORK, "never"), "--steps", "1"])
        self.assertIsInstance(caught.exception.code, str)
        return caught.exception.code

    def test_rejects_missing_shard(self):
        message = self.run_main_expecting_error(["--train", os.path.join(WORK, "nope*.zip"), "--val", VAL_SHARD])
        self.assertIn("no such shard", message)

    def test_rejects_val_maps_in_train(self):
        message = self.run_main_expecting_error(["--train", TRAIN_SHARD, "--val", VAL_SHARD, TRAIN_SHARD])
        self.assertIn("val maps overlap train maps: " + TRAIN_MAP, message)

    def test_rejects_select_maps_not_in_train(self):
        message = self.run_main_expecting_error(["--train", TRAIN_SHARD, "--val", VAL_SHARD,
                                                 "--select-maps", "synth_nowhere"])
        self.assertIn("--select-maps synth_nowhere: not in the training shards", message)
        message = self.run_main_expecting_error(["--train", TRAIN_SHARD, "--val", VAL_SHARD,
                                                 "--select-maps", TRAIN_MAP])
        self.assertIn("nothing is left to train on", message)

    def test_rejects_bad_net_and_loss_options(self):
        for option, value in (("--gradient-weight", "-0.5"), ("--gradient-weight", "nan"), ("--deep-blocks", "-1")):
            with self.assertRaises(SystemExit) as caught, contextlib.redirect_stderr(io.StringIO()) as stderr:
                train_depth.parse_args(["--train", TRAIN_SHARD, "--val", VAL_SHARD, "--out", WORK, "--steps", "1",
                                        option, value])
            self.assertEqual(caught.exception.code, 2)
            self.assertIn(option + " must be at least 0", stderr.getvalue())

    def test_end_to_end_on_cpu(self):
        metrics = self.train_and_check("run", [])
        self.assertEqual((metrics["picked_by"], metrics["loss"], metrics["select"]), ("val", "laplace", None))
        self.assertEqual((metrics["keep"], metrics["kept_step"]), ("best", metrics["best_step"]))

    def test_end_to_end_decoupled_with_context_and_selection(self):
        metrics = self.train_and_check("run_v6", ["--loss", "decoupled", "--global-context", "--ema", "0.9",
                                                  "--select-maps", SELECT_MAP], [SELECT_SHARD])
        self.assertEqual(metrics["ema"], 0.9)
        self.assertEqual((metrics["picked_by"], metrics["loss"], metrics["global_context"]),
                         ("select", "decoupled", True))
        self.assertEqual((metrics["select_frames"], metrics["select_maps"]), (6, [SELECT_MAP]))
        self.assertEqual(list(metrics["select"]["per_map"]), [SELECT_MAP])
        self.assertIn("scaled_error", metrics["val"]["all"])

    def test_end_to_end_column_context(self):
        metrics = self.train_and_check("run_v7", ["--loss", "decoupled", "--column-context", "--ema", "0.9",
                                                  "--select-maps", SELECT_MAP, "--width-multiplier", "1.25",
                                                  "--deep-blocks", "1", "--gradient-weight", "0.5"],
                                       [SELECT_SHARD])
        self.assertEqual((metrics["column_context"], metrics["global_context"]), (True, False))
        self.assertEqual((metrics["width_multiplier"], metrics["deep_blocks"], metrics["gradient_weight"]),
                         (1.25, 1, 0.5))
        self.assertEqual(metrics["parameters"],
                         count_parameters(DepthNet(HEIGHT, WIDTH, column_context=True, width_multiplier=1.25,
                                                   deep_blocks=1)))

    def test_end_to_end_keep_last(self):
        # The end's averaged weights are kept though the selection's best may lie earlier.
        metrics = self.train_and_check("run_v8", ["--loss", "decoupled", "--ema", "0.9", "--keep", "last",
                                                  "--select-maps", SELECT_MAP], [SELECT_SHARD])
        self.assertEqual((metrics["keep"], metrics["kept_step"], metrics["steps"]), ("last", 5, 5))
        self.assertIn(metrics["best_step"], (3, 5))

    def test_end_to_end_input_scale_2(self):
        # 256 x 192 shards: the net reads them as they are and outputs 128 x 96.
        metrics = self.train_and_check("run_x2", ["--input-scale", "2", "--column-context"],
                                       train=TRAIN_SHARD_X2, val=VAL_SHARD_X2)
        self.assertEqual((metrics["input_width"], metrics["input_height"], metrics["output_width"],
                          metrics["output_height"], metrics["input_scale"]), (256, 192, 128, 96, 2))
        self.assertEqual(metrics["parameters"],
                         count_parameters(DepthNet(HEIGHT, WIDTH, column_context=True, input_scale=2)))

    def test_end_to_end_shards_read_smaller(self):
        # The same 256 x 192 shards read by a net of 128 x 96 in and out.
        metrics = self.train_and_check("run_x2_small", ["--output-size", "128x96"],
                                       train=TRAIN_SHARD_X2, val=VAL_SHARD_X2)
        self.assertEqual((metrics["input_width"], metrics["output_width"], metrics["input_scale"]), (128, 128, 1))

    def test_end_to_end_floor_relative(self):
        metrics = self.train_and_check("run_floor", ["--floor-prior"])
        self.assertEqual(metrics["floor_prior"], {key: CAMERA[key] for key in ("fy", "cy", "eye_height_m")})

    def train_and_check(self, name, options, extra_train=(), train=None, val=None):
        """Trains 5 steps on the CPU with options (on train, TRAIN_SHARD by default,
        and extra_train; validated on val, VAL_SHARD by default); checks the outputs
        and the ONNX against torch; returns metrics.json."""
        train, val = train or TRAIN_SHARD, val or VAL_SHARD
        out = os.path.join(WORK, name)
        env = dict(os.environ, OMP_NUM_THREADS="1", OPENCV_FOR_THREADS_NUM="1")
        command = [sys.executable, os.path.join(HERE, "train_depth.py"), "--train", train, *extra_train,
                   "--val", val, "--out", out, "--steps", "5", "--batch", "4", "--eval-every", "3",
                   "--device", "cpu", "--workers", "1"] + options
        run = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             universal_newlines=True, timeout=120)
        self.assertEqual(run.returncode, 0, run.stdout)
        for name in ("log.csv", "depth_prior.pt", "depth_prior.onnx", "metrics.json", "curves.png", "samples.png"):
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        for key in ("val", "train_subset", "parameters", "flops_per_frame", "train_seconds", "device",
                    "torch_version", "seed", "command_line", "train_frames", "val_frames", "train_maps",
                    "val_maps", "onnx_sha256", "floor_prior"):
            self.assertIn(key, metrics)
        self.assertEqual(set(metrics["val"]), {"all", "rotate", "per_map"})
        self.assertEqual(metrics["val"]["all"]["frames"], 8)
        self.assertEqual(list(metrics["val"]["per_map"]), [VAL_MAP])
        self.assertEqual((metrics["train_frames"], metrics["train_maps"]), (24, [TRAIN_MAP]))
        with open(os.path.join(out, "log.csv")) as handle:
            self.assertEqual([line.split(",")[0] for line in handle.read().split()], ["step", "3", "5"])
        # The exported file must run in cv2.dnn and agree with the saved torch weights.
        checkpoint = torch.load(os.path.join(out, "depth_prior.pt"))
        self.assertEqual((checkpoint["keep"], checkpoint["step"]), (metrics["keep"], metrics["kept_step"]))
        exported = onnx.load(os.path.join(out, "depth_prior.onnx"))
        properties = {entry.key: entry.value for entry in exported.metadata_props}
        self.assertEqual((properties["keep"], properties["kept_step"]), (metrics["keep"], str(metrics["kept_step"])))
        model = DepthNet(checkpoint["height"], checkpoint["width"], checkpoint["floor_prior"],
                         checkpoint["global_context"], checkpoint["column_context"], checkpoint["width_multiplier"],
                         checkpoint["deep_blocks"], checkpoint["input_scale"])
        model.load_state_dict(checkpoint["state_dict"])
        rgb = load_shards([val])["rgb"][:3]
        rgb = np.stack([cv2.resize(image, (model.input_width, model.input_height), interpolation=cv2.INTER_AREA)
                        for image in rgb])
        rgb = train_depth.as_input(torch.from_numpy(rgb)).contiguous().numpy()
        report = verify_with_opencv(os.path.join(out, "depth_prior.onnx"), model, rgb)
        self.assertLess(report["max_abs_diff_log_depth"], 1e-3)
        return metrics


if __name__ == "__main__":
    sys.exit(run_smoke_test(sys.modules[__name__], "learn_smoke_test"))
