#!/usr/bin/env python3
"""CPU smoke test of the world model's training code (one core, about a minute).

Unit tests of the hand-checkable parts (motion from poses, sequence splitting, the
warp, PSNR/SSIM, the horizon table, the discriminator's hinge losses) and end-to-end
runs of train_world_model.py on tiny synthetic shards of a panorama seen through a
turning camera, whose ONNX output must load in cv2.dnn and match torch: the warps,
--adversarial-weight, and --init from an earlier run's weights (and its refusals).

  smoke_test_world_model.py [--xml PATH]   # PATH: JUnit XML for scripts/count_test_results"""
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest
from copy import deepcopy

import cv2
import numpy as np
import onnx
import torch

import train_world_model
from split_shard import cut_points, split_shard
from valerant_learn.junit import run_smoke_test
from valerant_learn.shards import load_shards, write_shard
from valerant_learn.training import sha256
from valerant_learn.world_data import WorldWindows, motion_between, split_sequences, wrap_degrees
from valerant_learn.world_discriminator import Adversary, PatchDiscriminator, discriminator_loss, generator_loss, \
    patch_weights
from valerant_learn.world_metrics import horizon_table, psnr, ssim
from valerant_learn.prior_depth import prior_depths
from valerant_learn.pose_warp import PoseGeometry, advance_pose, depth_in_camera, pose_sampling, relative_transform
from valerant_learn.world_net import WorldNet, apply_warp, carry_seen, input_name, rollout
from valerant_learn.world_warp import AnchorState, anchor_step, pixel_grid, rotation_sampling

HERE = os.path.dirname(os.path.abspath(__file__))
WIDTH, HEIGHT = 128, 96
CAMERA = {"fx": 64.0, "fy": 64.0, "cx": 63.5, "cy": 47.5, "depth_min_m": 0.05, "depth_max_m": 200.0,
          "seed": 0, "units_per_metre": 32, "eye_height_m": 1.5625}
TRAIN_MAP, VAL_MAP = "synth_train", "synth_val"
# One pixel of panorama a frame: the camera turns by a fixed step.
TURN_DEG_PER_FRAME = 1.6


def panorama_shard(path, map_name, sequences, length, seed):
    """Sequences of a camera turning left over a random panorama: frame t is the
    window starting t pixels further left (so each frame shifts the image right by
    one pixel), yaw up TURN_DEG_PER_FRAME a frame; the last sequence also walks."""
    rng = np.random.default_rng(seed)
    frames, rgbs = [], []
    for s in range(sequences):
        panorama = cv2.resize(rng.integers(0, 255, (12, 40, 3), dtype=np.uint8), (WIDTH + length + 1, HEIGHT),
                              interpolation=cv2.INTER_LINEAR)
        for t in range(length):
            left = length - t
            rgbs.append(panorama[:, left:left + WIDTH])
            frames.append({"map": map_name, "spawn": 0, "sequence": s, "step": t,
                           "kind": "rollout" if s == 0 else "walk", "key": "" if t == 0 else "j",
                           "x": 0.1 * t * (s == sequences - 1), "y": 0.0, "z": 1.5625,
                           "yaw_deg": TURN_DEG_PER_FRAME * t, "pitch_deg": 0.0, "in_solid": 0})
    depth = np.full((len(rgbs), HEIGHT, WIDTH), 5.0, dtype=np.float32)
    write_shard(path, np.stack(rgbs), depth, frames, CAMERA)


def setUpModule():
    global WORK, TRAIN_SHARD, VAL_SHARD
    WORK = tempfile.mkdtemp(prefix="valerant_wm_smoke_")
    TRAIN_SHARD = os.path.join(WORK, "train.zip")
    VAL_SHARD = os.path.join(WORK, "val.zip")
    panorama_shard(TRAIN_SHARD, TRAIN_MAP, 3, 12, seed=1)
    panorama_shard(VAL_SHARD, VAL_MAP, 2, 10, seed=2)


def tearDownModule():
    shutil.rmtree(WORK, ignore_errors=True)


class MotionTest(unittest.TestCase):
    def test_wrap(self):
        self.assertEqual(float(wrap_degrees(350.0 - 10.0)), -20.0)
        self.assertEqual(float(wrap_degrees(10.0 - 350.0)), 20.0)
        self.assertEqual(float(wrap_degrees(-180.0)), 180.0)

    def test_motion_between_poses(self):
        # Turn 90 deg left, then 1 m along +x: the new heading is +y, whose right is
        # +x, so the 32 units are a strafe to the right.
        motion = motion_between({"x": 0.0, "y": 0.0, "yaw_deg": 0.0, "pitch_deg": 0.0},
                                {"x": 1.0, "y": 0.0, "yaw_deg": 90.0, "pitch_deg": 2.0})
        np.testing.assert_allclose(motion, [0.0, 32.0, 90.0, 2.0], atol=1e-5)
        # Heading 180 deg, 0.5 m along -x: 16 units forward, across the 359 -> 179 wrap.
        motion = motion_between({"x": 0.0, "y": 0.0, "yaw_deg": 359.0, "pitch_deg": 0.0},
                                {"x": -0.5, "y": 0.0, "yaw_deg": 180.0, "pitch_deg": 0.0})
        np.testing.assert_allclose(motion, [16.0 * np.cos(np.radians(0.0)), 0.0, -179.0, 0.0], atol=1e-4)

    def test_split_sequences_breaks_at_gaps_and_maps(self):
        frames = {"map": np.array(["a", "a", "a", "a", "b", "b"]), "sequence": np.array([0, 0, 0, 1, 1, 1]),
                  "step": np.array([0, 1, 3, 0, 0, 1])}
        self.assertEqual([list(run) for run in split_sequences(frames)], [[0, 1], [2], [3], [4, 5]])

    def test_window_pads_context_with_the_first_frame(self):
        rgb = np.arange(5, dtype=np.uint8)[:, None, None, None] * np.ones((1, 2, 2, 3), np.uint8)
        frames = {"map": np.array(["a"] * 5), "sequence": np.zeros(5, int), "step": np.arange(5),
                  "kind": np.array(["walk"] * 5), "x": np.zeros(5), "y": np.zeros(5),
                  "yaw_deg": np.arange(5) * 2.0, "pitch_deg": np.zeros(5)}
        windows = WorldWindows(rgb, frames, context=3)
        context, targets, motions = windows.window(0, 1, 2)
        self.assertEqual([int(f[0, 0, 0]) for f in context], [0, 0, 1])
        self.assertEqual([int(f[0, 0, 0]) for f in targets], [2, 3])
        np.testing.assert_allclose(motions[:, 2], [2.0, 2.0])
        self.assertEqual(len(windows.starts(2)), 3)


