# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""What the Python tests of the command-line tools share: running a tool, and a test case
whose every test gets its own scratch directory under SIC_SCRATCH, removed afterwards.
The test scripts import it from their own directory."""

import os
import shutil
import subprocess
import tempfile
import unittest

SCRATCH = os.environ.get("SIC_SCRATCH", tempfile.gettempdir())
# The exit status of every tool for bad arguments or bad input.
USAGE_ERROR = 2


def run(*arguments, env=None, timeout=300):
    """Runs a tool with arguments (converted to strings) and returns the completed process,
    its output as text."""
    return subprocess.run([str(a) for a in arguments], capture_output=True, text=True, timeout=timeout, env=env)


class ToolTestCase(unittest.TestCase):
    def setUp(self):
        os.makedirs(SCRATCH, exist_ok=True)
        self.dir = tempfile.mkdtemp(prefix=self.id().split(".")[-1] + "-", dir=SCRATCH)

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def path(self, *names):
        """A path inside this test's scratch directory."""
        return os.path.join(self.dir, *names)

    def check(self, result, message=""):
        """Asserts that a tool run succeeded, showing its output if not; returns the run."""
        self.assertEqual(result.returncode, 0, message + "\nstdout:\n" + result.stdout + "\nstderr:\n" + result.stderr)
        return result
