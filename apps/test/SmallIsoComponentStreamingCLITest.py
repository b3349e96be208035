#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""SmallIsoComponentFilter's streaming mode (--memory-limit, or an input larger than the memory it
may use): the same voxels, mask and statistics as the in-memory run, in every format that streams,
within the memory asked for; and its errors.

Environment: SIC_FILTER, SIC_PHANTOM, SIC_PROBE (see SmallIsoComponentCLITest.py), SIC_HAVE_VTK,
SIC_SCRATCH, SIC_SANITIZER (the sanitizer the tools were built with, if any).
"""

import contextlib
import gzip
import json
import os
import re
import subprocess
import sys
import unittest
import zlib

from sic_tool_test import USAGE_ERROR, ToolTestCase, noise, run, write_segmentation

FILTER = os.environ.get("SIC_FILTER", "")
LABEL_FILTER = os.environ.get("SIC_LABEL_FILTER", "")
PHANTOM = os.environ.get("SIC_PHANTOM", "")
PROBE = os.environ.get("SIC_PROBE", "")
HAVE_VTK = os.environ.get("SIC_HAVE_VTK", "0") == "1"
# Under AddressSanitizer the process's resident memory is mostly the sanitizer's (its shadow
# memory and the quarantine that keeps freed blocks): the tests of how much memory the tool
# holds only mean something for a build without it.
MEMORY_UNMEASURABLE = os.environ.get("SIC_SANITIZER", "") == "address"
ISOVALUE = "150"
# The statistics that describe the image (not how the run went).
IMAGE_STATISTICS = ("above", "below", "modified_voxels", "unrepairable_voxels")


def load_json(path):
    with open(path, encoding="utf-8") as file:
        return json.load(file)


class SmallIsoComponentStreamingCLITest(ToolTestCase):
    def phantom(self, size, name="phantom.nrrd", *options):
        path = self.path(name)
        self.check(run(PHANTOM, path, "--size", size, *options))
        return path

    def filtered(self, source, output, *options):
        """Runs the filter with a mask and statistics; returns the statistics."""
        stem = os.path.splitext(output)[0]
        extension = os.path.splitext(output)[1]
        self.check(run(FILTER, source, output, "--isovalue", ISOVALUE, "--max-size", "20", "--removed-mask",
                       stem + "-mask" + extension, "--stats", stem + ".json", "--quiet", *options))
        return load_json(stem + ".json")

    @staticmethod
    def write_line(path, planes):
        """A uint8 NRRD of 512 x 512 x planes voxels of 0 and a line of 200 through all planes: a component of one
        voxel per plane, open to the last plane."""
        plane = bytearray(512 * 512)
        plane[256 * 512 + 256] = 200
        header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 512 512 %d\nendian: little\nencoding: raw\n\n"
        # Plane by plane: a measured child's peak counts the test's own size when that is larger.
        with open(path, "wb") as file:
            file.write((header % planes).encode())
            for _ in range(planes):
                file.write(plane)

    def assertSameImages(self, a, b):
        result = run(PROBE, "equal", a, b)
        self.assertEqual(result.returncode, 0, a + " and " + b + ": " + result.stdout + result.stderr)

    def assertSameStatistics(self, streamed, in_memory):
        for key in IMAGE_STATISTICS:
            self.assertEqual(streamed["statistics"][key], in_memory["statistics"][key], key)
        self.assertEqual(streamed["statistics"]["mode"], "streaming")
        self.assertEqual(in_memory["statistics"]["mode"], "in-memory")

    def test_every_streaming_format_gives_the_in_memory_result(self):
        source = self.phantom("48")
        reference = self.filtered(source, self.path("memory.nrrd"))
        for extension in (".mha", ".mhd", ".nrrd", ".nhdr"):
            for compress in (True, False):
                with self.subTest(extension=extension, compress=compress):
                    output = self.path("streamed-" + ("c" if compress else "r") + extension)
                    options = ["--memory-limit", "512M"] + ([] if compress else ["--no-compression"])
                    streamed = self.filtered(source, output, *options)
                    self.assertSameStatistics(streamed, reference)
                    self.assertSameImages(output, self.path("memory.nrrd"))
                    self.assertSameImages(os.path.splitext(output)[0] + "-mask" + extension, self.path("memory-mask.nrrd"))
                    self.assertEqual(streamed["statistics"]["memory_limit_bytes"], 512 << 20)
                    # The streamed file reads back in the streaming mode too.
                    again = self.filtered(output, self.path("again" + extension), "--memory-limit", "512M")
                    self.assertEqual(again["statistics"]["modified_voxels"], 0)

    def skip_unless_memory_is_measurable(self):
        if MEMORY_UNMEASURABLE:
            print("skipped: built with AddressSanitizer, whose shadow memory and quarantine make up most of "
                  "the resident memory this test measures")
            raise unittest.SkipTest("AddressSanitizer build")

    def test_a_small_limit_streams_in_thin_slabs(self):
        self.skip_unless_memory_is_measurable()
        source = self.phantom("256", "big.mha", "--no-compression")  # 32 MiB of int16 voxels
        reference = self.filtered(source, self.path("memory.mha"), "--no-compression")
        limit = 100 << 20
        streamed = self.filtered(source, self.path("streamed.mha"), "--memory-limit", str(limit), "--no-compression")
        self.assertSameStatistics(streamed, reference)
        self.assertSameImages(self.path("streamed.mha"), self.path("memory.mha"))
        self.assertLess(streamed["statistics"]["slab_planes"], 256)
        # 256^3 voxels are far below the size swept in slabs in memory.
        self.assertEqual(reference["statistics"]["slab_planes"], 0)
        self.assertEqual(reference["statistics"]["mode"], "in-memory")
        self.assertLessEqual(streamed["statistics"]["peak_resident_bytes"], limit)
        for key in ("read_seconds", "write_seconds"):
            self.assertGreaterEqual(streamed["statistics"][key], 0.0)

    def measured_run(self, *arguments):
        """Runs a tool; returns its exit status, its stderr and its own peak resident memory in bytes (measured)."""
        with open(self.path("stderr.txt"), "w+") as stderr:
            process = subprocess.Popen([str(a) for a in arguments], stdout=subprocess.DEVNULL, stderr=stderr)
            _, status, usage = os.wait4(process.pid, 0)
            process.returncode = os.waitstatus_to_exitcode(status)
            stderr.seek(0)
            return process.returncode, stderr.read(), usage.ru_maxrss * 1024

    def assertWithinLimitOrRefused(self, source, limit, *options, slack=1.1):
        """Streams source under limit (a MiB count): the run's measured peak stays within slack times the limit, or
        the tool refuses at once, and then the memory it says it needs is enough."""
        output = self.path("out.mha")
        arguments = [FILTER, source, output, "--isovalue", "128", "--quiet", *options]
        status, stderr, peak = self.measured_run(*arguments, "--memory-limit", "%dM" % limit)
        if status == USAGE_ERROR:
            self.assertEqual(len(stderr.splitlines()), 1, stderr)
            self.assertLessEqual(peak, slack * (limit << 20), "peak %.1f MiB, limit %d MiB" % (peak / 2 ** 20, limit))
            needed = re.search(r"at most about (\d+) MiB", stderr)
            self.assertIsNotNone(needed, stderr)
            self.assertFalse(os.path.exists(output))
            self.assertEqual(self.staging_leftovers(self.path()), [])
            self.assertGreater(int(needed.group(1)), limit, stderr)
            limit = int(needed.group(1))
            status, stderr, peak = self.measured_run(*arguments, "--memory-limit", "%dM" % limit)
        self.assertEqual(status, 0, stderr)
        self.assertLessEqual(peak, slack * (limit << 20), "peak %.1f MiB, limit %d MiB" % (peak / 2 ** 20, limit))
        os.remove(output)

    def test_noisy_volumes_stay_within_the_limit(self):
        """Noise and a checkerboard (every voxel a run and a component of its own) have far more scanline runs
        than smooth volumes: the plan counts them."""
        self.skip_unless_memory_is_measurable()
        header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 128 256 %d\nendian: little\nencoding: raw\n\n"
        with open(self.path("noise.nrrd"), "wb") as file:
            file.write((header % 256).encode() + noise(128 * 256 * 256))
        line, other = bytes([0, 200]) * 64, bytes([200, 0]) * 64
        planes = (line + other) * 128 + (other + line) * 128
        with open(self.path("checker.nrrd"), "wb") as file:
            file.write((header % 32).encode() + planes * 16)
        for name in ("noise.nrrd", "checker.nrrd"):
            for limit in (48, 64):
                with self.subTest(name=name, limit=limit):
                    self.assertWithinLimitOrRefused(self.path(name), limit, "--max-size", "2", "--threads", "1")

    def test_many_runs_of_few_components_are_planned_near_their_peak(self):
        """Stripes have a run at every voxel but only a few long components, as smooth volumes have far more runs
        than components: the memory the tool says it needs is enough and not much more than the run takes."""
        self.skip_unless_memory_is_measurable()
        header = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 384 256 32\nendian: little\nencoding: raw\n\n"
        with open(self.path("stripes.nrrd"), "wb") as file:
            file.write(header.encode() + bytes([0, 200]) * 192 * 256 * 32)
        arguments = [FILTER, self.path("stripes.nrrd"), self.path("out.mha"), "--isovalue", "128", "--max-size", "2",
                     "--threads", "1", "--quiet", "--memory-limit"]
        status, stderr, _ = self.measured_run(*arguments, "1M")
        self.assertEqual(status, USAGE_ERROR, stderr)
        needed = int(re.search(r"at most about (\d+) MiB", stderr).group(1))
        status, stderr, peak = self.measured_run(*arguments, "%dM" % needed)
        self.assertEqual(status, 0, stderr)
        self.assertLessEqual(peak, 1.1 * (needed << 20), "peak %.1f MiB, needs %d MiB" % (peak / 2 ** 20, needed))
        self.assertLessEqual(needed << 20, 1.6 * peak, "peak %.1f MiB, needs %d MiB" % (peak / 2 ** 20, needed))

    def test_the_window_is_never_deeper_than_the_image(self):
        """A K far larger than the image's depth needs no more than the whole image's planes."""
        self.skip_unless_memory_is_measurable()
        source = self.phantom("96")
        self.check(run(FILTER, source, self.path("memory.nrrd"), "--isovalue", ISOVALUE, "--max-size", "100000",
                       "--quiet"))
        status, stderr, peak = self.measured_run(FILTER, source, self.path("streamed.nrrd"), "--isovalue", ISOVALUE,
                                                 "--max-size", "100000", "--quiet", "--memory-limit", "256M")
        self.assertEqual(status, 0, stderr)
        self.assertLessEqual(peak, 256 << 20)
        self.assertSameImages(self.path("streamed.nrrd"), self.path("memory.nrrd"))

    def test_a_window_far_below_its_bound_is_not_refused(self):
        """With K far larger than a plane the window's bound is the whole image, yet the phantom's components
        close within a few planes: a limit the shallowest window fits in is tried and kept, not refused."""
        self.skip_unless_memory_is_measurable()
        source = self.phantom("96")
        self.check(run(FILTER, source, self.path("memory.nrrd"), "--isovalue", ISOVALUE, "--max-size", "100000",
                       "--quiet"))
        arguments = [FILTER, source, self.path("streamed.nrrd"), "--isovalue", ISOVALUE, "--max-size", "100000",
                     "--quiet", "--memory-limit"]
        status, stderr, _ = self.measured_run(*arguments, "1M")
        self.assertEqual(status, USAGE_ERROR, stderr)
        least = int(re.search(r"needs about (\d+) MiB with the shallowest window", stderr).group(1))
        most = int(re.search(r"at most about (\d+) MiB", stderr).group(1))
        self.assertGreater(most, least + 8, stderr)
        status, stderr, peak = self.measured_run(*arguments, "%dM" % least)
        self.assertEqual(status, 0, stderr)
        self.assertLessEqual(peak, 1.1 * (least << 20), "peak %.1f MiB, limit %d MiB" % (peak / 2 ** 20, least))
        self.assertSameImages(self.path("streamed.nrrd"), self.path("memory.nrrd"))

    def test_a_run_that_passes_the_limit_stops_and_leaves_nothing(self):
        """A line of one voxel per plane through the whole image is a small component that stays open to the
        last plane, so the window holds every plane: a limit between the shallowest window and the bound is
        tried, and the run stops when it passes the limit, saying so in one line and leaving no output."""
        self.skip_unless_memory_is_measurable()
        self.write_line(self.path("line.nrrd"), 96)
        output = self.path("out.nrrd")
        arguments = [FILTER, self.path("line.nrrd"), output, "--isovalue", "128", "--max-size", "1000", "--quiet",
                     "--removed-mask", self.path("mask.nrrd"), "--memory-limit"]
        status, stderr, _ = self.measured_run(*arguments, "1M")
        least = int(re.search(r"needs about (\d+) MiB with the shallowest window", stderr).group(1))
        most = int(re.search(r"at most about (\d+) MiB", stderr).group(1))
        limit = least + 4
        self.assertLess(limit + 8, most, stderr)
        status, stderr, peak = self.measured_run(*arguments, "%dM" % limit)
        self.assertEqual(status, USAGE_ERROR, stderr)
        self.assertEqual(len(stderr.splitlines()), 1, stderr)
        self.assertRegex(stderr, r"the run passed it after \d+ of 96 planes")
        self.assertLessEqual(peak, 1.1 * (limit << 20), "peak %.1f MiB, limit %d MiB" % (peak / 2 ** 20, limit))
        self.assertFalse(os.path.exists(output))
        self.assertFalse(os.path.exists(self.path("mask.nrrd")))
        self.assertEqual(self.staging_leftovers(self.path()), [])
        status, stderr, peak = self.measured_run(*arguments, "%dM" % most)
        self.assertEqual(status, 0, stderr)
        self.assertLessEqual(peak, most << 20, "peak %.1f MiB, limit %d MiB" % (peak / 2 ** 20, most))

    def test_limits_near_the_process_size_are_kept_or_refused(self):
        """The process itself (libraries, buffers, threads) holds tens of MiB: a limit near that size is either
        kept, measured, or refused saying what the process itself needs."""
        self.skip_unless_memory_is_measurable()
        source = self.phantom("96")
        for limit in range(32, 64, 4):
            with self.subTest(limit=limit):
                status, stderr, peak = self.measured_run(FILTER, source, self.path("out.mha"), "--isovalue",
                                                         ISOVALUE, "--memory-limit", "%dM" % limit)
                if status == USAGE_ERROR:
                    self.assertEqual(len(stderr.splitlines()), 1, stderr)
                    self.assertIn("the process itself", stderr)
                    continue
                self.assertEqual(status, 0, stderr)
                self.assertLessEqual(peak, limit << 20, "peak %.1f MiB" % (peak / 2 ** 20))

    def test_two_dimensional_images_stream_by_lines(self):
        self.check(run(PROBE, "make", self.path("flat.mha"), "int16", "2"))
        reference = self.filtered(self.path("flat.mha"), self.path("memory.mha"))
        streamed = self.filtered(self.path("flat.mha"), self.path("streamed.nhdr"), "--memory-limit", "256M")
        self.assertSameStatistics(streamed, reference)
        self.assertSameImages(self.path("streamed.nhdr"), self.path("memory.mha"))

    def test_voxels_placed_by_the_header_stream_as_itk_reads_them(self):
        """Headers that put their voxels elsewhere than right after them (MetaImage's HeaderSize,
        NRRD's line skip and byte skip): the streamed run reads the voxels the in-memory run reads,
        not the bytes before or after them."""
        sizes = (9, 8, 7)
        count = sizes[0] * sizes[1] * sizes[2]
        voxels = bytes(200 if value < 90 else 10 for value in noise(count, seed=5))
        garbage = noise(64, seed=6)
        meta = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
                "CompressedData = False\nDimSize = %d %d %d\nElementType = MET_UCHAR\n" % sizes)
        nrrd = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nendian: little\nencoding: raw\n" % sizes
        local = (meta + "HeaderSize = 1000\nElementDataFile = LOCAL\n").encode()
        files = {
            "at.mha": local + garbage + bytes(1000 - len(local) - len(garbage)) + voxels + garbage,
            "end.mha": (meta + "HeaderSize = -1\nElementDataFile = LOCAL\n").encode() + garbage + voxels,
            "lower.mha": (meta + "ElementDataFile = local\n").encode() + voxels,
            "skip.mhd": (meta + "HeaderSize = 7\nElementDataFile = skip.raw\n").encode(),
            "skip.raw": garbage[:7] + voxels + garbage,
            "lines.nhdr": (nrrd + "line skip: 2\nbyte skip: 3\ndata file: lines.raw\n").encode(),
            "lines.raw": b"first\nsecond\n" + garbage[:3] + voxels + garbage,
            "last.nhdr": (nrrd + "byte skip: -1\ndata file: last.raw\n").encode(),
            "last.raw": garbage + voxels,
        }
        for name, content in files.items():
            with open(self.path(name), "wb") as file:
                file.write(content)
        for name in ("at.mha", "end.mha", "lower.mha", "skip.mhd", "lines.nhdr", "last.nhdr"):
            with self.subTest(name=name):
                stem = os.path.splitext(name)[0]
                reference = self.filtered(self.path(name), self.path(stem + "-memory.nrrd"))
                streamed = self.filtered(self.path(name), self.path(stem + "-streamed.nrrd"), "--memory-limit", "512M")
                self.assertSameStatistics(streamed, reference)
                self.assertGreater(reference["statistics"]["modified_voxels"], 0)
                self.assertSameImages(self.path(stem + "-streamed.nrrd"), self.path(stem + "-memory.nrrd"))
                self.assertSameImages(self.path(stem + "-streamed-mask.nrrd"), self.path(stem + "-memory-mask.nrrd"))

    def test_both_modes_accept_and_refuse_the_same_compressed_inputs(self):
        """gzip data in several members (what pigz, bgzip and concatenated gzip files hold) are read alike by
        both modes; compressed data that inflate to more voxels than the header describes, and zlib data where
        gzip data should be, are refused by both."""
        sizes = (24, 20, 16)
        plane = sizes[0] * sizes[1]
        voxels = bytes(200 if value < 90 else 10 for value in noise(plane * sizes[2], seed=5))
        third = len(voxels) // 3
        nrrd = ("NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nendian: little\nencoding: gzip\n\n"
                % sizes).encode()
        meta = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nCompressedData = True\n"
                "CompressedDataSize = %d\nDimSize = %d %d %d\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
        extra = zlib.compress(voxels + voxels[:plane])
        files = {
            "one.nrrd": nrrd + gzip.compress(voxels),
            "two.nrrd": nrrd + gzip.compress(voxels[:third]) + gzip.compress(voxels[third:]),
            "bgzip.nrrd": nrrd + b"".join(gzip.compress(voxels[i:i + third]) for i in range(0, len(voxels), third))
            + gzip.compress(b""),
            "extra.nrrd": nrrd + gzip.compress(voxels + voxels[:plane]),
            "extra.mha": (meta % ((len(extra),) + sizes)).encode() + extra,
            # A zlib stream, not gzip: ITK's NRRD reader would take it as uncompressed voxels.
            "zlib.nrrd": nrrd + zlib.compress(voxels),
        }
        for name, content in files.items():
            with open(self.path(name), "wb") as file:
                file.write(content)
        reference = self.filtered(self.path("one.nrrd"), self.path("reference.nrrd"))
        self.assertGreater(reference["statistics"]["modified_voxels"], 0)
        for name in ("one.nrrd", "two.nrrd", "bgzip.nrrd"):
            for mode, options in (("memory", []), ("streamed", ["--memory-limit", "512M"])):
                with self.subTest(name=name, mode=mode):
                    output = self.path("%s-%s.nrrd" % (os.path.splitext(name)[0], mode))
                    statistics = self.filtered(self.path(name), output, *options)
                    for key in IMAGE_STATISTICS:
                        self.assertEqual(statistics["statistics"][key], reference["statistics"][key], key)
                    self.assertSameImages(output, self.path("reference.nrrd"))
        before = sorted(os.listdir(self.dir))
        for name in ("extra.nrrd", "extra.mha"):
            for options in ([], ["--memory-limit", "512M"]):
                with self.subTest(name=name, options=options):
                    result = run(FILTER, self.path(name), self.path("out.nrrd"), "--isovalue", ISOVALUE, "--quiet",
                                 *options)
                    self.assertUsageError(result, name, "is inconsistent", "expected exactly as many")
        for options in ([], ["--memory-limit", "512M"]):
            with self.subTest(name="zlib.nrrd", options=options):
                result = run(FILTER, self.path("zlib.nrrd"), self.path("out.nrrd"), "--isovalue", ISOVALUE, "--quiet",
                             *options)
                self.assertUsageError(result, "zlib.nrrd", "is not gzip data", "expected")
        self.assertEqual(sorted(os.listdir(self.dir)), before)

    def test_both_modes_read_the_spacing_alike(self):
        """A negative spacing is read as ITK's reader reads it, the positive spacing along a flipped axis, by both
        modes (so --max-volume gives both the same K); a spacing of 0 is refused by both."""
        sizes = (12, 10, 8)
        voxels = bytes(200 if value < 90 else 10 for value in noise(sizes[0] * sizes[1] * sizes[2], seed=6))
        meta = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = %d %d %d\nElementSpacing = %s\n"
                "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
        for name, spacing in (("negative.mha", "1 -2 0.5"), ("zero.mha", "1 0 1")):
            with open(self.path(name), "wb") as file:
                file.write((meta % (sizes + (spacing,))).encode() + voxels)
        for mode, options in (("memory", []), ("streamed", ["--memory-limit", "512M"])):
            with self.subTest(mode=mode):
                self.check(run(FILTER, self.path("negative.mha"), self.path(mode + ".mha"), "--isovalue", ISOVALUE,
                               "--max-volume", "6", "--stats", self.path(mode + ".json"), "--quiet", *options))
                self.assertEqual(load_json(self.path(mode + ".json"))["parameters"]["effective_max_size"], 6)
                result = run(FILTER, self.path("zero.mha"), self.path("zero-out.mha"), "--isovalue", ISOVALUE,
                             *options)
                self.assertUsageError(result, "'" + self.path("zero.mha") + "' has a spacing of 0 along axis 1",
                                      "expected")
                self.assertFalse(os.path.exists(self.path("zero-out.mha")))
        self.assertSameImages(self.path("streamed.mha"), self.path("memory.mha"))
        with open(self.path("memory.mha"), "rb") as memory, open(self.path("streamed.mha"), "rb") as streamed:
            self.assertIn(b"TransformMatrix = 1 0 0 0 -1 0 0 0 1\n", streamed.read())
            self.assertIn(b"TransformMatrix = 1 0 0 0 -1 0 0 0 1\n", memory.read())

    def test_both_modes_refuse_axes_that_do_not_span_the_space(self):
        """A direction matrix of determinant 0 (two axes along one line), which the in-memory mode's reader refuses
        as it reads the voxels, is refused by both modes before anything is written."""
        header = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 4 3 2\n"
                  "TransformMatrix = 1 0 0 1 0 0 0 0 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n")
        with open(self.path("collinear.mha"), "wb") as file:
            file.write(header.encode() + bytes(24))
        for options in ([], ["--memory-limit", "512M"]):
            with self.subTest(options=options):
                result = run(FILTER, self.path("collinear.mha"), self.path("out.mha"), "--isovalue", ISOVALUE,
                             "--quiet", *options)
                self.assertUsageError(result, "collinear.mha", "direction matrix of determinant 0",
                                      "expected axes in independent directions")
        self.assertEqual(sorted(os.listdir(self.dir)), ["collinear.mha"])

    def test_errors_are_one_line_and_write_nothing(self):
        source = self.phantom("16")
        cases = [
            (["--memory-limit", "12Q"], "not a byte count"),
            (["--memory-limit", "0"], "not a byte count"),
            (["--memory-limit", "1K"], "too small"),
        ]
        for options, words in cases:
            with self.subTest(options=options):
                result = run(FILTER, source, self.path("out.mha"), "--isovalue", ISOVALUE, *options)
                self.assertEqual(result.returncode, USAGE_ERROR, result.stderr)
                self.assertIn(words, result.stderr)
                self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
                self.assertFalse(os.path.exists(self.path("out.mha")))
        result = run(FILTER, source, self.path("out.nii"), "--isovalue", ISOVALUE, "--memory-limit", "1G")
        self.assertEqual(result.returncode, USAGE_ERROR)
        self.assertIn("MetaImage", result.stderr)
        if HAVE_VTK:
            result = run(FILTER, source, self.path("out.mha"), "--isovalue", ISOVALUE, "--memory-limit", "1G",
                         "--surface", self.path("s.vtp"))
            self.assertEqual(result.returncode, USAGE_ERROR)
            self.assertIn("whole volume", result.stderr)
        self.assertEqual(sorted(os.listdir(self.dir)), ["phantom.nrrd"])

    @contextlib.contextmanager
    def memory_control_group(self, limit):
        """A control group whose memory limit is \a limit bytes; yields the command prefix that runs a program
        in it. Skips the test where none can be made."""
        group = None
        for root, limit_file in (("/sys/fs/cgroup/memory", "memory.limit_in_bytes"), ("/sys/fs/cgroup", "memory.max")):
            if os.path.exists(os.path.join(root, limit_file if root.endswith("memory") else "cgroup.controllers")):
                candidate = os.path.join(root, "smalliso-test-%d" % os.getpid())
                try:
                    os.mkdir(candidate)
                except OSError:
                    continue
                group = (candidate, limit_file)
                break
        if group is None:
            print("skipped: no memory control group can be made here (needs root and a cgroup memory controller)")
            raise unittest.SkipTest("no memory control group")
        directory, limit_file = group
        try:
            try:
                with open(os.path.join(directory, limit_file), "w") as file:
                    file.write(str(limit))
            except OSError as error:
                print("skipped: the control group's memory limit cannot be set (%s)" % error)
                raise unittest.SkipTest("no memory limit")
            yield ["sh", "-c", 'echo $$ > "$0" && exec "$@"', os.path.join(directory, "cgroup.procs")]
        finally:
            try:
                os.rmdir(directory)
            except OSError:
                pass

    def test_a_volume_larger_than_a_memory_control_group_streams_by_itself(self):
        """The tool in a control group whose memory limit is smaller than the volume: without
        --memory-limit it must see the limit, stream, stay within it and give the in-memory result."""
        self.skip_unless_memory_is_measurable()
        source = self.phantom("512", "large.mhd", "--no-compression")  # 256 MiB of int16 voxels
        reference = self.filtered(source, self.path("memory.mhd"), "--no-compression")
        limit = 192 << 20
        with self.memory_control_group(limit) as inside:
            self.check(run(*inside, FILTER, source, self.path("streamed.mhd"), "--isovalue", ISOVALUE, "--max-size",
                           "20", "--no-compression", "--stats", self.path("streamed.json"), "--quiet"))
        streamed = load_json(self.path("streamed.json"))
        for key in IMAGE_STATISTICS:
            self.assertEqual(streamed["statistics"][key], reference["statistics"][key], key)
        self.assertEqual(streamed["statistics"]["mode"], "streaming")
        self.assertLessEqual(streamed["statistics"]["peak_resident_bytes"], limit)
        self.assertSameImages(self.path("streamed.mhd"), self.path("memory.mhd"))

    def test_a_run_that_streams_by_itself_stops_within_its_share(self):
        """Streaming by itself, the tool watches the three quarters of the available memory it chose, and
        says that it chose them when a run passes them."""
        self.skip_unless_memory_is_measurable()
        self.write_line(self.path("line.nrrd"), 512)
        output = self.path("out.nrrd")
        with self.memory_control_group(96 << 20) as inside:
            result = run(*inside, FILTER, self.path("line.nrrd"), output, "--isovalue", "128", "--max-size", "1000",
                         "--quiet")
        self.assertUsageError(result, "the memory the tool may use (three quarters of the available memory)",
                              "the run passed it after")
        self.assertFalse(os.path.exists(output))

    def test_a_label_map_larger_than_a_memory_control_group_streams_by_itself(self):
        """A label map in a control group too small to filter it in memory streams by itself, within the group's
        limit, and gives the in-memory result."""
        self.skip_unless_memory_is_measurable()
        source = self.path("labels.nrrd")
        write_segmentation(source, [512, 512, 256], 3, period=11)  # 128 MiB of uint16 labels
        stats = {}
        for mode in ("memory", "streamed"):
            stats[mode] = self.path(mode + ".json")
            arguments = [LABEL_FILTER, source, self.path(mode + ".nrrd"), "--max-size", "6", "--removed-mask",
                         self.path(mode + "-mask.nrrd"), "--no-compression", "--stats", stats[mode], "--quiet"]
            if mode == "memory":
                self.check(run(*arguments))
                continue
            limit = 200 << 20
            with self.memory_control_group(limit) as inside:
                self.check(run(*inside, *arguments))
        memory, streamed = load_json(stats["memory"])["statistics"], load_json(stats["streamed"])["statistics"]
        self.assertEqual(streamed["mode"], "streaming")
        self.assertLess(streamed["slab_planes"], 256)
        self.assertLessEqual(streamed["peak_resident_bytes"], limit)
        self.assertGreater(memory["modified_voxels"], 0)
        self.assertEqual(streamed["modified_voxels"], memory["modified_voxels"])
        self.assertSameImages(self.path("streamed.nrrd"), self.path("memory.nrrd"))
        self.assertSameImages(self.path("streamed-mask.nrrd"), self.path("memory-mask.nrrd"))

if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