class WarpTest(unittest.TestCase):
    def test_flow_one_pixel_right_samples_the_next_column(self):
        last = torch.arange(12, dtype=torch.float32).view(1, 1, 3, 4).expand(1, 3, 3, 4) / 20
        out = torch.zeros(1, 6, 3, 4)
        out[:, 0] = 1.0  # dx = 1: pixel x shows last(x + 1)
        out[:, 2] = 1.0  # mask: all warp
        warped = apply_warp(last, out)
        expected = torch.tensor([[1, 2, 3, 3], [5, 6, 7, 7], [9, 10, 11, 11]], dtype=torch.float32) / 20
        torch.testing.assert_close(warped[0, 0], expected)

    def test_mask_zero_gives_the_fill(self):
        last = torch.rand(1, 3, 4, 5)
        out = torch.zeros(1, 6, 4, 5)
        out[:, 3:6] = 0.25
        torch.testing.assert_close(apply_warp(last, out), torch.full((1, 3, 4, 5), 0.25))

    def test_half_pixel_flow_interpolates(self):
        last = torch.tensor([0.0, 1.0]).view(1, 1, 1, 2).expand(1, 3, 2, 2)
        out = torch.zeros(1, 6, 2, 2)
        out[:, 0] = 0.5
        out[:, 2] = 1.0
        torch.testing.assert_close(apply_warp(last, out)[0, 0, 0], torch.tensor([0.5, 1.0]))


class RotationAnchorWarpTest(unittest.TestCase):
    # 90 deg field of view at 128 x 96, principal point at the image centre (corner convention).
    CAMERA = {"fx": 64.0, "fy": 64.0, "cx": 64.0, "cy": 48.0}

    def test_no_rotation_samples_every_pixel_in_place(self):
        positions, in_view = rotation_sampling(torch.zeros(1, 4), self.CAMERA, 96, 128)
        torch.testing.assert_close(positions[0], pixel_grid(96, 128, "cpu"))
        self.assertEqual(float(in_view.min()), 1.0)

    def test_a_45_degree_left_turn(self):
        # 129 x 97 pixels with the principal point at corner coordinate (64.5, 48.5): pixel
        # (64, 48) is the optical axis and pixel 128's ray has x = (128.5 - 64.5) / 64 = 1.
        # Turning 45 deg left, the new axis is the old ray x = -tan 45 = -1: corner 64.5 - 64,
        # pixel index 0; the new ray x = 1 is the old axis (x2 = cos 45 - sin 45 = 0,
        # z2 = sin 45 + cos 45 = sqrt 2): index 64. Row 0 (y = -48 / 64 = -0.75) at column
        # 128 lands at v = 64 (-0.75) / sqrt 2 + 48 = 48 - 48 / sqrt 2 = 14.059.
        camera = {"fx": 64.0, "fy": 64.0, "cx": 64.5, "cy": 48.5}
        motion = torch.tensor([[0.0, 0.0, 45.0, 0.0]], dtype=torch.float64)
        positions, in_view = rotation_sampling(motion, camera, 97, 129)
        self.assertAlmostEqual(float(positions[0, 0, 48, 64]), 0.0, places=9)
        self.assertAlmostEqual(float(positions[0, 1, 48, 64]), 48.0, places=9)
        self.assertAlmostEqual(float(positions[0, 0, 48, 128]), 64.0, places=9)
        self.assertAlmostEqual(float(positions[0, 1, 0, 128]), 48 - 48 / np.sqrt(2), places=9)
        # Left of the new axis the rays leave the old image.
        self.assertEqual((float(in_view[0, 0, 48, 63]), float(in_view[0, 0, 48, 64])), (0.0, 1.0))

    def test_looking_down_moves_the_picture_up(self):
        # Pitch down by atan(1/64): the centre ray samples one row below the centre.
        motion = torch.tensor([[0.0, 0.0, 0.0, float(np.degrees(np.arctan(1 / 64)))]], dtype=torch.float64)
        positions, _ = rotation_sampling(motion, {"fx": 64.0, "fy": 64.0, "cx": 64.0, "cy": 48.5}, 97, 128)
        self.assertAlmostEqual(float(positions[0, 1, 48, 64]), 49.0, places=9)

    def test_the_anchor_is_sampled_once(self):
        # A row 0 1 0 1 0 1 moved half a pixel twice. Resampling the last frame would give
        # 0.5 and then 0.5; through the coordinates the second frame is the anchor moved by
        # one whole pixel, 1 0 1 0, where the column's coordinates stay valid (columns 0-3;
        # column 4 samples validity 0.5 between a valid and an invalid column, column 5
        # lies outside). Those come from the newest frame: 0.75 and 1 (the border). 4 of 6 valid >= 0.6:
        # no re-anchoring.
        anchor = torch.tensor([0.0, 1.0, 0.0, 1.0, 0.0, 1.0]).view(1, 1, 1, 6).expand(1, 3, 2, 6)
        state = AnchorState.start(anchor)
        shift = pixel_grid(2, 6, "cpu")[None] + torch.tensor([0.5, 0.0]).view(1, 2, 1, 1)
        ones, zeros = torch.ones(1, 1, 2, 6), torch.zeros(1, 3, 2, 6)
        first, state = anchor_step(state, anchor, shift, ones, zeros)
        torch.testing.assert_close(first[0, 0], torch.tensor([[0.5, 0.5, 0.5, 0.5, 0.5, 1.0]] * 2))
        torch.testing.assert_close(state.valid[0, 0], torch.tensor([[1.0, 1.0, 1.0, 1.0, 1.0, 0.0]] * 2))
        second, state = anchor_step(state, first, shift, ones, zeros)
        torch.testing.assert_close(second[0, 0], torch.tensor([[1.0, 0.0, 1.0, 0.0, 0.75, 1.0]] * 2))
        torch.testing.assert_close(state.valid[0, 0], torch.tensor([[1.0, 1.0, 1.0, 1.0, 0.0, 0.0]] * 2))
        self.assertIs(state.anchor, anchor)

    def test_a_filled_frame_becomes_the_anchor(self):
        anchor = torch.rand(1, 3, 4, 5)
        state = AnchorState.start(anchor)
        frame, state = anchor_step(state, anchor, pixel_grid(4, 5, "cpu")[None], torch.zeros(1, 1, 4, 5),
                                   torch.full((1, 3, 4, 5), 0.3))
        torch.testing.assert_close(frame, torch.full((1, 3, 4, 5), 0.3))
        torch.testing.assert_close(state.anchor, frame)
        torch.testing.assert_close(state.coords, pixel_grid(4, 5, "cpu")[None])
        self.assertEqual(float(state.valid.min()), 1.0)


