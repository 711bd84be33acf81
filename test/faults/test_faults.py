#!/usr/bin/python3
"""Fault injection against the built tools: a full disk at every output file, a real
file-size limit, kills at random moments of an episode, reruns into unfinished run
folders, bad numbers and config files on the command line, signals, broken map files,
malformed evaluation folders and a shell without the workspace (WithoutWorkspace).
Every fault must end in a clear error naming its input (or a complete run), never an
abort, a hang, a truncated file under a final name or a lost map. Also
the smoke episodes of the learned world backend (LearnedWorldEpisodes), on the
hand-made test model, from an engine spawn and from a screenshot.

  test_faults.py [--xml DIR]   # DIR: JUnit XML for scripts/count_test_results

Needs a build (VALERANT_BUILD, default .ws/build) and the OpenArena maps. The episodes
use the oracle SLAM and 1-4 steps, so the suite runs in a few minutes on 2 cores."""
import argparse
import json
import os
import random
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("VALERANT_BUILD", os.path.join(ROOT, ".ws", "build"))
BIN = os.path.join(BUILD, "devel", "lib", "valerant")
EPISODE = ["--slam", "oracle", "--map", "oa_dm1", "--spawn", "0"]
TIMEOUT = 300  # seconds: any tool that runs longer than this hangs
# The files a finished run holds whatever its map (the map exports need points and are
# checked where a run makes them).
ALWAYS_WRITTEN = ["config.yaml", "decisions.jsonl", "keyframes.pcd", "keyframes.txt", "trajectory.txt",
                  "gt_trajectory.txt", "topdown.png", "view.png", "report.json", "grid.pgm", "grid.yaml",
                  "walkable.json"]
SNAPSHOT_FILES = ["config.yaml", "keyframes.000000.pcd", "keyframes.txt", "trajectory.txt", "report.json"]
MAP_EXPORTS = ["map.ply", "map.pcd", "map.bt", "mesh.obj", "mesh.glb", "overview.png", "orbit.png"]
USAGE_ERROR = 2  # the exit status of a bad command line (src/tools/command_line.h)
CONFIG_FLAGS = ["--config", "--set"]
# learn/make_test_world_model.py's model of the shipped warp (rotation_anchor)
TEST_WORLD_MODEL = os.path.join(ROOT, "test", "data", "world_model_anchor.onnx")
TEST_POSE_WORLD_MODEL = os.path.join(ROOT, "test", "data", "world_model_pose.onnx")
# Every tool (valerant_bench: every benchmark) with every flag its --help must list, the
# flags a run needs, and an integer flag with which to give it a bad number.
TOOL_FLAGS = {
    ("valerant_render",): (["--map", "--spawn", "--candidate", "--every", "--out"] + CONFIG_FLAGS,
                           ["--out", "OUT"], "--every"),
    ("valerant_explore",): (["--map", "--spawn", "--seed", "--slam", "--policy", "--budget", "--no-rf", "--no-col-pc",
                             "--no-col-depth", "--no-dp", "--image", "--force", "--resume", "--out"] + CONFIG_FLAGS,
                            ["--out", "OUT"], "--spawn"),
    ("valerant_slam",): (["--map", "--spawn", "--slam", "--candidates", "--out"] + CONFIG_FLAGS,
                         ["--out", "OUT"], "--spawn"),
    ("valerant_eval",): (["--maps", "--spawns", "--configs", "--out", "--jobs", "--budget", "--slam", "--publish",
                          "--run-timeout", "--report-only"] + CONFIG_FLAGS,
                         ["--maps", "oa_dm1", "--out", "OUT"], "--jobs"),
    ("valerant_export",): (["--run", "--out", "--formats", "--force"], ["--run", "RUN", "--out", "OUT"], None),
    ("valerant_dataset",): (["--out", "--split", "--maps", "--exclude", "--map-sets", "--seed", "--width", "--height",
                             "--spawns", "--rotations", "--walks", "--shard-mib", "--in-solid", "--texture-shuffle",
                             "--list-maps"] + CONFIG_FLAGS,
                            ["--out", "OUT"], "--seed"),
    ("valerant_bench", "render"): (["--map", "--spawn", "--frames"] + CONFIG_FLAGS, [], "--frames"),
    ("valerant_bench", "slam"): (["--map", "--spawn", "--slam", "--candidates", "--repeats"] + CONFIG_FLAGS, [],
                                 "--repeats"),
    ("valerant_bench", "graph"): (["--map", "--spawn", "--seed", "--slam", "--budget", "--out"] + CONFIG_FLAGS,
                                  ["--out", "OUT"], "--budget"),
    ("valerant_bench", "map"): (["--run", "--updates"], ["--run", "RUN"], "--updates"),
    ("valerant_bench", "depth"): (["--maps", "--spawns", "--model"] + CONFIG_FLAGS, [], "--spawns"),
    ("valerant_bench", "extent"): (["--maps", "--spawns"] + CONFIG_FLAGS, [], "--spawns"),
    ("valerant_bench", "wm"): (["--maps", "--spawns", "--model", "--out"] + CONFIG_FLAGS, [], "--spawns"),
    ("valerant_bench", "sweep"): (["--map", "--spawn", "--candidates", "--gap", "--repeats"] + CONFIG_FLAGS, [],
                                  "--gap"),
}


def tool(name):
    return os.path.join(BIN, name)


