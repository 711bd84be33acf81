"""JUnit XML of a unittest run, and the command line both learn/ smoke tests share
(scripts/test runs them with --xml)."""
import argparse
import os
import time
import unittest
import xml.etree.ElementTree as ET

import cv2
import torch


class JUnitResult(unittest.TextTestResult):
    """Also records every test's outcome and time for the JUnit XML."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.cases = []

    def startTest(self, test):
        self.started = time.time()
        super().startTest(test)

    def record(self, test, problem=None):
        # A setUpModule error comes without a test case; write_junit reports it.
        if hasattr(test, "_testMethodName"):
            self.cases.append((test, time.time() - self.started, problem))

    def addSuccess(self, test):
        super().addSuccess(test)
        self.record(test)

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self.record(test, self.failures[-1][1])

    def addError(self, test, err):
        super().addError(test, err)
        self.record(test, self.errors[-1][1])


def write_junit(path, result, seconds, suite_name):
    """Writes the JUnit XML of a JUnitResult (scripts/count_test_results reads it)."""
    failed = [case for case in result.cases if case[2] is not None]
    module_errors = [(test, problem) for test, problem in result.errors if not hasattr(test, "_testMethodName")]
    suite = ET.Element("testsuite", name=suite_name, tests=str(len(result.cases) + len(module_errors)),
                       failures=str(len(failed) + len(module_errors)), errors="0", time="%.3f" % seconds)
    for test, duration, problem in result.cases:
        case = ET.SubElement(suite, "testcase", classname="learn.%s" % type(test).__name__,
                             name=test._testMethodName, time="%.3f" % duration)
        if problem is not None:
            lines = problem.strip().splitlines()
            failure = ET.SubElement(case, "failure", message=lines[-1] if lines else "failed")
            failure.text = problem
    for test, problem in module_errors:
        case = ET.SubElement(suite, "testcase", classname="learn.%s" % suite_name, name=str(test))
        ET.SubElement(case, "failure", message=problem.strip().splitlines()[-1]).text = problem
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def run_smoke_test(module, suite_name):
    """The smoke tests' main(): parses --xml, runs the module's tests on one thread,
    writes the JUnit XML there; returns the exit status."""
    parser = argparse.ArgumentParser(description=module.__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--xml", metavar="PATH", help="write JUnit XML here")
    args = parser.parse_args()
    torch.set_num_threads(1)
    cv2.setNumThreads(1)
    suite = unittest.defaultTestLoader.loadTestsFromModule(module)
    start = time.time()
    result = unittest.TextTestRunner(verbosity=2, resultclass=JUnitResult).run(suite)
    if args.xml:
        write_junit(args.xml, result, time.time() - start, suite_name)
    return 0 if result.wasSuccessful() else 1