class PoseAnchorWarpTest(unittest.TestCase):
    # 90 deg field of view at 128 x 96, principal point at the image centre (corner
    # convention): pixel index x has the ray x' = (x + 0.5 - 64) / 64, so the optical
    # axis lies at index 63.5, 47.5.
    CAMERA = {"fx": 64.0, "fy": 64.0, "cx": 64.0, "cy": 48.0}
    START = torch.zeros(1, 4, dtype=torch.float64)

    @staticmethod
    def motion(forward=0.0, strafe=0.0, yaw=0.0, pitch=0.0):
        return torch.tensor([[forward, strafe, yaw, pitch]], dtype=torch.float64)

    def test_the_engine_turns_then_moves_along_the_new_heading(self):
        # 90 deg left, then 32 units (1 m) forward: the heading is +y, so the camera ends at
        # (0, 1); then 32 units of strafe to the right of +y, which is +x: (1, 1).
        turned = advance_pose(self.START, self.motion(forward=32.0, yaw=90.0))
        torch.testing.assert_close(turned, torch.tensor([[0.0, 1.0, 90.0, 0.0]], dtype=torch.float64))
        torch.testing.assert_close(advance_pose(turned, self.motion(strafe=32.0)),
                                   torch.tensor([[1.0, 1.0, 90.0, 0.0]], dtype=torch.float64))

    def test_relative_transform(self):
        # A camera 1 m ahead sees at depth 2 what the start camera sees at depth 3; one
        # turned 90 deg left sees straight ahead what lies 1 m to the start camera's left
        # (optical x = -1).
        ahead = torch.tensor([[1.0, 0.0, 0.0, 0.0]], dtype=torch.float64)
        r, t = relative_transform(self.START, ahead)
        torch.testing.assert_close(r[0] @ torch.tensor([0.0, 0.0, 2.0], dtype=torch.float64) + t[0],
                                   torch.tensor([0.0, 0.0, 3.0], dtype=torch.float64))
        left = torch.tensor([[0.0, 0.0, 90.0, 0.0]], dtype=torch.float64)
        r, t = relative_transform(self.START, left)
        torch.testing.assert_close(r[0] @ torch.tensor([0.0, 0.0, 1.0], dtype=torch.float64) + t[0],
                                   torch.tensor([-1.0, 0.0, 0.0], dtype=torch.float64))

    def sampling(self, depth, motion):
        return pose_sampling(depth, self.START, advance_pose(self.START, motion), self.CAMERA)

    def test_a_step_towards_a_wall(self):
        # A wall 2 m ahead, 16 units (0.5 m) forward: the next camera sees it at 1.5 m, so
        # pixel p samples the newest frame at 63.5 + (p - 63.5) * 1.5 / 2 (rows about 47.5):
        # (127, 95) at (111.125, 83.125), every position inside the image.
        wall = torch.full((1, 1, 96, 128), 2.0, dtype=torch.float64)
        positions, in_view = self.sampling(wall, self.motion(forward=16.0))
        torch.testing.assert_close(positions[0, :, 95, 127], torch.tensor([111.125, 83.125], dtype=torch.float64))
        torch.testing.assert_close(positions[0, :, 0, 0], torch.tensor([15.875, 11.875], dtype=torch.float64))
        self.assertEqual(float(in_view.min()), 1.0)

    def test_a_strafe_along_a_wall(self):
        # 8 units (0.25 m) to the right, the wall at 2 m: every pixel samples 64 * 0.25 / 2
        # = 8 pixels to its right, and the last 8 columns leave the newest image.
        wall = torch.full((1, 1, 96, 128), 2.0, dtype=torch.float64)
        positions, in_view = self.sampling(wall, self.motion(strafe=8.0))
        torch.testing.assert_close(positions[0, 0, 10, :3], torch.tensor([8.0, 9.0, 10.0], dtype=torch.float64))
        self.assertEqual((float(in_view[0, 0, 10, 119]), float(in_view[0, 0, 10, 120])), (1.0, 0.0))

    def test_a_turn_then_a_step(self):
        # 129 x 97 pixels, the axis at pixel (64, 48). 20 deg left, then 16 units (0.5 m)
        # along the new heading: the camera at (0.5 cos 20, 0.5 sin 20) = (0.46985, 0.17101)
        # m, its axis (cos 20, sin 20) meets the wall x = 2 m after (2 - 0.46985) / cos 20 =
        # 1.62836 m, at y = 0.17101 + 1.62836 sin 20 = 0.72794 m: in the newest camera 0.72794
        # m to the left at depth 2, so pixel (64, 48) samples u = 64 - 64 * 0.72794 / 2 =
        # 40.7059, v = 48.
        camera = {"fx": 64.0, "fy": 64.0, "cx": 64.5, "cy": 48.5}
        wall = torch.full((1, 1, 97, 129), 2.0, dtype=torch.float64)
        positions, in_view = pose_sampling(wall, self.START, advance_pose(self.START, self.motion(16.0, yaw=20.0)),
                                           camera)
        self.assertAlmostEqual(float(positions[0, 0, 48, 64]), 40.7059, places=4)
        self.assertAlmostEqual(float(positions[0, 1, 48, 64]), 48.0, places=9)
        self.assertEqual(float(in_view[0, 0, 48, 64]), 1.0)

    def test_the_floor_converges_in_three_iterations(self):
        # The floor 1.5625 m below a level camera: row v has depth h fy / (v + 0.5 - 48).
        # 4.5 units (0.140625 m) forward, the next frame's bottom row (a = 95 + 0.5 - 48 =
        # 47.5) sees the floor point whose row u (from the axis) solves u = a (1 - f / Z(u))
        # = a (1 - f u / (h fy)): u = a / (1 + a f / (h fy)) = 47.5 / 1.066796875 = 44.5258,
        # index 92.0258. From the rotation's guess (index 95) the error shrinks by
        # a f / (h fy) = 0.0668 an iteration: 2.97 * 0.0668^3 = 0.0009 px after three.
        rows = torch.arange(96, dtype=torch.float64).view(1, 1, 96, 1).expand(1, 1, 96, 128)
        floor = torch.where(rows > 47, 1.5625 * 64 / (rows + 0.5 - 48).clamp(min=0.5), torch.full_like(rows, 80.0))
        positions, _ = self.sampling(floor, self.motion(forward=4.5))
        self.assertAlmostEqual(float(positions[0, 1, 95, 64]), 47.5 + 47.5 / 1.066796875, delta=0.0015)

    def test_the_turn_alone_is_the_rotation_warp(self):
        depth = 1.0 + 5.0 * torch.rand(1, 1, 96, 128, dtype=torch.float64)
        motion = self.motion(yaw=7.0, pitch=-3.0)
        positions, in_view = self.sampling(depth, motion)
        rotation, rotation_in_view = rotation_sampling(motion, self.CAMERA, 96, 128)
        torch.testing.assert_close(positions, rotation)
        torch.testing.assert_close(in_view, rotation_in_view)

    def test_depth_in_camera_after_a_step(self):
        # Anchor pixel (64, 48) at depth 2 m (ray x' = 0.5 / 64), the camera 0.5 m ahead:
        # depth 1.5 m; a quarter turn left: the point lies 2 m to that camera's right and
        # 0.5 / 64 * 2 = 0.015625 m behind it, its depth clamped to 0.05.
        depth = torch.full((1, 1, 96, 128), 2.0, dtype=torch.float64)
        coords = pixel_grid(96, 128, "cpu", torch.float64)[None]
        ahead = torch.tensor([[0.5, 0.0, 0.0, 0.0]], dtype=torch.float64)
        self.assertAlmostEqual(float(depth_in_camera(depth, coords, self.START, ahead, self.CAMERA)[0, 0, 48, 64]),
                               1.5, places=12)
        turned = torch.tensor([[0.0, 0.0, 90.0, 0.0]], dtype=torch.float64)
        self.assertAlmostEqual(float(depth_in_camera(depth, coords, self.START, turned, self.CAMERA)[0, 0, 48, 64]),
                               0.05, places=12)

    def test_a_filled_frame_becomes_the_anchor_with_its_depth_carried(self):
        # The wall at 2 m, 16 units forward, everything filled: the new anchor is the fill,
        # its pose (0.5, 0), its depth the wall's from there, 1.5 m.
        frame = torch.rand(1, 3, 96, 128, dtype=torch.float64)
        state = AnchorState.start(frame, torch.full((1, 1, 96, 128), 2.0, dtype=torch.float64), self.CAMERA)
        positions, _, moved = state.geometry.sampling(state.coords, self.motion(forward=16.0))
        fill = torch.full_like(frame, 0.3)
        _, state = anchor_step(state, frame, positions, torch.zeros_like(frame[:, :1]), fill, moved)
        torch.testing.assert_close(state.anchor, fill)
        torch.testing.assert_close(state.geometry.anchor_pose, torch.tensor([[0.5, 0.0, 0.0, 0.0]],
                                                                            dtype=torch.float64))
        torch.testing.assert_close(state.geometry.depth, torch.full((1, 1, 96, 128), 1.5, dtype=torch.float64))

    def test_a_missing_depth_is_the_sky(self):
        geometry = PoseGeometry.start(torch.tensor([[[[float("nan"), 0.01]]]]), self.CAMERA)
        torch.testing.assert_close(geometry.depth, torch.tensor([[[[80.0, 0.05]]]]))


