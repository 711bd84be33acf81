#!/usr/bin/python3
"""The install space works on its own: installs the already built tree (cmake --install
with DESTDIR, so nothing is built twice and nothing outside a scratch folder is
written), sources PREFIX/setup.bash in an environment that knows nothing of the source
tree or the build, and runs from there `roslaunch valerant explore.launch` with a
budget of 2, a real tiny run of valerant_render and valerant_explore, the map lists of
valerant_dataset (config/map_sets.yaml), the generated messages from Python and every
other tool's --help.

  test_install.py [--xml DIR]   # DIR: JUnit XML for scripts/count_test_results

Needs a build (VALERANT_BUILD, default .ws/build) and the OpenArena maps."""
import argparse
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("VALERANT_BUILD", os.path.join(ROOT, ".ws", "build"))
TIMEOUT = 300  # seconds: any command that runs longer than this hangs
TOOLS = ["valerant_render", "valerant_explore", "valerant_slam", "valerant_eval", "valerant_export",
         "valerant_dataset", "valerant_bench"]
NODES = ["world_model_server", "policy_arbiter", "map_fusion", "explorer", "run_publisher"]


def cached_install_prefix(build):
    """CMAKE_INSTALL_PREFIX of the configured build: absolute install destinations
    (catkin's setup files) are baked with it, so it is kept and DESTDIR moves it."""
    with open(os.path.join(build, "CMakeCache.txt")) as cache:
        for line in cache:
            if line.startswith("CMAKE_INSTALL_PREFIX:"):
                return line.split("=", 1)[1].strip()
    raise RuntimeError(build + "/CMakeCache.txt: no CMAKE_INSTALL_PREFIX")


def sourced_environment(prefix, home):
    """The environment after `source PREFIX/setup.bash`, started from a bare one."""
    bare = {"HOME": home, "PATH": "/usr/bin:/bin", "LANG": "C.UTF-8"}
    done = subprocess.run(["bash", "-c", 'source "$0/setup.bash" && env -0', prefix], env=bare, cwd=home,
                          capture_output=True, check=True, timeout=TIMEOUT)
    return dict(entry.split("=", 1) for entry in done.stdout.decode().split("\0") if "=" in entry)


class InstallSpace(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        if not os.path.isfile(os.path.join(BUILD, "CMakeCache.txt")):
            raise unittest.SkipTest(BUILD + " is not configured")
        cls.scratch = tempfile.mkdtemp(prefix="valerant_install_")
        stage = os.path.join(cls.scratch, "stage")
        installing = subprocess.run(["cmake", "--install", BUILD], env=dict(os.environ, DESTDIR=stage),
                                    capture_output=True, text=True, timeout=TIMEOUT)
        if installing.returncode != 0:
            raise RuntimeError("cmake --install failed:\n" + installing.stdout[-3000:] + installing.stderr[-3000:])
        cls.prefix = stage + cached_install_prefix(BUILD)
        cls.work = os.path.join(cls.scratch, "work")  # the commands' working directory
        os.makedirs(cls.work)
        cls.env = sourced_environment(cls.prefix, cls.scratch)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.scratch, ignore_errors=True)

    def run_installed(self, args, timeout=TIMEOUT, env=None):
        done = subprocess.run(args, cwd=self.work, env=dict(self.env, PWD=self.work, **(env or {})),
                              capture_output=True, text=True, timeout=timeout)
        return done.returncode, done.stdout, done.stderr

    def test_environment_knows_nothing_of_the_source_tree_or_build(self):
        for name, value in self.env.items():
            self.assertNotIn(os.path.realpath(ROOT), value, name)
            self.assertNotIn(os.path.realpath(BUILD), value, name)

    def test_package_is_found_in_the_install_space(self):
        status, out, err = self.run_installed(["rospack", "find", "valerant"])
        self.assertEqual(status, 0, err)
        self.assertEqual(out.strip(), os.path.join(self.prefix, "share", "valerant"))
        share = out.strip()
        for path in ["package.xml", "nodelet_plugins.xml", "config/valerant.yaml", "config/paper.yaml", "config/map_sets.yaml",
                     "models/depth_prior.onnx", "rviz/valerant.rviz", "launch/explore.launch",
                     "launch/params/explorer.yaml", "msg/Decision.msg", "action/Explore.action"]:
            self.assertTrue(os.path.isfile(os.path.join(share, path)), path)
        self.assertTrue(os.access(os.path.join(share, "launch", "env_loader.sh"), os.X_OK))
        self.assertTrue(os.access(os.path.join(share, "scripts", "plot_eval.py"), os.X_OK))  # valerant_eval's plots
        self.assertTrue(os.path.isfile(os.path.join(self.prefix, "include", "valerant", "config", "package_dir.h")))

    def test_tools_are_on_the_path_and_nodes_where_rosrun_looks(self):
        for name in TOOLS:
            self.assertEqual(shutil.which(name, path=self.env["PATH"]), os.path.join(self.prefix, "bin", name))
        for name in NODES:
            self.assertTrue(os.access(os.path.join(self.prefix, "lib", "valerant", name), os.X_OK), name)

    def test_generated_messages_import_from_python(self):
        status, _, err = self.run_installed(
            ["python3", "-c", "from valerant.msg import ExploreAction, Decision; from valerant.srv import Commit"])
        self.assertEqual(status, 0, err)

    def test_render_a_tiny_rollout(self):
        out = os.path.join(self.work, "render")
        status, stdout, err = self.run_installed(["valerant_render", "--map", "oa_dm1", "--spawn", "0",
                                                  "--candidate", "uw", "--set", "world.width=64",
                                                  "--set", "world.height=48", "--out", out])
        self.assertEqual(status, 0, err)
        self.assertIsInstance(json.loads(stdout.strip().splitlines()[-1]), dict)
        self.assertTrue(os.path.isdir(os.path.join(out, "uw")), os.listdir(out))

    def test_explore_one_step(self):
        out = os.path.join(self.work, "explore")
        status, _, err = self.run_installed(["valerant_explore", "--map", "oa_dm1", "--spawn", "0", "--slam", "oracle",
                                             "--budget", "1", "--out", out])
        self.assertEqual(status, 0, err)
        with open(os.path.join(out, "report.json")) as report:
            self.assertEqual(json.load(report)["tool"], "valerant_explore")

    def test_dataset_reads_the_installed_map_sets(self):
        status, out, err = self.run_installed(["valerant_dataset", "--list-maps"])
        self.assertEqual(status, 0, err)
        self.assertIn("oa_dm1", out)

    def test_every_other_tool_starts_and_answers_help(self):
        for name in ["valerant_slam", "valerant_eval", "valerant_export", "valerant_bench"]:
            status, out, err = self.run_installed([name, "--help"], timeout=60)
            self.assertIn(status, (0, 1, 2), name + ": " + err)  # not killed by a signal, no missing library
            self.assertNotIn("error while loading shared libraries", err, name)
            self.assertRegex(out + err, r"(?i)usage|--help", name)

    def test_roslaunch_explore_with_a_budget_of_two(self):
        with socket.socket() as probe:
            probe.bind(("localhost", 0))
            port = probe.getsockname()[1]
        out = os.path.join(self.work, "launch")
        status, stdout, err = self.run_installed(
            ["roslaunch", "-p", str(port), "valerant", "explore.launch", "budget:=2", "output_dir:=" + out],
            env={"ROS_MASTER_URI": "http://localhost:%d" % port})
        self.assertEqual(status, 0, (stdout + err)[-4000:])
        with open(os.path.join(out, "report.json")) as report:
            self.assertGreaterEqual(json.load(report)["committed_steps"], 1)


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
