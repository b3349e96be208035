# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""What the Python tests of the command-line tools share: running a tool, writing NRRD files by
hand, and a test case whose every test gets its own scratch directory under SIC_SCRATCH, removed
afterwards, and can mount a small (or full) disk there. The test scripts import it from their own
directory."""

import errno
import gzip
import hashlib
import os
import random
import shutil
import struct
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


def digest(path):
    """The SHA-256 of the file at path."""
    with open(path, "rb") as file:
        return hashlib.sha256(file.read()).hexdigest()


def noise(count, seed=1):
    """count bytes that no compressor shrinks."""
    return random.Random(seed).randbytes(count)


def write_nrrd(path, sizes, data, encoding="raw", data_file=None, kind="short"):
    """A NRRD file written by hand: attached data, or a detached header naming data_file (written
    beside it). encoding gzip compresses data; data is written as given otherwise."""
    header = "NRRD0004\ntype: %s\ndimension: %d\nsizes: %s\nendian: little\nencoding: %s\n" % (
        kind, len(sizes), " ".join(str(s) for s in sizes), encoding)
    payload = gzip.compress(data) if encoding == "gzip" else data
    if data_file is None:
        with open(path, "wb") as file:
            file.write(header.encode() + b"\n" + payload)
    else:
        with open(path, "w") as file:
            file.write(header + "data file: %s\n" % data_file)
        with open(os.path.join(os.path.dirname(path), data_file), "wb") as file:
            file.write(payload)


def write_segmentation(path, sizes, seed, period=None):
    """A uint16 NRRD like a segmentation: a disc of six labels in bands that drift from plane to plane on a background
    of 0, and specks of random labels anywhere: one to three voxels along the first axis, or one to seven along the
    last, which make the components whose walks and voters reach furthest across planes. With a period, the planes
    repeat after that many (a large map made quickly)."""
    generator = random.Random(seed)
    width, height = sizes[0], sizes[1]
    depth = sizes[2] if len(sizes) == 3 else 1
    made = min(depth, period or depth)
    voxels = []
    for z in range(made):
        plane = []
        for y in range(height):
            line = [0] * width
            for x in range(width):
                if (x - width // 2) ** 2 + (y - height // 2) ** 2 < (min(width, height) * 2 // 5) ** 2:
                    line[x] = 1 + ((x + 3 * z) // 37 + y // 29) % 6
            plane.append(line)
        voxels.append(plane)
    for _ in range(width * height * made // 400):
        x, y, z = generator.randrange(width - 3), generator.randrange(height), generator.randrange(made)
        label = generator.choice((0, 1, 2, 3, 4, 5, 6, 9))
        along_x = generator.random() < 0.5
        for step in range(generator.randrange(1, 4) if along_x else min(generator.randrange(1, 8), made - z)):
            voxels[z + (0 if along_x else step)][y][x + (step if along_x else 0)] = label
    planes = [b"".join(struct.pack("<%dH" % width, *line) for line in plane) for plane in voxels]
    with open(path, "wb") as file:
        file.write(("NRRD0004\ntype: ushort\ndimension: %d\nsizes: %s\nendian: little\nencoding: raw\n\n" % (
            len(sizes), " ".join(str(size) for size in sizes))).encode())
        for z in range(depth):
            file.write(planes[z % made])


# What a skipped test prints, for CTest's SKIP_REGULAR_EXPRESSION.
NO_TMPFS = "skipped: a full disk is a small tmpfs, and mounting one needs root (and mount); "


class ToolTestCase(unittest.TestCase):
    def setUp(self):
        os.makedirs(SCRATCH, exist_ok=True)
        self.dir = tempfile.mkdtemp(prefix=self.id().split(".")[-1] + "-", dir=SCRATCH)
        self.mounts = []

    def tearDown(self):
        for mount in reversed(self.mounts):
            subprocess.run(["umount", mount], capture_output=True)
        shutil.rmtree(self.dir, ignore_errors=True)

    def small_disk(self, name, size="256k", full=False):
        """A directory of this test's scratch directory on a tmpfs of the given size (unmounted
        afterwards), filled up when full; the test is skipped, saying why, where no tmpfs can be
        mounted."""
        if os.name != "posix" or os.geteuid() != 0:
            self.skipTest(NO_TMPFS + "not running as root")
        path = self.path(name)
        os.mkdir(path)
        result = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=" + size, "tmpfs", path], capture_output=True,
                                text=True)
        if result.returncode != 0:
            self.skipTest(NO_TMPFS + "mount failed: " + result.stderr.strip())
        self.mounts.append(path)
        if full:
            filler = os.open(os.path.join(path, "filler"), os.O_WRONLY | os.O_CREAT, 0o600)
            try:
                while os.write(filler, b"\0" * 4096) > 0:
                    pass
            except OSError as error:
                if error.errno != errno.ENOSPC:
                    raise
            finally:
                os.close(filler)
        return path

    def staging_leftovers(self, directory):
        """The staging directories left in directory."""
        return [name for name in os.listdir(directory) if name.startswith(".SmallIsoComponent-")]

    def assertUsageError(self, result, *words):
        """Exit status 2 and exactly one line on stderr, the tool's, that mentions each of words and no staging
        path."""
        self.assertEqual(result.returncode, USAGE_ERROR, result.stderr)
        lines = result.stderr.splitlines()
        self.assertEqual(len(lines), 1, "expected one line on stderr, got:\n" + result.stderr)
        self.assertTrue(lines[0].startswith("SmallIsoComponent"), lines[0])
        # The scratch folder is named after the test, whose name may hold the words looked for.
        message = lines[0].replace(self.dir, "<scratch>")
        for word in words:
            self.assertIn(word.replace(self.dir, "<scratch>"), message)
        self.assertNotIn(".SmallIsoComponent-", lines[0], "the message names a staging path")
        return lines[0]

    def path(self, *names):
        """A path inside this test's scratch directory."""
        return os.path.join(self.dir, *names)

    def check(self, result, message=""):
        """Asserts that a tool run succeeded, showing its output if not; returns the run."""
        self.assertEqual(result.returncode, 0, message + "\nstdout:\n" + result.stdout + "\nstderr:\n" + result.stderr)
        return result