class PriorDepthTest(unittest.TestCase):
    def test_threads_give_each_frames_depth(self):
        model = os.path.join(HERE, "..", "models", "depth_prior.onnx")
        rgb = load_shards([TRAIN_SHARD])["rgb"][:3]
        net = cv2.dnn.readNetFromONNX(model)
        net.setInput(cv2.dnn.blobFromImage(rgb[2], 1.0 / 255.0, swapRB=False, crop=False))
        np.testing.assert_allclose(prior_depths(model, rgb, 2)[2], np.exp(net.forward()[0, 0]), rtol=1e-5)


class MetricsTest(unittest.TestCase):
    def test_psnr_of_a_uniform_error(self):
        # Every pixel off by 0.1: MSE 0.01, PSNR 10 log10(1 / 0.01) = 20 dB.
        a = torch.full((1, 3, 16, 16), 0.5)
        self.assertAlmostEqual(float(psnr(a + 0.1, a)[0]), 20.0, places=4)

    def test_ssim_of_equal_and_of_shifted_constant_images(self):
        a = torch.rand(1, 3, 16, 16)
        self.assertAlmostEqual(float(ssim(a, a)[0]), 1.0, places=5)
        # Constant images 0.2 and 0.4: no variance, so SSIM = (2 mu1 mu2 + C1) / (mu1^2 + mu2^2 + C1)
        # = (0.16 + 1e-4) / (0.2 + 1e-4) = 0.80010.
        self.assertAlmostEqual(float(ssim(torch.full((1, 3, 16, 16), 0.2), torch.full((1, 3, 16, 16), 0.4))[0]),
                               0.1601 / 0.2001, places=4)

    def test_horizon_table_counts_long_enough_rollouts(self):
        long, short = torch.rand(97, 3, 16, 16), torch.rand(57, 3, 16, 16)
        table = horizon_table([(long, long, long[0]), (short, short.clone(), short[0])])
        self.assertEqual([table[h]["rollouts"] for h in ("8", "57", "97")], [2, 2, 1])
        self.assertAlmostEqual(table["8"]["model"]["ssim"], 1.0, places=5)
        self.assertAlmostEqual(table["97"]["model"]["psnr"], 100.0, places=3)


