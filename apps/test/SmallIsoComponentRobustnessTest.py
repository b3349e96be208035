#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""Tests of the tools under bad input and faults, run by CTest one test method at a time: a full
disk, inputs whose data files outputs could overwrite, truncated and corrupt inputs, termination
signals, empty images, FIFOs, long file names, headers that promise more data than there is.
The full-disk tests mount a small tmpfs, so they need root; elsewhere they are skipped, saying so.

Environment (set by apps/test/CMakeLists.txt):
  SIC_FILTER, SIC_REPORT  the tools
  SIC_PROBE               the SmallIsoComponentCLITestProbe executable (makes test images)
  SIC_SCRATCH             a directory for the tests' files
"""
import gzip
import os
import random
import resource
import signal
import stat
import struct
import subprocess
import time
import unittest
import zlib

from sic_tool_test import ToolTestCase, digest, noise, run, write_nrrd

FILTER = os.environ.get("SIC_FILTER", "")
REPORT = os.environ.get("SIC_REPORT", "")
PROBE = os.environ.get("SIC_PROBE", "")
PHANTOM = os.environ.get("SIC_PHANTOM", "")
# The probe's test images: isovalue 50 separates background from object.
TEST_ISOVALUE = "50"


def write_metaimage(path, sizes, data, compressed=False, data_file="LOCAL", compressed_size=None):
    """A MetaImage file written by hand (int16), its data attached (LOCAL) or in data_file. compressed_size: the
    CompressedDataSize written (by default the compressed data's; "" for none)."""
    payload = zlib.compress(data) if compressed else data
    if compressed_size is None:
        compressed_size = len(payload)
    header = ("ObjectType = Image\nNDims = %d\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
              "CompressedData = %s\n%sDimSize = %s\nElementType = MET_SHORT\nElementDataFile = %s\n") % (
        len(sizes), "True" if compressed else "False",
        "CompressedDataSize = %s\n" % compressed_size if compressed and compressed_size != "" else "",
        " ".join(str(s) for s in sizes), data_file)
    if data_file == "LOCAL":
        with open(path, "wb") as file:
            file.write(header.encode() + payload)
    else:
        with open(path, "w") as file:
            file.write(header)
        with open(os.path.join(os.path.dirname(path), data_file), "wb") as file:
            file.write(payload)


def write_nifti(path, sizes, data, sform=None, magic=b"n+1\0"):
    """A single-file NIfTI-1 image (int16) written by hand: 348-byte header, 4 bytes of extension
    flags, then the voxels at offset 352. sform: (sform_code, the 12 numbers of srow_x, srow_y,
    srow_z), with qform_code 1 and the identity quaternion."""
    header = bytearray(348)
    struct.pack_into("<i", header, 0, 348)
    dims = [len(sizes)] + list(sizes) + [1] * (7 - len(sizes))
    struct.pack_into("<8h", header, 40, *dims)
    struct.pack_into("<hh", header, 70, 4, 16)  # datatype int16, 16 bits per voxel
    struct.pack_into("<8f", header, 76, 1, *([1.0] * 7))
    struct.pack_into("<f", header, 108, 352.0)
    struct.pack_into("<f", header, 112, 1.0)  # scl_slope
    if sform is not None:
        struct.pack_into("<hh", header, 252, 1, sform[0])
        struct.pack_into("<12f", header, 280, *sform[1])
    header[344:348] = magic
    with open(path, "wb") as file:
        file.write(bytes(header) + b"\0" * 4 + data)


def png_chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def png_file(header=None, chunks=None, width=24, height=16):
    """A PNG file written by hand: an 8-bit grey image (a gradient), or the given IHDR body and chunks."""
    if header is None:
        header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    if chunks is None:
        rows = b"".join(b"\0" + bytes((3 * x + 5 * y) % 256 for x in range(width)) for y in range(height))
        chunks = [png_chunk(b"IDAT", zlib.compress(rows)), png_chunk(b"IEND", b"")]
    return b"\x89PNG\r\n\x1a\n" + png_chunk(b"IHDR", header) + b"".join(chunks)


def ball(size):
    """An int16 image of size³ voxels (a ball of 1000 in a background of 0, plus noise of 0 to 3), that gzip
    shrinks to a tenth."""
    noisy = random.Random(3)
    centre, radius = size // 2, size * 5 // 16
    values = [1000 * ((x - centre) ** 2 + (y - centre) ** 2 + (z - centre) ** 2 < radius ** 2) + noisy.randrange(4)
              for z in range(size) for y in range(size) for x in range(size)]
    return struct.pack("<%dh" % len(values), *values)


def truncate_to_half(path):
    with open(path, "rb") as file:
        data = file.read()
    with open(path, "wb") as file:
        file.write(data[:len(data) // 2])


def flip_bytes(path, start, count):
    with open(path, "rb") as file:
        data = bytearray(file.read())
    for i in range(start, start + count):
        data[i] ^= 0xFF
    with open(path, "wb") as file:
        file.write(data)


class SmallIsoComponentRobustnessTest(ToolTestCase):
    def make_image(self, name, pixel_type="int16", dimension=3):
        path = self.path(name)
        self.check(run(PROBE, "make", path, pixel_type, dimension))
        return path

    def noise_image(self, name="noise.nrrd", size=64):
        """An int16 image of random voxels, as large compressed as raw: 2 × size³ bytes."""
        path = self.path(name)
        write_nrrd(path, [size] * 3, noise(2 * size ** 3))
        return path

    def listing(self, directory=None):
        return sorted(os.listdir(directory or self.dir))

    # 1. A full disk: nothing is renamed into place unless it was written completely.

    def test_full_disk_leaves_no_output(self):
        source = self.noise_image()
        for extension in (".mha", ".mhd", ".nii", ".nii.gz", ".nrrd", ".nhdr"):
            with self.subTest(extension=extension):
                disk = self.small_disk("disk" + extension.replace(".", "-"))
                output = os.path.join(disk, "o" + extension)
                self.assertUsageError(run(FILTER, source, output, "--isovalue", "0", "--quiet"), "o" + extension)
                self.assertEqual(self.listing(disk), [], "nothing may be left on the full disk")

    def test_full_disk_for_the_mask_statistics_and_report(self):
        source = self.noise_image(size=32)
        disk = self.small_disk("disk", full=True)
        filtered = [FILTER, source, self.path("out.nrrd"), "--isovalue", "0", "--quiet"]
        cases = [
            (filtered + ["--removed-mask", os.path.join(disk, "mask.mha")], "mask.mha"),
            (filtered + ["--removed-mask", os.path.join(disk, "mask.nii")], "mask.nii"),
            (filtered + ["--stats", os.path.join(disk, "stats.json")], "stats.json"),
            ([REPORT, source, "--isovalue", "0", "--no-surfaces", "--output", os.path.join(disk, "report.csv")],
             "report.csv"),
        ]
        for arguments, name in cases:
            with self.subTest(name=name):
                self.assertUsageError(run(*arguments), name)
                self.assertEqual(self.listing(disk), ["filler"])
                self.assertFalse(os.path.exists(self.path("out.nrrd")))

    def test_full_disk_for_the_plot(self):
        source = self.noise_image(size=32)
        disk = self.small_disk("disk", size="64k")
        result = run(REPORT, source, "--isovalue", "0", "--no-surfaces", "--plot", os.path.join(disk, "plot.png"))
        if "gnuplot" in result.stderr and "not on PATH" in result.stderr:
            self.skipTest("skipped: gnuplot is not installed")
        self.assertUsageError(result, "plot.png")
        self.assertEqual(self.listing(disk), [])

    # 2. No output may write over any file of the input, its data files included.

    def test_outputs_never_write_over_the_inputs_data_files(self):
        data = noise(2 * 8 ** 3)
        detached = self.path("det.nhdr")
        write_nrrd(detached, [8, 8, 8], data, data_file="det.raw")
        gzipped = self.path("gz.nhdr")
        write_nrrd(gzipped, [8, 8, 8], data, encoding="gzip", data_file="victim.raw.gz")
        meta = self.path("meta.mhd")
        write_metaimage(meta, [8, 8, 8], data, compressed=True, data_file="victim2.zraw")
        pictured = self.path("pic.nhdr")
        write_nrrd(pictured, [8, 8, 8], data, data_file="plot.png")
        cases = [
            (FILTER, detached, [self.path("o.nrrd"), "--stats", self.path("det.raw")], "det.raw"),
            (FILTER, detached, [self.path("o.nrrd"), "--removed-mask", self.path("det.raw")], "det.raw"),
            (FILTER, detached, [self.path("det.raw")], "det.raw"),
            (FILTER, gzipped, [self.path("victim.nhdr")], "victim.raw.gz"),
            (FILTER, meta, [self.path("victim2.mhd")], "victim2.zraw"),
            (FILTER, meta, [self.path("o.nrrd"), "--removed-mask", self.path("victim2.mhd")], "victim2.zraw"),
            (REPORT, detached, ["--output", self.path("det.raw")], "det.raw"),
            (REPORT, pictured, ["--plot", self.path("plot.png")], "plot.png"),
        ]
        before = self.listing()
        digests = {name: digest(self.path(name)) for name in before}
        for tool, source, arguments, victim in cases:
            with self.subTest(source=source, arguments=arguments):
                options = ["--quiet"] if tool == FILTER else ["--no-surfaces"]
                result = run(tool, source, *arguments, "--isovalue", "0", *options)
                if tool == REPORT and "gnuplot" in result.stderr and "not on PATH" in result.stderr:
                    continue
                self.assertUsageError(result, "data file of the input image", victim)
                self.assertEqual(self.listing(), before)
                self.assertEqual({name: digest(self.path(name)) for name in before}, digests)

    def test_outputs_whose_files_collide_are_refused(self):
        source = self.make_image("in.nrrd")
        # out.nhdr writes its voxels to out.raw.gz, which is also where the statistics go.
        result = run(FILTER, source, self.path("out.nhdr"), "--isovalue", TEST_ISOVALUE, "--quiet",
                     "--stats", self.path("out.raw.gz"))
        self.assertUsageError(result, "both write", "out.raw.gz")
        self.assertEqual(self.listing(), ["in.nrrd"])

    def test_outputs_never_replace_fifos_devices_or_links_to_them(self):
        source = self.make_image("in.nrrd")
        os.mkfifo(self.path("fifo.json"))
        os.symlink(os.devnull, self.path("null.json"))
        os.mkfifo(self.path("fifo.nrrd"))
        os.symlink(self.path("fifo.nrrd"), self.path("fifo-link.nrrd"))
        filtered = [FILTER, source, self.path("out.nrrd"), "--isovalue", TEST_ISOVALUE, "--quiet"]
        cases = [
            (filtered + ["--stats", self.path("fifo.json")], "it is a FIFO"),
            (filtered + ["--stats", self.path("null.json")], "it is a link to a device"),
            (filtered + ["--removed-mask", self.path("fifo.nrrd")], "it is a FIFO"),
            ([FILTER, source, self.path("fifo-link.nrrd"), "--isovalue", TEST_ISOVALUE, "--quiet"],
             "it is a link to a FIFO"),
            ([REPORT, source, "--isovalue", TEST_ISOVALUE, "--no-surfaces", "--output", self.path("null.json")],
             "it is a link to a device"),
        ]
        before = self.listing()
        for arguments, message in cases:
            with self.subTest(arguments=arguments):
                self.assertUsageError(run(*arguments), message, "expected a regular file or a new path")
                self.assertEqual(self.listing(), before)
                self.assertTrue(os.path.islink(self.path("null.json")))
                self.assertEqual(os.readlink(self.path("null.json")), os.devnull)
                for fifo in ("fifo.json", "fifo.nrrd"):
                    self.assertTrue(stat.S_ISFIFO(os.lstat(self.path(fifo)).st_mode), fifo)

    # 3, 4, 9. Incomplete and corrupt inputs are refused before anything is allocated.

    def test_truncated_inputs_are_refused(self):
        data = noise(2 * 16 ** 3)
        cases = []
        for name, write in [
            ("raw.mha", lambda p: write_metaimage(p, [16] * 3, data)),
            ("zlib.mha", lambda p: write_metaimage(p, [16] * 3, data, compressed=True)),
            ("raw.nrrd", lambda p: write_nrrd(p, [16] * 3, data)),
            ("gzip.nrrd", lambda p: write_nrrd(p, [16] * 3, data, encoding="gzip")),
            ("raw.nii", lambda p: write_nifti(p, [16] * 3, data)),
        ]:
            write(self.path(name))
            cases.append(self.path(name))
        for name in ("itk.nii", "itk.nii.gz", "itk.mha"):
            cases.append(self.make_image(name))
        write_metaimage(self.path("detached.mhd"), [16] * 3, data, data_file="detached.raw")
        cases.append((self.path("detached.mhd"), self.path("detached.raw")))
        for case in cases:
            header, data_file = case if isinstance(case, tuple) else (case, case)
            with self.subTest(input=os.path.basename(data_file)):
                self.check(run(FILTER, header, self.path("whole.nrrd"), "--isovalue", "0", "--quiet"))
                os.remove(self.path("whole.nrrd"))
                truncate_to_half(data_file)
                before = self.listing()
                self.assertUsageError(run(FILTER, header, self.path("o.nrrd"), "--isovalue", "0", "--quiet"),
                                      "incomplete", os.path.basename(header))
                self.assertUsageError(run(REPORT, header, "--isovalue", "0", "--no-surfaces"), "incomplete")
                self.assertEqual(self.listing(), before)

    def test_corrupt_compressed_inputs_are_refused(self):
        data = noise(2 * 32 ** 3)
        gzip_nrrd = self.path("flipped.nrrd")
        # Compressible data, as in real volumes: the flipped bytes still inflate to enough voxels, and ITK's NRRD
        # reader stops before the checksum that would show them wrong.
        write_nrrd(gzip_nrrd, [32] * 3, ball(32), encoding="gzip")
        crc_nrrd = self.path("crc.nrrd")
        write_nrrd(crc_nrrd, [32] * 3, data, encoding="gzip")
        zlib_mha = self.path("adler.mha")
        write_metaimage(zlib_mha, [32] * 3, data, compressed=True)
        nifti = self.make_image("crc.nii.gz")
        # Small enough that its header is read through the whole stream and its checksum.
        small_nifti = self.path("small.nii")
        write_nifti(small_nifti, [4] * 3, noise(2 * 4 ** 3))
        with open(small_nifti, "rb") as source, gzip.open(small_nifti + ".gz", "wb") as target:
            target.write(source.read())
        size = os.path.getsize(gzip_nrrd)
        cases = [
            (gzip_nrrd, size // 2, 2000),  # 2,000 flipped bytes in the second half of the gzip data
            (crc_nrrd, os.path.getsize(crc_nrrd) - 8, 4),  # the gzip trailer's CRC-32 alone
            (zlib_mha, os.path.getsize(zlib_mha) - 4, 4),  # the zlib stream's Adler-32
            (nifti, os.path.getsize(nifti) - 8, 4),
            (small_nifti + ".gz", os.path.getsize(small_nifti + ".gz") - 8, 4),
        ]
        for path, start, count in cases:
            with self.subTest(input=os.path.basename(path)):
                self.check(run(FILTER, path, self.path("whole.nrrd"), "--isovalue", "0", "--quiet"))
                os.remove(self.path("whole.nrrd"))
                flip_bytes(path, start, count)
                before = self.listing()
                self.assertUsageError(run(FILTER, path, self.path("o.nrrd"), "--isovalue", "0", "--quiet"),
                                      "is corrupt: ", os.path.basename(path))
                self.assertEqual(self.listing(), before)

    def test_cut_short_small_compressed_input_is_incomplete(self):
        # Small enough that its header is read through the whole stream: compressed data that end early, or that
        # are not there at all, are incomplete, not corrupt.
        small_nifti = self.path("small.nii")
        write_nifti(small_nifti, [4] * 3, noise(2 * 4 ** 3))
        with open(small_nifti, "rb") as source:
            whole = gzip.compress(source.read())
        for name, length in (("half.nii.gz", len(whole) // 2), ("empty.nii.gz", 0)):
            with self.subTest(input=name):
                with open(self.path(name), "wb") as file:
                    file.write(whole[:length])
                before = self.listing()
                self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "0", "--quiet"),
                                      name, "is incomplete: its compressed data")
                self.assertUsageError(run(REPORT, self.path(name), "--isovalue", "0", "--no-surfaces"), name,
                                      "is incomplete: its compressed data")
                self.assertEqual(self.listing(), before)

    def test_corrupt_png_inputs_are_refused(self):
        # libpng gives up on these while ITK reads the header, and ITK (5.2) cannot recover from it there: each is
        # refused before ITK reads it, whatever the file's name.
        good = png_file()
        rows = b"".join(b"\0" + bytes(24) for _ in range(16))
        image_data = png_chunk(b"IDAT", zlib.compress(rows))
        end = png_chunk(b"IEND", b"")
        grey = struct.pack(">IIBBBBB", 24, 16, 8, 0, 0, 0, 0)
        cases = [
            # What the read fuzzer found: a PNG signature, then bytes that are no chunk.
            ("garbage.nii", good[:8] + b"AL\nx\x9cc`@\x80\x14\x01\x0c\x03\x02ObjectType = Image\n", "four letters"),
            ("garbage.mha", good[:8] + bytes(40), "four letters"),
            ("name.png", png_file(chunks=[png_chunk(b"a1b2", b"x"), image_data, end]), "four letters"),
            ("depth.png", png_file(header=struct.pack(">IIBBBBB", 24, 16, 7, 0, 0, 0, 0)), "bit depth 7"),
            ("colour.png", png_file(header=struct.pack(">IIBBBBB", 24, 16, 8, 5, 0, 0, 0)), "colour type 5"),
            ("interlace.png", png_file(header=struct.pack(">IIBBBBB", 24, 16, 8, 0, 0, 0, 2)), "interlace method 2"),
            ("zero.png", png_file(width=0), "0 x 16 pixels"),
            ("wide.png", png_file(header=struct.pack(">IIBBBBB", 2000000, 1, 8, 0, 0, 0, 0)), "too large"),
            ("short.png", png_file(header=grey[:12]), "12 bytes instead of 13"),
            ("first.png", good[:8] + png_chunk(b"tEXt", b"a\0b") + good[8:], "instead of IHDR"),
            ("twice.png", png_file(chunks=[png_chunk(b"IHDR", grey), image_data, end]), "two IHDR"),
            ("critical.png", png_file(chunks=[png_chunk(b"ZZZZ", b""), image_data, end]), "ZZZZ"),
            ("palette.png", png_file(header=struct.pack(">IIBBBBB", 24, 16, 8, 3, 0, 0, 0)), "palette"),
            ("entries.png", png_file(chunks=[png_chunk(b"PLTE", bytes(4)), image_data, end]), "PLTE"),
            ("early-end.png", png_file(chunks=[end]), "before any image data"),
            ("huge-text.png", png_file(chunks=[png_chunk(b"tEXt", bytes(8000001)), image_data, end]), "tEXt chunk"),
            ("huge-data.png", png_file(chunks=[png_chunk(b"IDAT", bytes(100000)), end]), "IDAT chunk"),
            ("crc.png", good[:-5] + bytes([good[-5] ^ 1]) + good[-4:], "CRC"),
        ]
        # Inflating to too few bytes is found by ITK's reader of the voxels, which recovers: one line without the
        # reader's address, that says what was wrong.
        short_data = png_chunk(b"IDAT", zlib.compress(rows[:100]))
        itk_cases = [("inflate.png", png_file(chunks=[short_data, end]),
                      "its image data (IDAT) do not decode to the image its header describes")]
        for name, data, words in cases + itk_cases:
            with self.subTest(input=name):
                with open(self.path(name), "wb") as file:
                    file.write(data)
                before = self.listing()
                line = self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "9",
                                                 "--quiet"), name, words)
                # The scratch folder's random name may hold "0x" too.
                self.assertNotIn("0x", line.replace(self.dir, ""))
                self.assertNotIn("ITK ERROR", line)
                if name.endswith(".mha"):  # the streaming reader checks it too
                    self.assertUsageError(run(FILTER, self.path(name), self.path("o.mha"), "--isovalue", "9",
                                              "--memory-limit", "1M", "--quiet"), name, words)
                self.assertUsageError(run(REPORT, self.path(name), "--isovalue", "9", "--no-surfaces"), name)
                self.assertEqual(self.listing(), before)
        # The same image, whole, is read whatever its name (ITK reads a PNG file by its content).
        for name in ("good.png", "good.nii", "good.mha"):
            with self.subTest(input=name):
                with open(self.path(name), "wb") as file:
                    file.write(good)
                self.check(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "9", "--quiet"))
                os.remove(self.path("o.nrrd"))
        # Streaming reads MetaImage and NRRD only: a PNG file under a MetaImage name is refused as PNG.
        self.assertUsageError(run(FILTER, self.path("good.mha"), self.path("o.mha"), "--isovalue", "9",
                                  "--memory-limit", "1M", "--quiet"), "good.mha", "cannot stream", "PNG file")

    def test_header_promising_more_data_than_its_file_holds(self):
        # 1700 × 1000 × 1000 int16 voxels are 3.4 GB; the data files hold 10 bytes.
        sizes = [1700, 1000, 1000]
        write_nrrd(self.path("big.nhdr"), sizes, b"0123456789", data_file="big.raw")
        write_metaimage(self.path("big.mhd"), sizes, b"0123456789", data_file="big-meta.raw")
        write_metaimage(self.path("big.mha"), sizes, b"0123456789")
        write_nifti(self.path("big.nii"), sizes, b"0123456789")
        for name, holds in (("big.nhdr", "10 bytes"), ("big.mhd", "10 bytes"), ("big.mha", "10 bytes"),
                            ("big.nii", "10 bytes")):
            with self.subTest(input=name):
                self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "0", "--quiet"),
                                      "incomplete", "holds " + holds, "3400000000 bytes")
        # Refused before the voxels were allocated: no tool run here came near their size.
        peak_kib = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        self.assertLess(peak_kib, 1024 * 1024, "a tool run used %d MiB" % (peak_kib // 1024))

    def test_metaimage_compressed_data_size_must_be_what_its_stream_takes(self):
        # ITK's MetaImage reader inflates CompressedDataSize bytes alone (without the field, the data file from its
        # first byte) and leaves the voxels after them zero: both modes and the report refuse a wrong or missing
        # field, saying what it should be.
        data = ball(32)
        size = len(zlib.compress(data))
        refused = (("half.mha", "LOCAL", size // 2), ("half.mhd", "half.zraw", size // 2),
                   ("double.mha", "LOCAL", 2 * size), ("none.mha", "LOCAL", ""))
        for name, data_file, field in refused:
            write_metaimage(self.path(name), [32] * 3, data, compressed=True, data_file=data_file,
                            compressed_size=field)
        before = self.listing()
        for name, _, _ in refused:
            for options in ([], ["--memory-limit", "64M"]):
                with self.subTest(input=name, options=options):
                    self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "2",
                                              "--quiet", *options), name, "expected 'CompressedDataSize = %d'" % size)
            self.assertUsageError(run(REPORT, self.path(name), "--isovalue", "2", "--no-surfaces"), name,
                                  "CompressedDataSize")
        self.assertEqual(self.listing(), before)
        # Read alike by both modes: the right size, or none before data that start their file.
        write_metaimage(self.path("right.mha"), [32] * 3, data, compressed=True)
        write_metaimage(self.path("whole.mhd"), [32] * 3, data, compressed=True, data_file="whole.zraw",
                        compressed_size="")
        for name in ("right.mha", "whole.mhd"):
            with self.subTest(input=name):
                outputs = [self.path(name + "-memory.nrrd"), self.path(name + "-streamed.nrrd")]
                self.check(run(FILTER, self.path(name), outputs[0], "--isovalue", "2", "--quiet"))
                self.check(run(FILTER, self.path(name), outputs[1], "--isovalue", "2", "--quiet",
                               "--memory-limit", "64M"))
                self.check(run(PROBE, "equal", outputs[0], outputs[1]))
                self.check(run(PROBE, "equal", outputs[0], self.path("right.mha-memory.nrrd")))

    def test_nrrd_encodings_itks_reader_cannot_read_are_refused(self):
        # ITK's NRRD reader has no bzip2 (nor zstd, nor any unknown encoding); both modes and the report say so.
        for encoding in ("bzip2", "bz2", "zstd"):
            write_nrrd(self.path(encoding + ".nrrd"), [4, 3, 2], bytes(48), encoding=encoding)
        before = self.listing()
        for encoding in ("bzip2", "bz2", "zstd"):
            name = encoding + ".nrrd"
            words = (name, "'encoding: %s', which ITK's NRRD reader cannot read" % encoding, "expected raw, gzip")
            for options in ([], ["--memory-limit", "64M"]):
                with self.subTest(input=name, options=options):
                    self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue",
                                              TEST_ISOVALUE, "--quiet", *options), *words)
            self.assertUsageError(run(REPORT, self.path(name), "--isovalue", TEST_ISOVALUE, "--no-surfaces"), *words)
        self.assertEqual(self.listing(), before)

    def test_metaimage_text_voxels_must_be_as_many_numbers_as_the_header_describes(self):
        # ITK's MetaImage reader takes text voxels (BinaryData False) as they come: too few, or a word that is no
        # number, leave the voxels after them as they were, without an error.
        values = [str(value % 100) for value in noise(4 * 5 * 6, seed=3)]
        header = ("ObjectType = Image\nNDims = 3\nBinaryData = False\nDimSize = 6 5 4\nElementType = MET_SHORT\n"
                  "ElementDataFile = LOCAL\n")
        texts = {"whole.mha": values, "short.mha": values[:-5], "word.mha": values[:7] + ["x7"] + values[8:]}
        for name, words in texts.items():
            with open(self.path(name), "w") as file:
                file.write(header + " ".join(words) + "\n")
        before = self.listing()
        for name, words in (("short.mha", ["incomplete", "hold 115 values", "describes 120"]),
                            ("word.mha", ["corrupt", "'x7' as value 8", "expected a number"])):
            with self.subTest(input=name):
                self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", TEST_ISOVALUE,
                                          "--quiet"), name, *words)
                self.assertUsageError(run(REPORT, self.path(name), "--isovalue", TEST_ISOVALUE, "--no-surfaces"),
                                      name, *words)
        self.assertEqual(self.listing(), before)
        self.check(run(FILTER, self.path("whole.mha"), self.path("o.nrrd"), "--isovalue", TEST_ISOVALUE, "--quiet"))

    def test_sizes_that_are_not_whole_numbers_of_at_least_one_are_refused(self):
        # ITK's NRRD reader refuses them with a trace that does not say which field is wrong, its MetaImage
        # reader takes a negative size as a huge one, and its NIfTI reader a size below 1 as 1 (reading part of
        # the voxels as the whole image).
        data = bytes(2 * 4 * 4 * 4)
        write_nrrd(self.path("zero.nrrd"), [0, 4, 4], data)
        write_nrrd(self.path("negative.nrrd"), [4, -4, 4], data)
        write_nrrd(self.path("word.nhdr"), ["4", "four", "4"], data, data_file="word.raw")
        write_metaimage(self.path("negative.mha"), [4, -4, 4], data)
        write_nifti(self.path("negative.nii"), [4, -4, 4], data)
        write_nifti(self.path("zero.nii"), [4, 4, 0], data)
        cases = (("negative.nii", ["'dim[1..dim[0]] = 4 -4 4'", "expected a whole number of voxels, at least 1"]),
                 ("zero.nii", ["is empty", "4 x 4 x 0", "expected at least one voxel along every axis"]),
                 ("zero.nrrd", ["is empty", "0 x 4 x 4", "expected at least one voxel along every axis"]),
                 ("negative.nrrd", ["'sizes: 4 -4 4'", "expected a whole number of voxels, at least 1"]),
                 ("word.nhdr", ["'sizes: 4 four 4'", "expected a whole number of voxels, at least 1"]),
                 ("negative.mha", ["'DimSize = 4 -4 4'", "expected a whole number of voxels, at least 1"]))
        before = self.listing()
        for name, words in cases:
            with self.subTest(input=name):
                line = self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "0.5"),
                                             name, *words)
                self.assertEqual(line.count("expected"), 1, line)
                self.assertUsageError(run(REPORT, self.path(name), "--isovalue", "0.5"), name, *words)
        self.assertEqual(self.listing(), before)

    # 5. Termination signals remove the staged outputs, then end the tool as the signal would.

    def test_termination_signals_remove_staged_outputs(self):
        # Large enough that the tool is still at work when the signal comes.
        source = self.path("large.nrrd")
        write_nrrd(source, [200, 200, 200], noise(2 * 200 ** 3))
        for number in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2,
                       signal.SIGALRM, signal.SIGXCPU):
            with self.subTest(signal=number.name):
                outputs = [self.path("out.nrrd"), self.path("mask.nrrd"), self.path("stats.json")]
                # No core file for SIGQUIT and SIGXCPU, whose default action dumps one.
                process = subprocess.Popen([FILTER, source, outputs[0], "--isovalue", "0", "--removed-mask",
                                            outputs[1], "--stats", outputs[2], "--quiet"],
                                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=self.dir,
                                           preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_CORE, (0, 0)))
                deadline = time.monotonic() + 60
                while len(self.staging_leftovers(self.dir)) < 3 and process.poll() is None:
                    self.assertLess(time.monotonic(), deadline, "the staging directories never appeared")
                    time.sleep(0.01)
                process.send_signal(number)
                _, stderr = process.communicate(timeout=120)
                self.assertEqual(process.returncode, -number, stderr.decode(errors="replace"))
                self.assertEqual(self.staging_leftovers(self.dir), [])
                for output in outputs:
                    self.assertFalse(os.path.exists(output), output)

    def test_a_closed_standard_output_removes_staged_outputs(self):
        """A reader of the progress that goes away (| head) ends the tool with SIGPIPE, which comes to the thread
        that wrote: the staged outputs are removed first, streamed or in memory."""
        source = self.path("large.nrrd")
        write_nrrd(source, [128, 128, 128], noise(2 * 128 ** 3))
        for options in ([], ["--memory-limit", "96M"]):
            with self.subTest(options=options):
                outputs = [self.path("out.mha"), self.path("mask.mha"), self.path("stats.json")]
                process = subprocess.Popen([FILTER, source, outputs[0], "--isovalue", "0", "--removed-mask",
                                            outputs[1], "--stats", outputs[2], "--progress-xml", *options],
                                           stdout=subprocess.PIPE, stderr=subprocess.PIPE)
                for _ in range(2):
                    process.stdout.readline()
                process.stdout.close()
                _, stderr = process.communicate(timeout=120)
                self.assertEqual(process.returncode, -signal.SIGPIPE, stderr.decode(errors="replace"))
                self.assertEqual(self.staging_leftovers(self.dir), [])
                for output in outputs:
                    self.assertFalse(os.path.exists(output), output)

    def test_address_space_limits_fail_with_one_line_and_leave_nothing(self):
        """Under an address-space limit (ulimit -v, as batch systems set), at every point where the run can run out
        (the signal thread, ITK's thread pool, the image, the window): success, or status 1 with one line."""
        if os.environ.get("SIC_SANITIZER", "") == "address":
            print("skipped: AddressSanitizer's shadow memory needs more address space than any limit here")
            self.skipTest("AddressSanitizer build")
        source = self.path("phantom.nrrd")
        self.check(run(PHANTOM, source, "--size", "96"))
        self.check(run(FILTER, source, self.path("reference.nrrd"), "--isovalue", "150", "--quiet"))

        def limited(megabytes):
            def limit():
                resource.setrlimit(resource.RLIMIT_AS, (megabytes << 20, megabytes << 20))
                resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
            return limit

        # Below this limit the dynamic loader fails, before any of the tool's code runs.
        start = 16
        while subprocess.run([FILTER, "--help"], capture_output=True, preexec_fn=limited(start)).returncode != 0:
            start += 4
            self.assertLess(start, 4096, "the tool never started")
        output = self.path("out.nrrd")
        for megabytes in range(start, start + 64, 4):
            for options in ([], ["--memory-limit", "96M"]):
                with self.subTest(megabytes=megabytes, options=options):
                    result = subprocess.run([FILTER, source, output, "--isovalue", "150", "--quiet", *options],
                                            capture_output=True, text=True, preexec_fn=limited(megabytes))
                    self.assertEqual(self.staging_leftovers(self.dir), [])
                    if result.returncode == 0:
                        self.check(run(PROBE, "equal", output, self.path("reference.nrrd")))
                        os.remove(output)
                        continue
                    self.assertEqual(result.returncode, 1, result.stderr)
                    self.assertEqual(len(result.stderr.splitlines()), 1, result.stderr)
                    self.assertFalse(os.path.exists(output))

    # 6. An empty image is refused by both tools.

    def test_empty_image_is_refused(self):
        empty = self.path("empty.mha")
        with open(empty, "w") as file:
            file.write("ObjectType = Image\nNDims = 3\nBinaryData = True\nDimSize = 0 10 10\n"
                       "ElementType = MET_SHORT\nElementDataFile = LOCAL\n")
        self.assertUsageError(run(FILTER, empty, self.path("o.nrrd"), "--isovalue", "0"), "is empty", "0 x 10 x 10")
        self.assertUsageError(run(REPORT, empty, "--isovalue", "0"), "is empty", "0 x 10 x 10")
        self.assertEqual(self.listing(), ["empty.mha"])

    def test_metaimage_field_names_longer_than_metaio_takes_are_refused(self):
        # ITK's MetaImage reader aborts on a field name of 255 characters or more (the fuzzer found it).
        for length, refused in ((254, False), (255, True), (400, True)):
            name = self.path("field-%d.mha" % length)
            with open(name, "wb") as file:
                file.write(("ObjectType = Image\nNDims = 3\n%s = 1\nBinaryData = True\nDimSize = 2 2 2\n"
                            "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" % ("A" * length)).encode())
                file.write(bytes(8))
            result = run(FILTER, name, self.path("o-%d.mha" % length), "--isovalue", "0.5", "--quiet")
            if refused:
                self.assertUsageError(result, "field name of %d characters" % length)
            else:
                self.assertEqual(result.returncode, 0, result.stderr)
        self.assertUsageError(run(REPORT, self.path("field-400.mha"), "--isovalue", "0.5"), "field name of 400")
        self.assertNotIn("o-255.mha", self.listing())
        self.assertNotIn("o-400.mha", self.listing())

    def test_metaimage_data_file_named_like_local_is_a_data_file(self):
        # MetaIO reads its voxels from the header's own file only for LOCAL, Local and local; any other
        # spelling names a data file, which must then be there and complete (the fuzzer found the
        # missing one, on which ITK's MetaImage reader leaks).
        data = bytes(2 * 4 * 4 * 4)
        for spelling in ("LOCAL", "Local", "local"):
            with self.subTest(spelling=spelling):
                source = self.path("attached-%s.mha" % spelling)
                with open(source, "wb") as file:
                    file.write(("ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\n"
                                "ElementDataFile = %s\n" % spelling).encode() + data)
                result = run(FILTER, source, self.path("o-%s.mha" % spelling), "--isovalue", "0.5", "--quiet")
                self.assertEqual(result.returncode, 0, result.stderr)
        source = self.path("detached.mha")
        with open(source, "wb") as file:
            file.write(b"ObjectType = Image\nNDims = 3\nDimSize = 4 4 4\nElementType = MET_SHORT\n"
                       b"ElementDataFile = LOCAl\n" + data)
        self.assertUsageError(run(FILTER, source, self.path("o.mha"), "--isovalue", "0.5"),
                              "LOCAl' does not exist")
        with open(self.path("LOCAl"), "wb") as file:
            file.write(data[:100])
        for tool in ((FILTER, source, self.path("o.mha")), (REPORT, source)):
            self.assertUsageError(run(*tool, "--isovalue", "0.5"), "LOCAl' holds 100 bytes", "describes 128")
        self.assertNotIn("o.mha", self.listing())

    def test_metaimage_headers_without_a_required_field_are_refused(self):
        # ITK's MetaImage reader refuses them saying the file does not exist, and leaks (the fuzzer found it).
        fields = {"NDims": "NDims = 3\n", "DimSize": "DimSize = 4 4 4\n", "ElementType": "ElementType = MET_SHORT\n"}
        for missing in fields:
            with self.subTest(missing=missing):
                source = self.path("no-%s.mha" % missing)
                with open(source, "wb") as file:
                    present = "".join(text for name, text in fields.items() if name != missing)
                    file.write(("ObjectType = Image\n" + present + "ElementDataFile = LOCAL\n").encode() + bytes(128))
                self.assertUsageError(run(FILTER, source, self.path("o.mha"), "--isovalue", "0.5"),
                                      "has no %s field" % missing)
                self.assertUsageError(run(REPORT, source, "--isovalue", "0.5"), "has no %s field" % missing)
        # Without ElementDataFile, MetaIO prints four lines and ITK says the file cannot be read, "Reason: Success".
        with open(self.path("header-only.mha"), "w") as file:
            file.write("ObjectType = Image\n" + "".join(fields.values()))
        for tool in ((FILTER, self.path("header-only.mha"), self.path("o.mha")), (REPORT, self.path("header-only.mha"))):
            self.assertUsageError(run(*tool, "--isovalue", "0.5"), "header ends before ElementDataFile")
        self.assertNotIn("o.mha", self.listing())

    def test_headers_itks_readers_misread_are_refused(self):
        # ITK's MetaImage reader reads a series' files a slice each and leaves the slices of missing or short files
        # as the memory held them; its NIfTI reader takes a single file's vox_offset below 352 as 348 and reads the
        # extension flags as voxels; MetaIO fails on too few sizes or a word that is not a number with lines that
        # name another field.
        data = bytes(range(256)) * (2 * 4 * 4 * 4 // 256) + bytes(2 * 4 * 4 * 4 % 256)
        write_metaimage(self.path("one-file.mhd"), [4, 4, 4], data, data_file="LIST 2D\none.raw")
        os.rename(self.path("LIST 2D\none.raw"), self.path("one.raw"))
        with open(self.path("short.mhd"), "w") as file:
            file.write("ObjectType = Image\nNDims = 3\nDimSize = 4 4 2\nElementType = MET_SHORT\n"
                       "ElementDataFile = LIST\nfirst.raw\nsecond.raw\n")
        with open(self.path("first.raw"), "wb") as file:
            file.write(bytes(2 * 4 * 4 + 6))
        with open(self.path("second.raw"), "wb") as file:
            file.write(bytes(2 * 4 * 4 - 6))
        write_nifti(self.path("offset.nii"), [4, 4, 4], data)
        with open(self.path("offset.nii"), "r+b") as file:
            file.seek(108)
            file.write(struct.pack("<f", 0.0))
        header = "ObjectType = Image\nNDims = 3\nDimSize = %s\nElementType = MET_SHORT\n%sElementDataFile = LOCAL\n"
        with open(self.path("sizes.mha"), "wb") as file:
            file.write((header % ("4 4", "")).encode() + data)
        with open(self.path("spacing.mha"), "wb") as file:
            file.write((header % ("4 4 4", "ElementSpacing = nan 1 1\n")).encode() + data)
        cases = (("one-file.mhd", ["describes 4 data files of a slice each and names 1"]),
                 ("short.mhd", ["data file", "second.raw", "holds 26 bytes", "a slice of 32 bytes"]),
                 ("offset.nii", ["its vox_offset is 0", "expected 352 or more"]),
                 ("sizes.mha", ["'DimSize = 4 4' has 2 sizes for NDims = 3", "expected one size per axis"]),
                 ("spacing.mha", ["'ElementSpacing = nan 1 1'", "expected finite numbers"]))
        before = self.listing()
        for name, words in cases:
            with self.subTest(input=name):
                self.assertUsageError(run(FILTER, self.path(name), self.path("o.nrrd"), "--isovalue", "0.5"),
                                      name, *words)
                self.assertUsageError(run(REPORT, self.path(name), "--isovalue", "0.5"), name, *words)
        self.assertEqual(self.listing(), before)

    def test_nifti_sforms_itks_reader_cannot_decompose_are_refused(self):
        # ITK's NIfTI reader aborts on a sform number that is not finite (the fuzzer found it) and hangs
        # when the matrix's norm overflows single precision.
        data = bytes(2 * 4 * 4 * 4)
        identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0]
        refused = (
            ("nan", 1, identity[:10] + [float("nan"), 0], "(srow_z[2]) is nan"),
            ("inf", 1, [float("-inf")] + identity[1:], "(srow_x[0]) is -inf"),
            ("huge", 1, [3e38, 3e38, 0, 0, 0, 3e38, 0, 0, 0, 0, 3e38, 0], "(srow_x[0]) is 3e+38"),
            ("offset", 2, identity[:7] + [-3e38] + identity[8:], "(srow_y[3]) is -3e+38"),
        )
        for name, code, srow, words in refused:
            with self.subTest(sform=name):
                source = self.path(name + ".nii")
                write_nifti(source, (4, 4, 4), data, sform=(code, srow))
                result = run(FILTER, source, self.path("o-" + name + ".nii"), "--isovalue", "0.5", timeout=60)
                self.assertUsageError(result, words, "at most 1e+18")
                self.assertUsageError(run(REPORT, source, "--isovalue", "0.5", timeout=60), words)
        # Read as before: numbers up to the limit, and a sform that ITK ignores (sform_code 0, or no NIfTI magic).
        accepted = (
            ("limit", 1, [0.9e18, 0, 0, 0, 0, 0.9e18, 0, 0, 0, 0, 0.9e18, 0.9e18], b"n+1\0"),
            ("unused", 0, [float("nan")] * 12, b"n+1\0"),
            ("analyze", 1, [float("nan")] * 12, bytes(4)),
        )
        for name, code, srow, magic in accepted:
            with self.subTest(sform=name):
                source = self.path(name + ".nii")
                write_nifti(source, (4, 4, 4), data, sform=(code, srow), magic=magic)
                result = run(FILTER, source, self.path("o-" + name + ".nrrd"), "--isovalue", "0.5", "--quiet",
                             timeout=60)
                self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual([name for name in self.listing() if name.startswith("o-")],
                         ["o-analyze.nrrd", "o-limit.nrrd", "o-unused.nrrd"])

    # 8. FIFOs, long names, --threads, the plot's extension.

    def test_fifo_input_is_refused(self):
        if not hasattr(os, "mkfifo"):
            self.skipTest("skipped: this platform has no FIFOs")
        fifo = self.path("fifo.nrrd")
        os.mkfifo(fifo)
        self.assertUsageError(run(FILTER, fifo, self.path("o.nrrd"), "--isovalue", "0", timeout=60), "not a regular file")
        self.assertUsageError(run(REPORT, fifo, "--isovalue", "0", timeout=60), "not a regular file")
        # A detached header whose data file is a FIFO.
        os.mkfifo(self.path("fifo.raw"))
        with open(self.path("fifo.nhdr"), "w") as file:
            file.write("NRRD0004\ntype: short\ndimension: 3\nsizes: 4 4 4\nendian: little\nencoding: raw\n"
                       "data file: fifo.raw\n")
        self.assertUsageError(run(FILTER, self.path("fifo.nhdr"), self.path("o.nrrd"), "--isovalue", "0", timeout=60),
                              "fifo.raw", "not a regular file")

    def test_output_names_up_to_the_longest_the_file_system_takes(self):
        source = self.make_image("in.nrrd")
        limit = os.pathconf(self.dir, "PC_NAME_MAX")
        for length in (limit - 11, limit):
            with self.subTest(length=length):
                names = ["o" * (length - 5) + ".nrrd", "m" * (length - 4) + ".mha", "s" * (length - 5) + ".json"]
                paths = [self.path(name) for name in names]
                self.check(run(FILTER, source, paths[0], "--isovalue", TEST_ISOVALUE, "--quiet",
                               "--removed-mask", paths[1], "--stats", paths[2]))
                self.assertEqual(self.listing(), sorted(["in.nrrd"] + names))
                for path in paths:
                    os.remove(path)

    def test_help_states_the_threads_limit(self):
        for tool, arguments in ((FILTER, [self.path("o.nrrd")]), (REPORT, [])):
            with self.subTest(tool=os.path.basename(tool)):
                message = self.assertUsageError(run(tool, self.make_image("in.nrrd"), *arguments, "--isovalue", "0",
                                                    "--threads", "100000"), "too many")
                limit = message.rsplit(" ", 1)[-1]
                help_text = " ".join(self.check(run(tool, "--help")).stdout.split())
                self.assertIn("at most %s (ITK's limit)" % limit, help_text)

    def test_plot_must_be_png(self):
        source = self.make_image("in.nrrd")
        for name in ("plot.jpg", "plot.svg", "plot"):
            with self.subTest(name=name):
                self.assertUsageError(run(REPORT, source, "--isovalue", "0", "--plot", self.path(name)), ".png")
                self.assertEqual(self.listing(), ["in.nrrd"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