def run(args, env=None, preexec_fn=None, timeout=TIMEOUT):
    """Runs a tool; returns (exit status, stdout, stderr)."""
    merged = dict(os.environ, **(env or {}))
    done = subprocess.run(args, capture_output=True, text=True, env=merged, preexec_fn=preexec_fn, timeout=timeout)
    return done.returncode, done.stdout, done.stderr


def explore(out, budget, *extra, env=None, preexec_fn=None):
    return run([tool("valerant_explore"), *EPISODE, "--budget", str(budget), "--out", out, *extra], env=env,
               preexec_fn=preexec_fn)


def partial_files(folder):
    """Temporary files of interrupted atomic writes, anywhere under `folder`."""
    found = []
    for here, dirs, files in os.walk(folder):
        found += [os.path.join(here, f) for f in files + dirs if ".partial" in f]
    return found


def complete_report(folder):
    """report.json of a finished run, or None."""
    try:
        with open(os.path.join(folder, "report.json")) as handle:
            report = json.load(handle)
    except (OSError, ValueError):
        return None
    return report if isinstance(report, dict) and "tool" in report else None


class Faults(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        for name in ("valerant_explore", "valerant_export", "valerant_eval", "policy_arbiter"):
            if not os.access(tool(name), os.X_OK):
                raise unittest.SkipTest(tool(name) + " is not built")
        cls.scratch = tempfile.mkdtemp(prefix="valerant_faults_")
        # One finished run: the reference for what a complete run holds.
        cls.reference = os.path.join(cls.scratch, "reference")
        status, _, err = explore(cls.reference, 2)
        assert status == 0, err

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch, ignore_errors=True)

    def folder(self, name):
        path = os.path.join(self.scratch, name)
        shutil.rmtree(path, ignore_errors=True)
        return path

    def assertFilesWhole(self, out):
        """Every file under a final name is whole: JSON parses, a PNG ends with its IEND
        chunk, a TUM trajectory has 8 numbers a line, a log has whole lines."""
        for here, _, files in os.walk(out):
            for name in files:
                if name.startswith("."):
                    continue  # a temporary file a kill left: never read, removed by --resume/--force
                path = os.path.join(here, name)
                with open(path, "rb") as handle:
                    data = handle.read()
                if name.endswith(".json"):
                    json.loads(data)
                elif name.endswith(".png"):
                    self.assertTrue(data.startswith(b"\x89PNG") and data.endswith(b"IEND\xaeB`\x82"), path)
                elif name.endswith(".txt"):
                    for line in data.decode().splitlines():
                        if line and not line.startswith("#"):
                            self.assertEqual(len(line.split()), 8, path)
                elif name.endswith(".jsonl"):
                    self.assertTrue(data == b"" or data.endswith(b"\n"), path)

    def assertUnfinishedAndWhole(self, out):
        """No report, no leftover temporary file, and the rerun without a flag refuses."""
        self.assertIsNone(complete_report(out), out)
        self.assertEqual(partial_files(out), [], out)
        self.assertFilesWhole(out)
        status, _, err = explore(out, 2)
        self.assertEqual(status, 1)
        self.assertIn("unfinished run", err)
        self.assertIn("--resume", err)

    def test_reference_run_is_complete(self):
        report = complete_report(self.reference)
        self.assertIsNotNone(report)
        for name in ALWAYS_WRITTEN + MAP_EXPORTS:
            self.assertTrue(os.path.isfile(os.path.join(self.reference, name)), name)
        self.assertFalse(os.path.exists(os.path.join(self.reference, "snapshot")), "a finished run keeps no snapshot")
        self.assertEqual(partial_files(self.reference), [])

    def test_disk_full_at_each_output_file(self):
        # VALERANT_FAIL_WRITES makes the writer of the file whose path ends so fail as a
        # full disk does: each final file, and each file of the snapshot taken per step.
        cases = [("full_" + name, name) for name in ALWAYS_WRITTEN + MAP_EXPORTS]
        cases += [("full_snapshot_" + name, ".snapshot.partial/" + name) for name in SNAPSHOT_FILES]
        for folder, item in cases:
            name = os.path.basename(item)
            with self.subTest(file=item):
                out = self.folder(folder)
                if not item.startswith("."):
                    item = folder + "/" + item  # the final file, not the snapshot's copy
                status, out_text, err = explore(out, 1, env={"VALERANT_FAIL_WRITES": item})
                self.assertEqual(status, 1, err)
                self.assertEqual(out_text, "", "no success line")
                self.assertIn(name, err)
                self.assertIn("No space left on device", err)
                if name != "config.yaml":  # without its config the folder holds no run at all
                    self.assertUnfinishedAndWhole(out)

    def test_file_size_limit_fails_cleanly(self):
        # A real write failure: the kernel refuses to grow any file past 64 KiB (EFBIG;
        # SIGXFSZ ignored, as a shell's `ulimit -f` with a trapped signal would).
        def limit():
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
            resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024, 64 * 1024))

        out = self.folder("fsize")
        status, _, err = explore(out, 1, preexec_fn=limit)
        self.assertEqual(status, 1, err)
        # The error names the file (PCL's own message may not carry errno's text).
        self.assertRegex(err.splitlines()[-1], "^valerant_explore: error: " + out + "/")
        self.assertIsNone(complete_report(out))
        self.assertEqual(partial_files(out), [])
        for name in os.listdir(out):  # nothing cut: every file under a final name is whole
            path = os.path.join(out, name)
            if os.path.isfile(path):
                self.assertLess(os.path.getsize(path), 64 * 1024, name)

    def test_kill_at_random_moments(self):
        rng = random.Random(7)
        for attempt in range(3):
            with self.subTest(attempt=attempt):
                out = self.folder("kill_%d" % attempt)
                delay = rng.uniform(1.0, 8.0)
                child = subprocess.Popen([tool("valerant_explore"), *EPISODE, "--budget", "4", "--out", out],
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                time.sleep(delay)
                child.kill()
                child.wait()
                self.assertFilesWhole(out)
                if complete_report(out) is not None:
                    continue  # it finished before the kill: a complete run is fine too
                if not os.path.isfile(os.path.join(out, "config.yaml")):
                    # Killed while loading, before the folder held a run (under load the
                    # start takes longer than the delay): nothing to resume, and saying so.
                    status, _, err = run([tool("valerant_explore"), "--resume", "--out", out])
                    self.assertEqual(status, 1, err)
                    self.assertIn("config.yaml", err)
                    continue
                # The map of the committed steps is recoverable from the snapshot.
                snapshot = os.path.join(out, "snapshot")
                if os.path.isdir(snapshot):
                    export = self.folder("kill_export_%d" % attempt)
                    status, _, err = run([tool("valerant_export"), "--run", snapshot, "--out", export,
                                          "--formats", "pcd,grid"])
                    self.assertEqual(status, 0, err)
                # --resume replays the recorded steps and finishes the run.
                status, _, err = run([tool("valerant_explore"), "--resume", "--out", out])
                self.assertEqual(status, 0, err)
                report = complete_report(out)
                self.assertIsNotNone(report)
                self.assertEqual(report["budget"], 4)
                with open(os.path.join(out, "decisions.jsonl")) as handle:
                    steps = [json.loads(line)["step"] for line in handle]
                self.assertEqual(steps, list(range(1, len(steps) + 1)))
                self.assertEqual(partial_files(out), [])

    def test_rerun_into_a_partial_folder(self):
        out = self.folder("partial")
        status, _, err = explore(out, 1, env={"VALERANT_FAIL_WRITES": "report.json"})
        self.assertEqual(status, 1, err)
        status, _, err = explore(out, 1)
        self.assertEqual(status, 1)
        self.assertIn("pass --resume to continue it or --force to replace it", err)
        status, _, err = explore(out, 1, "--force")
        self.assertEqual(status, 0, err)
        self.assertIsNotNone(complete_report(out))
        status, _, err = explore(out, 1)
        self.assertEqual(status, 1)
        self.assertIn("holds a finished run already", err)
        status, _, err = run([tool("valerant_explore"), "--resume", "--out", out])
        self.assertEqual(status, 1)
        self.assertIn("nothing to resume", err)

    def test_resume_refuses_a_run_that_decides_otherwise(self):
        out = self.folder("diverged")
        status, _, err = explore(out, 2, env={"VALERANT_FAIL_WRITES": "report.json"})
        self.assertEqual(status, 1, err)
        with open(os.path.join(out, "decisions.jsonl")) as handle:
            lines = [json.loads(line) for line in handle]
        lines[0]["chosen"] = "lq" if lines[0]["chosen"] != "lq" else "jq"
        with open(os.path.join(out, "decisions.jsonl"), "w") as handle:
            handle.write("".join(json.dumps(line) + "\n" for line in lines) + '{"step": 3, "cut by a ki')
        status, _, err = run([tool("valerant_explore"), "--resume", "--out", out])
        self.assertEqual(status, 1)
        self.assertIn("step 1: the resumed episode's chosen is", err)
        self.assertIsNone(complete_report(out))

    def test_huge_and_bad_numbers_are_errors_naming_the_flag(self):
        out = self.folder("huge")
        for flags, message in [(["--budget", "1000000000"], "--budget 1000000000: policy.budget_steps: value"),
                               (["--budget", "0"], "--budget 0: policy.budget_steps: value 0 outside"),
                               (["--spawn", "99999999999"], "--spawn 99999999999: world.spawn"),
                               (["--set", "policy.budget_step=3"], "policy.budget_step: unknown key"),
                               (["--set", "collision.body_radius=-1"], "collision.body_radius: value -1 outside")]:
            with self.subTest(flags=flags):
                status, _, err = run([tool("valerant_explore"), *EPISODE, *flags, "--out", out])
                self.assertEqual(status, USAGE_ERROR, err)
                self.assertIn(message, err)
                self.assertFalse(os.path.exists(out), "nothing is made before the input is checked")

    def test_every_tool_answers_help_with_every_flag(self):
        status, out, err = run([tool("valerant_bench"), "--help"])
        self.assertEqual(status, 0, err)
        for benchmark in ("render", "slam", "graph", "map", "depth", "extent", "wm"):
            self.assertIn(benchmark, out)
        for command, (flags, _, _) in TOOL_FLAGS.items():
            for help_flag in ("--help", "-h"):
                with self.subTest(command=command, help=help_flag):
                    status, out, err = run([tool(command[0]), *command[1:], help_flag])
                    self.assertEqual(status, 0, err)
                    listed = set(re.findall(r"--[a-z][a-z-]*", out))
                    for flag in flags + ["--help"]:
                        self.assertIn(flag, listed, out)
                    self.assertIn("Exit status", out)

    def test_bad_command_lines_are_errors_naming_the_flag_and_value(self):
        out = self.folder("bad_command_line")
        for command, (_, needed, integer_flag) in TOOL_FLAGS.items():
            needed = [out if word in ("OUT", "RUN") else word for word in needed]
            cases = [(["--no-such-flag"], ["--no-such-flag: unknown flag"]),
                     (["stray"], ["'stray': unexpected argument"])]
            if integer_flag:
                cases.append(([integer_flag, "2x"], [integer_flag, "2x"]))
            for flags, messages in cases:
                with self.subTest(command=command, flags=flags):
                    status, _, err = run([tool(command[0]), *command[1:], *needed, *flags])
                    self.assertEqual(status, USAGE_ERROR, err)
                    for message in messages:
                        self.assertIn(message, err)
                    self.assertIn("--help", err)
                    self.assertFalse(os.path.exists(out), "nothing is made before the command line is checked")
        for command in (["valerant_explore"], ["valerant_export", "--run", out]):
            with self.subTest(command=command):
                status, _, err = run([tool(command[0]), *command[1:]])  # --out left out
                self.assertEqual(status, USAGE_ERROR, err)
                self.assertIn("--out is required", err)
        status, _, err = run([tool("valerant_explore"), "--force", "--resume", "--out", out])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("--force excludes --resume", err)
        status, _, err = run([tool("valerant_explore"), "--resume", "--budget", "3", "--out", out])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("--resume: takes the run's own configuration (its config.yaml); leave out --budget", err)
        status, _, err = run([tool("valerant_bench")])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("subcommand", err)
        # An empty folder or file: valerant_eval once wrote its grid into / ("" + "/runs").
        for command, (_, needed, _) in TOOL_FLAGS.items():
            for path_flag in ("--out", "--run"):
                if path_flag not in needed:
                    continue
                with self.subTest(command=command, flag=path_flag):
                    words = [out if word in ("OUT", "RUN") else word for word in needed]
                    words[words.index(path_flag) + 1] = ""
                    status, _, err = run([tool(command[0]), *command[1:], *words], timeout=60)
                    self.assertEqual(status, USAGE_ERROR, err)
                    self.assertIn(path_flag + ": an empty value names no folder", err)
        status, _, err = run([tool("valerant_bench"), "rendre"])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("'rendre': unknown subcommand (one of: render, slam, graph, map, depth, extent, wm, sweep)", err)
        # Counts that render nothing once wrote no shard and exited 0.
        status, _, err = run([tool("valerant_dataset"), "--maps", "oa_dm1", "--spawns", "0", "--rotations", "0",
                              "--walks", "0", "--out", out])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("--spawns 0 --rotations 0 --walks 0 --wall-rotations 0: render nothing", err)
        self.assertFalse(os.path.exists(out))

    def test_truncated_config_is_an_error_naming_the_key(self):
        with open(os.path.join(ROOT, "config", "valerant.yaml")) as handle:
            text = handle.read()
        cut = os.path.join(self.scratch, "cut.yaml")
        with open(cut, "w") as handle:
            handle.write(text[:text.index("\ncollision:")])
        status, _, err = run([tool("valerant_explore"), *EPISODE, "--config", cut, "--out", self.folder("cut")])
        self.assertEqual(status, 1)
        self.assertIn(cut + ": collision: missing", err)

    def test_config_files_that_do_not_load_are_errors_naming_them(self):
        broken = os.path.join(self.scratch, "broken.yaml")
        with open(broken, "w") as handle:
            handle.write("policy:\n  budget_steps: [1, 2\n")
        missing = os.path.join(self.scratch, "missing.yaml")
        for flags, status_wanted, message in [
                (["--config", missing], 1, missing + ": cannot read config file"),
                (["--config", broken], 1, broken + ": invalid YAML"),
                (["--config", self.scratch], 1, self.scratch + ": is a folder, not a config file"),
                (["--config", ""], USAGE_ERROR, "--config: an empty value names no file"),
                (["--set", "policy.budget_steps="], USAGE_ERROR, "policy.budget_steps: expected a number, got ''")]:
            with self.subTest(flags=flags):
                out = self.folder("bad_config")
                status, _, err = run([tool("valerant_explore"), *EPISODE, *flags, "--out", out])
                self.assertEqual(status, status_wanted, err)
                self.assertIn(message, err)
                self.assertFalse(os.path.exists(out), "nothing is made before the configuration loads")

    def test_signals(self):
        for sig, code, name in [(signal.SIGINT, 130, "SIGINT"), (signal.SIGTERM, 143, "SIGTERM")]:
            with self.subTest(signal=name):
                out = self.folder("signal_" + name)
                child = subprocess.Popen([tool("valerant_explore"), *EPISODE, "--budget", "15", "--out", out],
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                time.sleep(4)
                child.send_signal(sig)
                self.assertEqual(child.wait(timeout=TIMEOUT), code)
                report = complete_report(out)
                self.assertIsNotNone(report, "the first signal still writes everything")
                self.assertTrue(report["interrupted"])
                self.assertEqual(report["signal"], name)
        # A second signal ends the process at once; what it leaves is an unfinished run.
        out = self.folder("signal_twice")
        child = subprocess.Popen([tool("valerant_explore"), *EPISODE, "--budget", "15", "--out", out],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(4)
        child.send_signal(signal.SIGINT)
        time.sleep(0.2)
        child.send_signal(signal.SIGINT)
        self.assertEqual(child.wait(timeout=TIMEOUT), -signal.SIGINT)
        self.assertFilesWhole(out)
        if complete_report(out) is None:  # --force clears what the kill left, temporary files too
            status, _, err = explore(out, 1, "--force")
            self.assertEqual(status, 0, err)
            self.assertEqual(partial_files(out), [])

    def test_eval_reports_malformed_reports_as_failed_rows(self):
        out = self.folder("eval_malformed")
        shapes = {0: "[]", 1: '{"tool": "valerant_explore", "ground_truth": "x"}', 2: '{"tool": "valerant_ex'}
        for spawn, text in shapes.items():
            run_dir = os.path.join(out, "runs", "oa_dm1-s%d-full" % spawn)
            os.makedirs(run_dir)
            with open(os.path.join(run_dir, "report.json"), "w") as handle:
                handle.write(text)
        status, summary, err = run([tool("valerant_eval"), "--maps", "oa_dm1", "--spawns", "3", "--configs", "full",
                                    "--out", out, "--report-only"])
        self.assertEqual(status, 1, err)  # failed rows, not an abort
        self.assertEqual(json.loads(summary)["failed"], 3)
        with open(os.path.join(out, "results.csv")) as handle:
            rows = handle.read().splitlines()[1:]
        self.assertEqual(len(rows), 3)
        self.assertIn("array", rows[0])
        self.assertIn("ground_truth", rows[1])
        self.assertTrue(os.path.isfile(os.path.join(out, "evaluation.md")))

    def test_eval_run_timeout_fails_the_run_and_reports(self):
        out = self.folder("eval_timeout")
        started = time.time()
        status, summary, err = run([tool("valerant_eval"), "--maps", "oa_dm1", "--spawns", "1", "--configs", "full",
                                    "--slam", "oracle", "--budget", "15", "--run-timeout", "3", "--out", out])
        self.assertEqual(status, 1, err)
        self.assertLess(time.time() - started, 60)
        with open(os.path.join(out, "results.csv")) as handle:
            self.assertIn("timed out after 3 s", handle.read())
        # SIGTERM let the episode stop after its step and write an interrupted report,
        # which the grid counts as failed (and redoes next time).
        run_dir = os.path.join(out, "runs", "oa_dm1-s0-full")
        report = complete_report(run_dir)
        self.assertTrue(report is None or report["interrupted"])
        self.assertFilesWhole(run_dir)

    def test_eval_budget_is_checked_before_any_run(self):
        out = self.folder("eval_budget")
        status, _, err = run([tool("valerant_eval"), "--maps", "oa_dm1", "--budget", "1000000000", "--out", out])
        self.assertEqual(status, USAGE_ERROR)
        self.assertIn("--budget 1000000000: policy.budget_steps: value", err)
        self.assertFalse(os.path.exists(os.path.join(out, "runs")))

    def map_archive(self, name, edit_bsp=None, corrupt_stored_byte=False):
        """A pk3 holding oa_dm1's BSP as maps/NAME.bsp, edited by `edit_bsp(bytearray)`,
        stored uncompressed; with `corrupt_stored_byte` one byte of the stored data is
        flipped after the archive is written, so the entry's CRC no longer matches."""
        source = "/usr/share/games/openarena/baseoa/pak1-maps.pk3"
        with zipfile.ZipFile(source) as archive:
            bsp = bytearray(archive.read("maps/oa_dm1.bsp"))
        if edit_bsp:
            edit_bsp(bsp)
        path = os.path.join(self.scratch, name + ".pk3")
        entry = "maps/%s.bsp" % name
        with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_STORED) as archive:
            archive.writestr(entry, bytes(bsp))
        if corrupt_stored_byte:
            with zipfile.ZipFile(path) as archive:
                info = archive.getinfo(entry)
            with open(path, "r+b") as handle:
                handle.seek(info.header_offset + 26)
                name_length, extra_length = struct.unpack("<HH", handle.read(4))
                middle = info.header_offset + 30 + name_length + extra_length + len(bsp) // 2
                handle.seek(middle)
                byte = handle.read(1)[0]
                handle.seek(middle)
                handle.write(bytes([byte ^ 0xFF]))
        return path + ":" + name

    def test_bsp_with_a_cycle_in_its_node_tree(self):
        def cycle(bsp):
            # Lump 3 (nodes): plane, children[2], mins[3], maxs[3] as int32, 36 bytes a
            # node. The root's first child becomes the root: descending never ends.
            offset, length = struct.unpack_from("<ii", bsp, 8 + 3 * 8)
            self.assertGreater(length, 36)
            struct.pack_into("<i", bsp, offset + 4, 0)

        spec = self.map_archive("cyclic_dm1", edit_bsp=cycle)
        status, _, err = run([tool("valerant_explore"), "--map", spec, "--slam", "oracle", "--budget", "1",
                              "--out", self.folder("cyclic")], timeout=120)
        self.assertEqual(status, 1, err)
        self.assertIn("cyclic_dm1.bsp", err)
        self.assertIn("cycle", err.lower())

    def test_pk3_entry_with_a_bad_crc(self):
        spec = self.map_archive("crc_dm1", corrupt_stored_byte=True)
        status, _, err = run([tool("valerant_explore"), "--map", spec, "--slam", "oracle", "--budget", "1",
                              "--out", self.folder("crc")], timeout=120)
        self.assertEqual(status, 1, err)
        self.assertIn("crc_dm1.bsp", err)
        self.assertIn("crc", err.lower())

    def test_world_model_bench_on_the_test_model(self):
        # valerant_bench wm end to end on one map and spawn with the hand-made anchor model
        # (learn/make_test_world_model.py): every part of its JSON line and one sheet.
        out = self.folder("wm_bench")
        status, stdout, err = run([tool("valerant_bench"), "wm", "--maps", "oa_dm2", "--spawns", "1", "--model",
                                   TEST_WORLD_MODEL, "--set", "world.learned.warp=rotation_anchor", "--out", out])
        self.assertEqual(status, 0, err)
        line = json.loads(stdout)
        self.assertEqual([h["frame"] for h in line["horizons"]], [8, 16, 32, 57, 97])
        # 97: jw, lw only; frames in solid are counted apart.
        self.assertEqual([h["rollouts"] + h["in_solid_skipped"] for h in line["horizons"]], [5, 5, 5, 5, 2])
        for horizon in line["horizons"]:
            for kind in ("model", "repeat", "flat"):
                self.assertGreater(horizon[kind]["psnr"], 0, horizon)
                self.assertLessEqual(horizon[kind]["ssim"], 1, horizon)
        for source in ("generated", "engine"):
            motion = line["motion"][source]
            self.assertEqual(motion["rollouts"], 5, motion)
            self.assertEqual(motion["heading_error_deg"]["rollouts"], 3, motion)  # uw, jw, lw translate
            self.assertGreaterEqual(motion["lost_frames"], 0, motion)
        self.assertGreater(line["depth_abs_rel"]["frames"], 0, line["depth_abs_rel"])
        self.assertGreater(line["depth_abs_rel"]["engine"], 0, line["depth_abs_rel"])
        self.assertGreater(line["ms_per_frame"], 0)
        sheet = os.path.join(out, "wm_oa_dm2_spawn0.png")
        self.assertEqual(line["sheets"], [sheet])
        with open(sheet, "rb") as handle:
            self.assertTrue(handle.read(8).startswith(b"\x89PNG"))

    def test_world_model_bench_on_the_pose_anchor_test_model(self):
        # A pose_anchor model starts from the depth prior's depth of the screenshot; the
        # bench once built the net without the prior and refused every such model.
        out = self.folder("wm_bench_pose")
        status, stdout, err = run([tool("valerant_bench"), "wm", "--maps", "oa_dm2", "--spawns", "1", "--model",
                                   TEST_POSE_WORLD_MODEL, "--set", "world.learned.warp=pose_anchor", "--out", out])
        self.assertEqual(status, 0, err)
        line = json.loads(stdout)
        self.assertEqual([h["rollouts"] + h["in_solid_skipped"] for h in line["horizons"]], [5, 5, 5, 5, 2])
        for horizon in line["horizons"]:
            self.assertGreater(horizon["model"]["psnr"], 0, horizon)
        self.assertEqual(line["motion"]["generated"]["rollouts"], 5, line["motion"])

    def test_graph_bench_names_the_error_of_the_episode_it_ran(self):
        # The in-process episode fails on the map; its error once stayed in its log.
        out = self.folder("graph_bench_bad_map")
        status, _, err = run([tool("valerant_bench"), "graph", "--map", "no_such_map", "--slam", "oracle",
                              "--budget", "1", "--out", out])
        self.assertEqual(status, 1, err)
        self.assertIn("valerant_explore: failed: valerant_explore: error: map 'no_such_map': not found", err)
        self.assertIn(os.path.join(out, "in_process", "stderr.log"), err)

    def test_world_model_bench_with_a_missing_model_is_an_error_naming_it(self):
        missing = os.path.join(self.scratch, "no_such_world_model.onnx")
        status, _, err = run([tool("valerant_bench"), "wm", "--maps", "oa_dm2", "--model", missing])
        self.assertEqual(status, 1, err)
        self.assertIn(missing, err)

    def test_bad_launch_parameter_is_an_error_naming_it(self):
        # The graph's ROS parameters are overrides through the same strict loader as the
        # tools' flags: a mistyped `policy:=` stops the node with the parameter named.
        port = str(11000 + os.getpid() % 1000)
        env = {"ROS_MASTER_URI": "http://localhost:" + port}
        master = subprocess.Popen(["roscore", "-p", port], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                  env=dict(os.environ, **env), start_new_session=True)
        try:
            deadline = time.time() + 60
            while run(["rosparam", "set", "/valerant_config/policy", "bogus"], env=env, timeout=30)[0] != 0:
                self.assertLess(time.time(), deadline, "roscore did not start")
                time.sleep(1)
            status, _, err = run([tool("policy_arbiter")], env=env, timeout=60)
            self.assertEqual(status, 1, err)
            self.assertIn("parameter /valerant_config/policy (bogus): policy.kind: 'bogus' is not one of", err)
        finally:
            os.killpg(master.pid, signal.SIGINT)
            master.wait(timeout=60)

    def test_mistyped_key_in_the_set_launch_argument_is_an_error_naming_it(self):
        # roslaunch's set:= passes any overrides through the same loader: a mistyped key
        # stops the graph (every node is required) with the key and the argument named.
        port = str(12000 + os.getpid() % 1000)
        launch = subprocess.Popen(["roslaunch", "-p", port, "valerant", "graph.launch", "slam:=oracle",
                                   "set:=policy.budget_steps=3 floor.enabeld=false"],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  env=dict(os.environ, ROS_MASTER_URI="http://localhost:" + port),
                                  start_new_session=True)
        try:
            output, _ = launch.communicate(timeout=180)
        finally:
            if launch.poll() is None:
                os.killpg(launch.pid, signal.SIGINT)
                launch.wait(timeout=60)
        self.assertIn("parameter /valerant_config/set (floor.enabeld=false): floor.enabeld: unknown key", output)


class WithoutWorkspace(unittest.TestCase):
    """The tools from a shell that has not sourced the workspace: no ROS_PACKAGE_PATH,
    VALERANT_SHARE_DIR or VALERANT_CONFIG, in a folder outside the package. --help works;
    a run that needs the package's files ends with an error naming the flag whose
    default it needed and the environment searched (exit 1), never an abort: the lookup
    of --config's default once threw outside main's handler (SIGABRT, exit 134)."""
    PACKAGE_VARIABLES = ("ROS_PACKAGE_PATH", "VALERANT_SHARE_DIR", "VALERANT_CONFIG")
    # The tools that read the package's configuration when --config is left out
    # (valerant_export and valerant_bench map read the run's own).
    READS_PACKAGE_CONFIG = [command for command in TOOL_FLAGS
                            if command not in (("valerant_export",), ("valerant_bench", "map"))]

    @classmethod
    def setUpClass(cls):
        cls.scratch = tempfile.mkdtemp(prefix="valerant_no_workspace_")
        cls.env = {name: value for name, value in os.environ.items() if name not in cls.PACKAGE_VARIABLES}

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch, ignore_errors=True)

    def run_bare(self, args, env=None):
        """Runs a tool in the scratch folder without the package's variables."""
        done = subprocess.run(args, capture_output=True, text=True, env=dict(self.env, **(env or {})),
                              cwd=self.scratch, timeout=TIMEOUT)
        return done.returncode, done.stdout, done.stderr

    def test_every_tool_answers_help(self):
        for command in [("valerant_bench",)] + list(TOOL_FLAGS):
            with self.subTest(command=command):
                status, out, err = self.run_bare([tool(command[0]), *command[1:], "--help"])
                self.assertEqual(status, 0, err)
                self.assertIn("Exit status", out)
                if command in self.READS_PACKAGE_CONFIG:
                    self.assertIn("--config FILE=the package's config/valerant.yaml (package not found)", out)

    def test_a_run_that_needs_the_package_names_the_flag_and_the_environment(self):
        out = os.path.join(self.scratch, "out")
        for command in self.READS_PACKAGE_CONFIG:
            needed = [out if word == "OUT" else word for word in TOOL_FLAGS[command][1]]
            with self.subTest(command=command):
                status, _, err = self.run_bare([tool(command[0]), *command[1:], *needed])
                self.assertEqual(status, 1, err)
                self.assertIn(" ".join(command) + ": error: --config left out: the package's "
                              "config/valerant.yaml: ROS_PACKAGE_PATH='': no folder there holds the valerant "
                              "package", err)
                self.assertFalse(os.path.exists(out), "nothing is made before the configuration loads")
        status, _, err = self.run_bare([tool("valerant_explore"), "--out", out], env={"VALERANT_SHARE_DIR": self.scratch})
        self.assertEqual(status, 1, err)
        self.assertIn("VALERANT_SHARE_DIR=" + self.scratch + ": holds no package.xml naming valerant", err)

    def test_files_given_on_the_command_line_need_no_package(self):
        config = ["--config", os.path.join(ROOT, "config", "valerant.yaml")]
        status, out, err = self.run_bare([tool("valerant_dataset"), *config, "--map-sets",
                                          os.path.join(ROOT, "config", "map_sets.yaml"), "--list-maps"])
        self.assertEqual(status, 0, err)
        self.assertIn("oa_dm1", out.split())
        status, _, err = self.run_bare([tool("valerant_dataset"), *config, "--list-maps"])
        self.assertEqual(status, 1, err)
        self.assertIn("--map-sets left out: the package's config/map_sets.yaml: ROS_PACKAGE_PATH=''", err)


class LearnedWorldEpisodes(unittest.TestCase):
    """valerant_explore with world.backend learned on the hand-made model
    (learn/make_test_world_model.py), from an engine spawn (the engine shadow gives the
    ground truth) and from a PNG the engine rendered (no ground truth)."""
    # The shift model (last_frame warp) moves the picture in walks too, so its episodes map.
    MODEL = os.path.join(ROOT, "test", "data", "world_model_shift.onnx")
    LEARNED = ["--set", "world.backend=learned", "--set", "world.learned.model=" + MODEL,
               "--set", "world.learned.warp=last_frame"]

    @classmethod
    def setUpClass(cls):
        for name in ("valerant_explore", "valerant_render", "valerant_export"):
            if not os.access(tool(name), os.X_OK):
                raise unittest.SkipTest(tool(name) + " is not built")
        cls.scratch = tempfile.mkdtemp(prefix="valerant_learned_")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch, ignore_errors=True)

    def test_engine_tools_refuse_the_learned_world(self):
        for command in ([tool("valerant_render"), "--out", os.path.join(self.scratch, "render")],
                        [tool("valerant_bench"), "slam"]):
            status, _, err = run(command + self.LEARNED)
            self.assertEqual(status, 2, err)
            self.assertIn("world.backend learned: ", err)
            self.assertIn("runs the game engine only (world.backend quake3)", err)

    def assertFinishedWithMap(self, out, status, err):
        self.assertEqual(status, 0, err)
        report = complete_report(out)
        self.assertIsNotNone(report, err)
        for name in ("trajectory.txt", "topdown.png", "view.png", "keyframes.pcd", "grid.pgm", "map.ply"):
            self.assertTrue(os.path.isfile(os.path.join(out, name)), name)
        self.assertGreaterEqual(report["committed_steps"], 1, err)
        self.assertGreater(report["map_points"], 0, err)
        return report

    def test_spawn_start_finishes_with_the_engines_ground_truth(self):
        out = os.path.join(self.scratch, "spawn")
        status, _, err = run([tool("valerant_explore"), "--map", "oa_dm1", "--spawn", "0", "--budget", "2", *self.LEARNED,
                              "--out", out])
        report = self.assertFinishedWithMap(out, status, err)
        self.assertIsInstance(report["ground_truth"], dict)
        self.assertGreater(report["ground_truth"]["committed_frames"], 1)
        self.assertGreater(report["frames_rendered"], 0)
        self.assertTrue(os.path.isfile(os.path.join(out, "gt_trajectory.txt")))
        self.assertIn("| observed ", err)  # the progress lines count coverage

    def test_screenshot_start_finishes_without_ground_truth(self):
        rendered = os.path.join(self.scratch, "render")
        status, _, err = run([tool("valerant_render"), "--map", "oa_dm1", "--spawn", "0", "--candidate", "q:1",
                              "--out", rendered])
        self.assertEqual(status, 0, err)
        shot = os.path.join(rendered, "spawn.png")
        out = os.path.join(self.scratch, "screenshot")
        status, line, err = run([tool("valerant_explore"), "--image", shot, "--budget", "2", *self.LEARNED,
                                 "--out", out])
        report = self.assertFinishedWithMap(out, status, err)
        self.assertIsNone(report["ground_truth"])
        self.assertIsNone(report["frames_rendered"])
        self.assertEqual(report["screenshot"], shot)
        self.assertEqual(report["world"], "learned")
        self.assertIsNone(report["map"])  # no level
        self.assertFalse(os.path.exists(os.path.join(out, "gt_trajectory.txt")))
        self.assertTrue(os.path.isfile(os.path.join(out, "screenshot.png")))
        self.assertNotIn("| observed ", err)  # no coverage without ground truth
        self.assertIsNone(json.loads(line)["ground_truth"])
        # The run exports like any other; its walkable area has nothing to be scored against.
        exported = os.path.join(self.scratch, "screenshot_export")
        status, line, err = run([tool("valerant_export"), "--run", out, "--out", exported, "--formats", "walkable"])
        self.assertEqual(status, 0, err)
        self.assertFalse(json.loads(line)["ground_truth"]["available"])

    def test_bad_image_and_image_without_the_learned_backend_are_errors_naming_them(self):
        out = os.path.join(self.scratch, "bad")
        status, _, err = run([tool("valerant_explore"), "--image", "/nonexistent/shot.png", *self.LEARNED,
                              "--out", out])
        self.assertEqual(status, 1, err)
        self.assertIn("/nonexistent/shot.png: screenshot file does not exist", err)
        text = os.path.join(self.scratch, "text.png")
        with open(text, "w") as handle:
            handle.write("not an image")
        status, _, err = run([tool("valerant_explore"), "--image", text, *self.LEARNED, "--out", out])
        self.assertEqual(status, 1, err)
        self.assertIn(text + ": not an image", err)
        status, _, err = run([tool("valerant_explore"), "--image", text, "--out", out])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("--image " + text + ": starts the learned world only: add --set world.backend=learned", err)
        status, _, err = run([tool("valerant_explore"), "--image", text, "--slam", "oracle", *self.LEARNED,
                              "--out", out])
        self.assertEqual(status, USAGE_ERROR, err)
        self.assertIn("has no ground truth for the oracle SLAM", err)
        status, _, err = run([tool("valerant_explore"), "--set", "world.backend=learned", "--set",
                              "world.learned.model=/nonexistent/wm.onnx", "--out", out])
        self.assertEqual(status, 1, err)
        self.assertIn("/nonexistent/wm.onnx: world model file does not exist", err)
        self.assertFalse(os.path.exists(out), "nothing is made before the world loads")

    def test_graph_episode_from_a_screenshot(self):
        # explore.launch with the learned world served by world_model_server from a PNG
        # the engine rendered: the graph is unchanged, the report has no ground truth.
        rendered = os.path.join(self.scratch, "graph_render")
        status, _, err = run([tool("valerant_render"), "--map", "oa_dm1", "--spawn", "0", "--candidate", "q:1",
                              "--out", rendered])
        self.assertEqual(status, 0, err)
        out = os.path.join(self.scratch, "graph")
        port = str(13000 + os.getpid() % 1000)
        launch = subprocess.Popen(["roslaunch", "-p", port, "valerant", "explore.launch", "budget:=2",
                                   "image:=" + os.path.join(rendered, "spawn.png"), "output_dir:=" + out,
                                   "set:=world.backend=learned world.learned.warp=last_frame world.learned.model=" + self.MODEL],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  env=dict(os.environ, ROS_MASTER_URI="http://localhost:" + port),
                                  start_new_session=True)
        try:
            output, _ = launch.communicate(timeout=TIMEOUT)
        finally:
            if launch.poll() is None:
                os.killpg(launch.pid, signal.SIGINT)
                launch.wait(timeout=60)
        self.assertIn("learned world from screenshot", output)
        report = complete_report(out)
        self.assertIsNotNone(report, output)
        self.assertEqual(report["world"], "learned")
        self.assertEqual(report["committed_steps"], 2, output)
        self.assertGreater(report["map_points"], 0, output)
        self.assertIsNone(report["ground_truth"])
        self.assertIsNone(report["map"])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--xml", metavar="DIR", help="write JUnit XML into this folder")
    args, rest = parser.parse_known_args()
    if args.xml:
        import xmlrunner  # Debian's python3-xmlrunner

        runner = xmlrunner.XMLTestRunner(output=args.xml, verbosity=2)
    else:
        runner = unittest.TextTestRunner(verbosity=2)
    program = unittest.main(argv=[sys.argv[0]] + rest, testRunner=runner, exit=False)
    return 0 if program.result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