class WorldNetTest(unittest.TestCase):
    def test_rollout_shapes_and_initial_mask(self):
        torch.manual_seed(0)
        model = WorldNet(2, 32, 48).eval()
        context = torch.rand(1, 2, 3, 32, 48)
        with torch.no_grad():
            frames = rollout(model, context, torch.zeros(1, 5, 4))
            out = model(torch.cat([context.flatten(1, 2), torch.zeros(1, 4, 32, 48)], 1))
        self.assertEqual(tuple(frames.shape), (1, 5, 3, 32, 48))
        self.assertTrue(0.97 < float(out[:, 2].mean()) < 0.99)

    def test_full_resolution_head(self):
        model = WorldNet(2, 32, 48, full_res_head=True).eval()
        with torch.no_grad():
            frames = rollout(model, torch.rand(1, 2, 3, 32, 48), torch.zeros(1, 3, 4))
        self.assertEqual(tuple(frames.shape), (1, 3, 3, 32, 48))

    def test_rotation_anchor_rollout(self):
        model = WorldNet(2, 32, 48, full_res_head=True, warp="rotation_anchor").eval()
        camera = {"fx": 24.0, "fy": 24.0, "cx": 24.0, "cy": 16.0}
        with torch.no_grad():
            frames = rollout(model, torch.rand(1, 2, 3, 32, 48), torch.tensor([[[0.0, 0.0, 1.6, 0.0]] * 3]), camera)
        self.assertEqual(tuple(frames.shape), (1, 3, 3, 32, 48))

    def test_pose_anchor_rollout(self):
        model = WorldNet(2, 32, 48, full_res_head=True, warp="pose_anchor").eval()
        camera = {"fx": 24.0, "fy": 24.0, "cx": 24.0, "cy": 16.0}
        context, motions = torch.rand(1, 2, 3, 32, 48), torch.tensor([[[4.5, 0.0, 1.6, 0.0]] * 3])
        with torch.no_grad():
            frames = rollout(model, context, motions, camera, torch.full((1, 1, 32, 48), 3.0))
        self.assertEqual(tuple(frames.shape), (1, 3, 3, 32, 48))
        with self.assertRaisesRegex(ValueError, "pose_anchor warp needs the depth"):
            rollout(model, context, motions, camera)
        self.assertEqual(input_name("pose_anchor"), "frames_motion_and_pose_warp")
        self.assertEqual(input_name("rotation_anchor"), "frames_and_motion")

    def test_rejects_a_size_not_a_multiple_of_16(self):
        with self.assertRaises(ValueError):
            WorldNet(4, 90, 128)

    def test_a_left_turn_invents_the_left_edge(self):
        # The head zeroed: flow 0, mask sigmoid(4) = 0.98, so the warp is the rotation's.
        # fx = 24, cx = 24 on 48 columns, a left turn of 10 degrees: pixel x of row 16 (its
        # ray level to 0.02) looks at atan((x + 0.5 - 24) / 24) - 10 degrees in the newest
        # frame, at u = 24 tan(that) + 23.5. x = 7: atan(-16.5 / 24) = -34.51, -44.51 deg,
        # u = -0.099: outside (its left tap is off the image); x = 8: -32.86, -42.86 deg,
        # u = 1.22: inside. The right edge, x = 47, looks at u = 39.9.
        model = WorldNet(2, 32, 48, full_res_head=True, warp="rotation_anchor").eval()
        with torch.no_grad():
            model.head.weight.zero_()
        camera = {"fx": 24.0, "fy": 24.0, "cx": 24.0, "cy": 16.0}
        with torch.no_grad():
            frames, invented = rollout(model, torch.rand(1, 2, 3, 32, 48), torch.tensor([[[0.0, 0.0, 10.0, 0.0]]]),
                                       camera, with_invented=True)
        self.assertEqual(tuple(frames.shape), (1, 1, 3, 32, 48))
        self.assertEqual(tuple(invented.shape), (1, 1, 1, 32, 48))
        self.assertEqual(invented[0, 0, 0, 16].tolist(), [1.0] * 8 + [0.0] * 40)


class CarrySeenTest(unittest.TestCase):
    def test_pixels_looking_off_the_image_or_at_invented_ones_or_filled_are_invented(self):
        # 4 x 6 frames, every pixel looking one pixel to its right: column 5 looks at
        # column 6, off the image; column 1 looks at column 2, which the newest frame
        # had invented; pixel (3, 3) keeps the fill.
        seen = torch.ones(1, 1, 4, 6)
        seen[0, 0, :, 2] = 0.0
        positions = pixel_grid(4, 6, torch.device("cpu"), torch.float32)[None].clone()
        positions[:, 0] += 1.0
        mask = torch.ones(1, 1, 4, 6)
        mask[0, 0, 3, 3] = 0.4  # the fill chosen: invented although it looks at a seen pixel
        expected = torch.tensor([[1.0, 0.0, 1.0, 1.0, 1.0, 0.0]] * 4)
        expected[3, 3] = 0.0
        torch.testing.assert_close(carry_seen(seen, positions, mask)[0, 0], expected)
        # Half a pixel right: column 5 looks at 5.5, one tap off the image (sampled 0.5);
        # column 4 at 4.5 lies between two seen pixels.
        positions[:, 0] -= 0.5
        self.assertEqual(carry_seen(torch.ones(1, 1, 4, 6), positions, torch.ones(1, 1, 4, 6))[0, 0, 0].tolist(),
                         [1.0, 1.0, 1.0, 1.0, 1.0, 0.0])


class SplitShardTest(unittest.TestCase):
    def test_cut_points_fall_between_sequences(self):
        # Sequences start at rows 0, 5, 6, 10 of 12: halves cut at 6 (nearest 6.0).
        self.assertEqual(cut_points([0, 5, 6, 10, 12], 2), [0, 6, 12])
        self.assertEqual(cut_points([0, 5, 6, 10, 12], 4), [0, 5, 6, 10, 12])
        with self.assertRaises(ValueError):
            cut_points([0, 5, 12], 3)

    def test_parts_hold_every_frame_and_whole_sequences(self):
        paths = split_shard(TRAIN_SHARD, 2, os.path.join(WORK, "parts"))
        whole, parts = load_shards([TRAIN_SHARD]), load_shards(paths)
        np.testing.assert_array_equal(whole["rgb"], parts["rgb"])
        np.testing.assert_array_equal(whole["step"], parts["step"])
        self.assertEqual([len(load_shards([p])["index"]) for p in paths], [12, 24])


class GradientDifferenceTest(unittest.TestCase):
    def test_blurred_step_edge(self):
        # True row 0 0 1 1, predicted 0 .25 .75 1: horizontal differences 0 1 0 against
        # .25 .5 .25, |.| = .25 .5 .25, mean 1/3 over the 3 differences of each of the two
        # rows; vertical differences are all 0: the term is 1/3.
        true = torch.tensor([[0.0, 0.0, 1.0, 1.0]] * 2)[None, None]
        predicted = torch.tensor([[0.0, 0.25, 0.75, 1.0]] * 2)[None, None]
        self.assertAlmostEqual(float(train_world_model.gradient_difference(predicted, true)), 1 / 3, places=6)
        self.assertEqual(float(train_world_model.gradient_difference(true, true)), 0.0)

    def test_weighted_by_the_smaller_weight_of_each_pair(self):
        # The same rows, pixel weights 1 1 0.5 0: the three horizontal pairs weigh 1, 0.5
        # and 0, (1 x .25 + .5 x .5) / 1.5 = 1/3 on each row; the vertical pairs' weights
        # are those of their column, over differences that are all 0.
        true = torch.tensor([[0.0, 0.0, 1.0, 1.0]] * 2)[None, None]
        predicted = torch.tensor([[0.0, 0.25, 0.75, 1.0]] * 2)[None, None]
        weights = torch.tensor([[1.0, 1.0, 0.5, 0.0]] * 2)[None, None]
        self.assertAlmostEqual(float(train_world_model.gradient_difference(predicted, true, weights)), 1 / 3, places=6)
        # Weights 0 1 1 1: only the pairs (1, 2) and (2, 3) count, (.5 + .25) / 2.
        weights = torch.tensor([[0.0, 1.0, 1.0, 1.0]] * 2)[None, None]
        self.assertAlmostEqual(float(train_world_model.gradient_difference(predicted, true, weights)), 0.375, places=6)


class ReconstructionWeightsTest(unittest.TestCase):
    def test_weights_of_invented_pixels(self):
        # Invented 0, 1 and 0.5 at an invented weight of 0.25: 1, 0.25 and 1 - 0.75 x 0.5.
        invented = torch.tensor([0.0, 1.0, 0.5]).view(1, 1, 1, 3)
        torch.testing.assert_close(train_world_model.reconstruction_weights(invented, 0.25),
                                   torch.tensor([1.0, 0.25, 0.625]).view(1, 1, 1, 3))

    def test_pixel_weighted_mean_over_channels(self):
        # Channel 0 holds 1 and 3, channel 1 5 and 7; weights 1 and 0: (1 + 5) / 2.
        values = torch.tensor([[[[1.0, 3.0]], [[5.0, 7.0]]]])
        self.assertAlmostEqual(float(train_world_model.pixel_weighted_mean(values, torch.tensor([[[[1.0, 0.0]]]]))),
                               3.0, places=6)

    def test_pixels_of_weight_zero_leave_every_term(self):
        # 11 x 12 frames, two SSIM windows (top left pixels (0, 0) and (0, 1), centres
        # (5, 5) and (5, 6)); true and predicted differ only in column 11, which only the
        # second window holds. Weight 0 on column 11 and on the second window's centre:
        # the L1 and gradient terms see no difference and the SSIM term only the first
        # window, whose frames are equal (index 1): the loss is 0. Unweighted, it is not;
        # weights of 1 everywhere give the unweighted loss.
        predicted = torch.rand(1, 3, 11, 12, generator=torch.Generator().manual_seed(3))
        true = predicted.clone()
        true[..., 11] = 1.0 - true[..., 11]
        weights = torch.ones(1, 1, 11, 12)
        weights[..., 11] = 0.0
        weights[..., 5, 6] = 0.0
        loss, l1 = train_world_model.reconstruction_loss(predicted, true, 1.0, weights)
        self.assertAlmostEqual(float(loss), 0.0, places=6)
        self.assertEqual(float(l1), 0.0)
        plain, _ = train_world_model.reconstruction_loss(predicted, true, 1.0)
        self.assertGreater(float(plain), 0.01)
        ones, _ = train_world_model.reconstruction_loss(predicted, true, 1.0, torch.ones(1, 1, 11, 12))
        self.assertAlmostEqual(float(ones), float(plain), places=6)


class DiscriminatorTest(unittest.TestCase):
    def test_hinge_losses(self):
        # Real logits 0.5 and 2: relu(1 - 0.5) = 0.5, relu(1 - 2) = 0; fake logits -2 and
        # 0: relu(1 - 2) = 0, relu(1 + 0) = 1. Equal weights: means 0.25 + 0.5 = 0.75; the
        # generator's term is the negated mean of the fake logits, 1.
        real, fake = torch.tensor([[[[0.5, 2.0]]]]), torch.tensor([[[[-2.0, 0.0]]]])
        equal = torch.ones(1, 1, 1, 2)
        self.assertAlmostEqual(float(discriminator_loss(real, fake, equal)), 0.75, places=6)
        self.assertAlmostEqual(float(generator_loss(fake, equal)), 1.0, places=6)
        # Weights 0.25 and 0.75 (sum 1): 0.25 * 0.5 + 0.75 * 0 = 0.125 and
        # 0.25 * 0 + 0.75 * 1 = 0.75, 0.875; the generator's -(0.25 * -2 + 0.75 * 0) = 0.5.
        # Weights 1 and 0: only the first patches count, 0.5 + 0 and 2.
        weights = torch.tensor([[[[0.25, 0.75]]]])
        self.assertAlmostEqual(float(discriminator_loss(real, fake, weights)), 0.875, places=6)
        self.assertAlmostEqual(float(generator_loss(fake, weights)), 0.5, places=6)
        first = torch.tensor([[[[1.0, 0.0]]]])
        self.assertAlmostEqual(float(discriminator_loss(real, fake, first)), 0.5, places=6)
        self.assertAlmostEqual(float(generator_loss(fake, first)), 2.0, places=6)

    def test_patch_weights_are_the_invented_share_of_each_cell(self):
        # 16 x 16, the left 4 columns invented: each 8 x 8 cell of the left column holds
        # 32 of 64 invented pixels, those of the right column none.
        invented = torch.zeros(1, 1, 16, 16)
        invented[..., :4] = 1.0
        torch.testing.assert_close(patch_weights(invented), torch.tensor([[[[0.5, 0.0], [0.5, 0.0]]]]))

    def test_patch_logits(self):
        net = PatchDiscriminator()
        self.assertEqual(tuple(net(torch.rand(2, 3, HEIGHT, WIDTH), torch.zeros(2, 1, HEIGHT, WIDTH)).shape),
                         (2, 1, HEIGHT // 8, WIDTH // 8))
        convs = [m for m in net.modules() if isinstance(m, torch.nn.Conv2d)]
        self.assertEqual([(c.in_channels, c.out_channels, c.kernel_size, c.stride) for c in convs],
                         [(4, 32, (4, 4), (2, 2)), (32, 64, (4, 4), (2, 2)), (64, 128, (4, 4), (2, 2)),
                          (128, 1, (3, 3), (1, 1))])
        self.assertTrue(all(torch.nn.utils.parametrize.is_parametrized(c, "weight") for c in convs))

    def test_several_updates_on_one_batch(self):
        # steps=3: three Adam updates on the same frames; the loss returned is the one
        # before the first, as discriminator_loss gives it with the weights as they were
        # (on a copy: each forward in training advances spectral_norm's power iteration).
        torch.manual_seed(0)
        adversary = Adversary(1e-3, torch.device("cpu"), steps=3)
        real, fake = torch.rand(2, 3, 16, 16), torch.rand(2, 3, 16, 16)
        invented = torch.ones(2, 1, 16, 16)
        copy = deepcopy(adversary.net)
        with torch.no_grad():
            before = discriminator_loss(copy(real, invented), copy(fake, invented), patch_weights(invented))
        self.assertAlmostEqual(float(adversary.step(real, fake, invented)), float(before), places=6)
        self.assertEqual({int(state["step"]) for state in adversary.optimizer.state.values()}, {3})
        with torch.no_grad():
            after = discriminator_loss(adversary.net(real, invented), adversary.net(fake, invented),
                                       patch_weights(invented))
        self.assertLess(float(after), float(before))

    def test_a_non_finite_loss_skips_the_step(self):
        adversary = Adversary(1e-3, torch.device("cpu"))
        before = [p.detach().clone() for p in adversary.net.parameters()]
        real = torch.full((1, 3, 16, 16), float("nan"))
        self.assertIsNone(adversary.step(real, torch.rand(1, 3, 16, 16), torch.ones(1, 1, 16, 16)))
        for old, new in zip(before, adversary.net.parameters()):
            torch.testing.assert_close(new, old)

    def test_sample_keeps_pairs_of_frames_with_enough_invented(self):
        # Invented shares 0, 0.5, 0.02, 0.005, 1, 0.3 (10 x 10 maps): frames 1, 2, 4 and 5
        # reach MIN_INVENTED_SHARE (0.01).
        predicted = torch.arange(6.0).view(6, 1, 1, 1).expand(6, 3, 10, 10)
        invented = torch.zeros(6, 1, 10, 10)
        for frame, pixels in ((1, 50), (2, 2), (4, 100), (5, 30)):
            invented[frame].view(-1)[:pixels] = 1.0
        invented[3, 0, 0, 0] = 0.5
        fake, real, shown = train_world_model.adversarial_sample(predicted, predicted + 10, invented, 3,
                                                                 torch.Generator().manual_seed(0))
        self.assertEqual(len(fake), 3)
        frames = fake[:, 0, 0, 0].tolist()
        self.assertEqual(len(set(frames)), 3)
        self.assertTrue(set(frames) <= {1.0, 2.0, 4.0, 5.0})
        torch.testing.assert_close(real, fake + 10)
        torch.testing.assert_close(shown, invented[[int(f) for f in frames]])
        fake, _, _ = train_world_model.adversarial_sample(predicted, predicted + 10, invented, 10, None)
        self.assertEqual(fake[:, 0, 0, 0].tolist(), [1.0, 2.0, 4.0, 5.0])
        self.assertIsNone(train_world_model.adversarial_sample(predicted, predicted, torch.zeros(6, 1, 10, 10), 3,
                                                               None))


class TrainWorldModelTest(unittest.TestCase):
    def test_rejects_val_maps_in_train(self):
        run = train_run("never", ["--val", VAL_SHARD, TRAIN_SHARD])
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("val maps overlap train maps: " + TRAIN_MAP, run.stdout)

    def test_end_to_end_on_cpu(self):
        out = os.path.join(WORK, "run")
        run = train_run("run", ["--val", VAL_SHARD, "--full-res-head", "--gradient-weight", "1"])
        self.assertEqual(run.returncode, 0, run.stdout)
        for name in ("log.csv", "world_model.pt", "world_model.onnx", "metrics.json", "curves.png", "rollouts.png"):
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        self.assertEqual((metrics["train_frames"], metrics["train_sequences"], metrics["val_rollouts"]), (36, 3, 1))
        self.assertEqual(metrics["horizons"]["8"]["rollouts"], 1)
        self.assertEqual(metrics["horizons"]["16"]["rollouts"], 0)
        self.assertLess(metrics["onnx_check"]["max_abs_diff"], 1e-3)
        self.assertEqual((metrics["full_res_head"], metrics["gradient_weight"]), (True, 1.0))
        with open(os.path.join(out, "log.csv")) as handle:
            self.assertEqual([line.split(",")[0] for line in handle.read().split()], ["step", "2", "4"])

    def test_rotation_anchor_end_to_end_on_cpu(self):
        out = os.path.join(WORK, "anchor")
        run = train_run("anchor", ["--val", VAL_SHARD, "--full-res-head", "--warp", "rotation_anchor"])
        self.assertEqual(run.returncode, 0, run.stdout)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        self.assertEqual(metrics["warp"], "rotation_anchor")
        self.assertLess(metrics["onnx_check"]["max_abs_diff"], 1e-3)
        self.assertEqual(metrics["onnx_check"]["inputs"], 2)

    def test_pose_anchor_end_to_end_on_cpu(self):
        out = os.path.join(WORK, "pose")
        run = train_run("pose", ["--val", VAL_SHARD, "--full-res-head", "--warp", "pose_anchor"])
        self.assertEqual(run.returncode, 0, run.stdout)
        self.assertIn("depth prior", run.stdout)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        self.assertEqual(metrics["warp"], "pose_anchor")
        self.assertEqual(len(metrics["depth_prior_sha256"]), 64)
        self.assertLess(metrics["onnx_check"]["max_abs_diff"], 1e-3)
        self.assertEqual([i.name for i in onnx.load(os.path.join(out, "world_model.onnx")).graph.input],
                         ["frames_motion_and_pose_warp"])

    def test_pose_anchor_without_the_prior_file(self):
        run = train_run("pose_no_prior", ["--val", VAL_SHARD, "--warp", "pose_anchor", "--depth-prior",
                                           os.path.join(WORK, "missing.onnx")])
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("--depth-prior %s: no such file" % os.path.join(WORK, "missing.onnx"), run.stdout)

    def test_adversarial_end_to_end_on_cpu(self):
        # 2 windows of 2 frames, then of 3: 4 and 6 predicted frames. The panorama turns
        # left 1.6 degrees a frame, so with the rotation warp every predicted frame's left
        # 1.8 columns of 128 look off the newest frame: invented, at least 1.6 % of it.
        # From step 2 of 4 (--adversarial-start 0.5), 3 of them are shown to the
        # discriminator a step.
        out = os.path.join(WORK, "adversarial")
        run = train_run("adversarial", ["--val", VAL_SHARD, "--warp", "rotation_anchor", "--adversarial-weight",
                                        "0.01", "--adversarial-frames", "3", "--adversarial-start", "0.5",
                                        "--log-every", "1"])
        self.assertEqual(run.returncode, 0, run.stdout)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        self.assertEqual((metrics["adversarial_weight"], metrics["adversarial_frames"], metrics["adversarial_lr"],
                          metrics["adversarial_start"], metrics["init"]), (0.01, 3, 2e-4, 0.5, None))
        with open(os.path.join(out, "log.csv")) as handle:
            rows = list(csv.DictReader(handle))
        self.assertEqual(len(rows), 2)
        self.assertTrue(all(np.isfinite(float(row[key])) for row in rows for key in ("train_loss", "val_l1")))
        logged = adversarial_log(run.stdout)
        self.assertEqual([(int(steps), int(generator)) for steps, generator, _, _ in logged],
                         [(0, 0), (0, 0), (1, 1), (2, 2)], run.stdout)
        # Before the start nothing was measured (the running means print 0).
        self.assertEqual([(float(d), float(g)) for _, _, d, g in logged[:2]], [(0.0, 0.0)] * 2)
        self.assertTrue(all(float(d) > 0 and np.isfinite(float(g)) for _, _, d, g in logged[2:]), logged)

    def test_discriminator_lead_on_cpu(self):
        # 4 steps, the discriminator from step 1 (progress 0.25) and the generator's term
        # from step 2 (0.25 + lead 0.25), two discriminator updates a step, invented pixels
        # at half weight from step 2 on.
        out = os.path.join(WORK, "lead")
        run = train_run("lead", ["--val", VAL_SHARD, "--warp", "rotation_anchor", "--adversarial-weight", "0.01",
                                 "--adversarial-frames", "3", "--adversarial-start", "0.25", "--discriminator-lead",
                                 "0.25", "--discriminator-steps", "2", "--invented-weight", "0.5", "--log-every", "1"])
        self.assertEqual(run.returncode, 0, run.stdout)
        logged = adversarial_log(run.stdout)
        self.assertEqual([(int(steps), int(generator)) for steps, generator, _, _ in logged],
                         [(0, 0), (1, 0), (2, 1), (3, 2)], run.stdout)
        # The discriminator learnt at step 1, but no generator term was measured then.
        self.assertTrue(float(logged[1][2]) > 0 and float(logged[1][3]) == 0.0, logged)
        with open(os.path.join(out, "metrics.json")) as handle:
            metrics = json.load(handle)
        self.assertEqual((metrics["discriminator_lead"], metrics["discriminator_steps"], metrics["invented_weight"]),
                         (0.25, 2, 0.5))

    def test_refuses_a_lead_past_the_end(self):
        run = train_run("lead_refused", ["--val", VAL_SHARD, "--adversarial-weight", "0.01", "--adversarial-start",
                                         "0.5", "--discriminator-lead", "0.5"])
        self.assertNotEqual(run.returncode, 0)
        self.assertIn("--adversarial-start + --discriminator-lead below 1", run.stdout)


class InitTest(unittest.TestCase):
    """--init: a run that starts from the weights of an earlier run's world_model.pt."""

    @classmethod
    def setUpClass(cls):
        cls.source = os.path.join(WORK, "init_source", "world_model.pt")
        run = train_run("init_source", ["--val", VAL_SHARD])
        if run.returncode:
            raise RuntimeError("the --init source run failed:\n" + run.stdout)

    def test_starts_from_the_checkpoint(self):
        # At a learning rate of 1e-9 one step leaves the weights where --init put them
        # (BatchNorm's running statistics move with the batch: not compared).
        out = os.path.join(WORK, "init_target")
        run = train_run("init_target", ["--val", VAL_SHARD, "--init", self.source, "--steps", "1", "--lr", "1e-9"])
        self.assertEqual(run.returncode, 0, run.stdout)
        self.assertIn("init: the weights of %s, step 4 of its run" % self.source, run.stdout)
        source = torch.load(self.source)["state_dict"]
        target = torch.load(os.path.join(out, "world_model.pt"))["state_dict"]
        for name, value in source.items():
            if "running_" not in name and "num_batches_tracked" not in name:
                torch.testing.assert_close(target[name], value, atol=1e-6, rtol=0, msg=name)
        with open(os.path.join(out, "metrics.json")) as handle:
            self.assertEqual(json.load(handle)["init"], {"path": self.source, "sha256": sha256(self.source), "step": 4})

    def test_refuses_a_missing_or_unreadable_file(self):
        missing, garbage = os.path.join(WORK, "missing.pt"), os.path.join(WORK, "garbage.pt")
        with open(garbage, "w") as handle:
            handle.write("not a checkpoint")
        for path, problem in ((missing, "no such file"), (garbage, "unreadable")):
            run = train_run("init_refused", ["--val", VAL_SHARD, "--init", path])
            self.assertNotEqual(run.returncode, 0)
            self.assertIn("train_world_model: error: --init %s: %s" % (path, problem), run.stdout)

    def test_refuses_a_checkpoint_of_other_options(self):
        for options, problem in ((["--warp", "rotation_anchor"], "made with --warp last_frame, this run has --warp "
                                                                 "rotation_anchor"),
                                 (["--context", "3"], "made with --context 4, this run has --context 3")):
            run = train_run("init_refused", ["--val", VAL_SHARD, "--init", self.source] + options)
            self.assertNotEqual(run.returncode, 0)
            self.assertIn("train_world_model: error: --init %s: %s" % (self.source, problem), run.stdout)
        # The frame size is the data's, checked once it is loaded.
        with self.assertRaisesRegex(ValueError, "--init %s: made for 128x96 frames, this data's are 48x32"
                                    % self.source):
            train_world_model.load_init(WorldNet(4, 32, 48), torch.load(self.source), self.source)


def adversarial_log(stdout):
    """(adversarial steps, of them with the generator's term, discriminator loss,
    adversarial term) of each progress line a run with --adversarial-weight printed."""
    return re.findall(r"skipped \(non-finite gradient\) 0  adversarial steps (\d+) \(generator (\d+)\)  "
                      r"discriminator loss (\S+)  adversarial term (\S+)  skipped \(discriminator\) 0\n", stdout)


def train_run(name, options):
    """train_world_model.py on the panorama shards, 4 steps of 2 windows, into WORK/name."""
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENCV_FOR_THREADS_NUM="1")
    command = [sys.executable, os.path.join(HERE, "train_world_model.py"), "--train", TRAIN_SHARD,
               "--out", os.path.join(WORK, name), "--steps", "4", "--batch", "2", "--eval-every", "2",
               "--unroll", "2", "--late-unroll", "3", "--device", "cpu", "--workers", "1"] + options
    return subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=120)


if __name__ == "__main__":
    sys.exit(run_smoke_test(sys.modules[__name__], "learn_smoke_test_world_model"))
