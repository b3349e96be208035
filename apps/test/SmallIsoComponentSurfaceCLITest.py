#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""Tests of the tools' isosurface options (--surface, --surface-before, --render, the
report's surface piece counts), run by CTest one test method at a time. Every test is
skipped, saying why, when the tools were built without VTK.

Environment (set by apps/test/CMakeLists.txt):
  SIC_FILTER, SIC_LABEL_FILTER, SIC_PHANTOM, SIC_PROBE, SIC_REPORT  the tools and the CLI test probe
  SIC_HAVE_VTK  1 when the tools were built with VTK
  SIC_SCRATCH   a directory for the tests' files
"""
import csv
import io
import json
import os
import struct
import sys
import unittest
import zlib

import sic_tool_test
from sic_tool_test import USAGE_ERROR, ToolTestCase

FILTER = os.environ.get("SIC_FILTER", "")
LABEL_FILTER = os.environ.get("SIC_LABEL_FILTER", "")
PHANTOM = os.environ.get("SIC_PHANTOM", "")
PROBE = os.environ.get("SIC_PROBE", "")
REPORT = os.environ.get("SIC_REPORT", "")
HAVE_VTK = os.environ.get("SIC_HAVE_VTK", "0") == "1"
PHANTOM_ISOVALUE = "150"
NO_VTK = "skipped: the tools were built without VTK (install libvtk9-dev, or run scripts/setup.sh, and reconfigure)"




def run(*arguments, env=None):
    # Rendering starts a virtual display and draws four panels: allow it more time.
    return sic_tool_test.run(*arguments, env=env, timeout=600)


def load_json(path):
    with open(path, encoding="utf-8") as file:
        return json.load(file)


def read_png(path):
    """Width, height and rows of RGB pixels of an 8-bit RGB or RGBA PNG."""
    with open(path, "rb") as file:
        data = file.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(path + " is not a PNG")
    position = 8
    idat = b""
    width = height = channels = None
    while position < len(data):
        (length,) = struct.unpack(">I", data[position:position + 4])
        kind = data[position + 4:position + 8]
        body = data[position + 8:position + 8 + length]
        position += 12 + length
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            if depth != 8 or colour not in (2, 6):
                raise ValueError("unexpected PNG format: depth %d colour type %d" % (depth, colour))
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw = zlib.decompress(idat)
    stride = width * channels
    rows = []
    previous = bytearray(stride)
    offset = 0
    for _ in range(height):
        kind = raw[offset]
        line = bytearray(raw[offset + 1:offset + 1 + stride])
        offset += 1 + stride
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            upper_left = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + ((left + up) >> 1)) & 255
            elif kind == 4:
                p = left + up - upper_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
                predictor = left if pa <= pb and pa <= pc else (up if pb <= pc else upper_left)
                line[i] = (line[i] + predictor) & 255
        rows.append([tuple(line[i:i + 3]) for i in range(0, stride, channels)])
        previous = line
    return width, height, rows


def is_red(pixel):
    r, g, b = pixel
    return r > 80 and r > 2 * g and r > 2 * b


def is_blue(pixel):
    r, g, b = pixel
    return b > 80 and b > 1.5 * r and b > 1.3 * g


def is_surface(pixel):
    r, g, b = pixel
    return r > 60 and 0.85 * r < g <= r and 0.7 * r < b < 0.93 * r

# A uint8 label map of two boxes, labels 3 and 5, that share a face, on background 0, with single-voxel islands of
# each label in the background and one voxel of label 5 inside the box of 3. Every island is at least one voxel away
# from everything else, so each is a piece of its own, as is the cavity the voxel of 5 leaves in the surface of 3;
# the boxes touch, but each label has its own surface.
LABEL_SIZE = (24, 20, 20)
LABEL_BOXES = {3: ((2, 9), (2, 18), (2, 18)), 5: ((9, 22), (9, 18), (9, 18))}
LABEL_ISLANDS = {3: [(12, 3, 3), (16, 3, 6)], 5: [(18, 3, 3), (20, 5, 12), (12, 14, 4)]}
SPECK_OF_5_IN_3 = (5, 9, 9)


def write_label_map(path):
    x_size, y_size, z_size = LABEL_SIZE
    voxels = bytearray(x_size * y_size * z_size)

    def put(point, label):
        x, y, z = point
        voxels[x + x_size * (y + y_size * z)] = label

    for label, (xs, ys, zs) in LABEL_BOXES.items():
        for z in range(*zs):
            for y in range(*ys):
                for x in range(*xs):
                    put((x, y, z), label)
    for label, islands in LABEL_ISLANDS.items():
        for point in islands:
            put(point, label)
    put(SPECK_OF_5_IN_3, 5)
    sic_tool_test.write_nrrd(path, LABEL_SIZE, bytes(voxels), kind="uchar")


def expected_label_pieces():
    """Surface pieces per label before filtering with K >= 1: the box, the islands, and for 3 the cavity around
    the voxel of 5 (a piece of 5 too); afterwards only the boxes."""
    return {"3": 1 + len(LABEL_ISLANDS[3]) + 1, "5": 1 + len(LABEL_ISLANDS[5]) + 1}


def ply_face_colours(path):
    """The (red, green, blue) of every face of a binary little-endian PLY file as VTK writes it."""
    sizes = {"char": 1, "uchar": 1, "short": 2, "ushort": 2, "int": 4, "uint": 4, "float": 4, "double": 8}
    formats = {"uchar": "B", "int": "i", "uint": "I"}
    with open(path, "rb") as file:
        data = file.read()
    header, _, body = data.partition(b"end_header\n")
    elements = []
    for line in header.decode("ascii").splitlines():
        words = line.split()
        if words[:1] == ["element"]:
            elements.append((words[1], int(words[2]), []))
        elif words[:1] == ["property"]:
            elements[-1][2].append(words[1:])
    offset, colours = 0, []
    for name, count, properties in elements:
        for _ in range(count):
            values = {}
            for prop in properties:
                if prop[0] == "list":
                    (n,) = struct.unpack_from("<" + formats[prop[1]], body, offset)
                    offset += sizes[prop[1]] + n * sizes[prop[2]]
                else:
                    if prop[0] in formats:
                        (values[prop[1]],) = struct.unpack_from("<" + formats[prop[0]], body, offset)
                    offset += sizes[prop[0]]
            if name == "face":
                colours.append((values["red"], values["green"], values["blue"]))
    assert offset == len(body), "PLY body size"
    return colours


def obj_faces(path):
    with open(path, encoding="ascii") as file:
        return sum(1 for line in file if line.startswith("f "))


def is_label_3(pixel):
    r, g, b = pixel  # the palette's teal, entry 3
    return g > 60 and g > 1.25 * r and b > 1.25 * r


def is_label_5(pixel):
    r, g, b = pixel  # the palette's yellow, entry 5
    return r > 80 and g > 0.65 * r and b < 0.6 * g


class SmallIsoComponentSurfaceCLITest(ToolTestCase):
    def setUp(self):
        if not HAVE_VTK:
            self.skipTest(NO_VTK)
        super().setUp()

    def phantom(self, size="48"):
        path = self.path("phantom.nrrd")
        self.check(run(PHANTOM, path, "--size", size))
        return path

    def panels(self, picture):
        """The pixels of the four panels of a complete 1600 × 1200 picture: top left, top right, bottom left,
        bottom right."""
        with open(picture, "rb") as file:
            self.assertEqual(file.read()[-12:], b"\0\0\0\0IEND\xaeB`\x82", "a complete PNG ends with IEND")
        width, height, rows = read_png(picture)
        self.assertEqual((width, height), (1600, 1200))
        half_w, half_h = width // 2, height // 2
        return [[pixel for row in rows[top:top + half_h] for pixel in row[left:left + half_w]]
                for top in (0, half_h) for left in (0, half_w)]

    def stl_triangles(self, path):
        with open(path, "rb") as file:
            data = file.read()
        (count,) = struct.unpack("<I", data[80:84])
        self.assertEqual(len(data), 84 + 50 * count, "binary STL size")
        return count

    def test_surface_files_in_every_format(self):
        phantom = self.phantom()
        counts = {}
        for extension in (".vtp", ".stl", ".ply", ".obj"):
            after = self.path("after" + extension)
            before = self.path("before" + extension)
            stats = self.path("stats" + extension + ".json")
            self.check(run(FILTER, phantom, self.path("out" + extension + ".nrrd"), "--isovalue", PHANTOM_ISOVALUE,
                           "--surface", after, "--surface-before", before, "--stats", stats, "--quiet"))
            for path in (after, before):
                with open(path, "rb") as file:
                    head = file.read(200)
                if extension == ".vtp":
                    self.assertIn(b"<VTKFile", head)
                    self.assertIn(b'type="PolyData"', head)
                elif extension == ".ply":
                    self.assertTrue(head.startswith(b"ply\n"), head[:20])
                elif extension == ".obj":
                    with open(path, encoding="ascii", errors="replace") as file:
                        kinds = {line.split(" ", 1)[0] for line in file if line.strip()}
                    self.assertTrue({"v", "f"} <= kinds, kinds)
            report = load_json(stats)
            statistics = report["statistics"]
            counts[extension] = (statistics["surface_components_before"], statistics["surface_components_after"])
            self.assertEqual(report["outputs"]["surface"], after)
            self.assertEqual(report["outputs"]["surface_before"], before)
        # The phantom has specks and bubbles: filtering removes pieces, the same in every run.
        self.assertEqual(len(set(counts.values())), 1, counts)
        before_pieces, after_pieces = counts[".vtp"]
        self.assertGreater(before_pieces, after_pieces)
        self.assertGreaterEqual(after_pieces, 1)
        self.assertLess(self.stl_triangles(self.path("after.stl")), self.stl_triangles(self.path("before.stl")))

    def test_surface_needs_3d_and_a_surface_extension(self):
        image2d = self.path("slice.nrrd")
        self.check(run(PROBE, "make", image2d, "int16", 2))
        cases = [
            ([image2d, self.path("o.nrrd"), "--isovalue", "50", "--surface", self.path("s.vtp")], "3-D"),
            ([self.phantom(), self.path("o.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--surface", self.path("s.vtk")],
             ".vtp"),
            ([self.path("phantom.nrrd"), self.path("o.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--render",
              self.path("r.jpg")], ".png"),
        ]
        for arguments, expected in cases:
            before = sorted(os.listdir(self.dir))
            result = run(FILTER, *arguments)
            self.assertEqual(result.returncode, USAGE_ERROR, result.stderr)
            self.assertIn(expected, result.stderr)
            self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
            self.assertEqual(sorted(os.listdir(self.dir)), before, "nothing may be written")

    def test_render_four_panels_headless(self):
        phantom = self.phantom()
        picture = self.path("panels.png")
        stats = self.path("stats.json")
        environment = dict(os.environ)
        environment.pop("DISPLAY", None)  # no display: the tool starts Xvfb itself
        self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--render", picture,
                       "--stats", stats, "--quiet", env=environment))
        panels = self.panels(picture)
        counts = [{"red": sum(map(is_red, p)), "blue": sum(map(is_blue, p)), "surface": sum(map(is_surface, p))}
                  for p in panels]
        message = str(counts)
        # Original and filtered: the surface, no removed pieces.
        for panel in (0, 1):
            self.assertGreater(counts[panel]["surface"], 1000, message)
            self.assertEqual(counts[panel]["red"], 0, message)
            self.assertEqual(counts[panel]["blue"], 0, message)
        # Removed only: specks and bubbles, no surface.
        self.assertGreater(counts[2]["red"], 20, message)
        self.assertGreater(counts[2]["blue"], 20, message)
        self.assertEqual(counts[2]["surface"], 0, message)
        # Filtered and removed together: the surface and the specks (bubbles show through it).
        self.assertGreater(counts[3]["surface"], 1000, message)
        self.assertGreater(counts[3]["red"], 20, message)
        self.assertGreater(counts[3]["blue"], 0, message)
        # The original and the filtered surface differ (the specks were part of the original).
        self.assertNotEqual(panels[0], panels[1])
        statistics = load_json(stats)["statistics"]
        self.assertGreater(statistics["surface_components_before"], statistics["surface_components_after"])
        self.assertGreater(statistics["removed_surface_components"], 0)

    def test_render_without_display_or_xvfb_is_refused(self):
        phantom = self.phantom()
        environment = dict(os.environ)
        environment.pop("DISPLAY", None)
        environment["PATH"] = self.path("no-programs-here")
        output = self.path("out.nrrd")
        result = run(FILTER, phantom, output, "--isovalue", PHANTOM_ISOVALUE, "--render", self.path("r.png"),
                     env=environment)
        self.assertEqual(result.returncode, USAGE_ERROR, result.stderr)
        self.assertIn("Xvfb", result.stderr)
        self.assertEqual(sorted(os.listdir(self.dir)), ["phantom.nrrd"], "nothing may be written")

    def test_full_disk_for_surfaces_and_rendering(self):
        # Some writers do not notice (PLY, OBJ), others print VTK's dump or name the staging path.
        phantom = self.phantom()
        disk = self.small_disk("disk", size="32k")
        for option, name in (("--surface", "s.vtp"), ("--surface", "s.stl"), ("--surface", "s.ply"),
                             ("--surface", "s.obj"), ("--surface-before", "b.vtp"), ("--render", "r.png")):
            with self.subTest(name=name):
                result = run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--quiet",
                             option, os.path.join(disk, name))
                self.assertUsageError(result, os.path.join(disk, name))
                self.assertEqual(os.listdir(disk), [], "nothing may be left on the full disk")
                self.assertFalse(os.path.exists(self.path("out.nrrd")))

    def test_surfaces_never_write_over_the_inputs_data_files(self):
        surface_input, picture_input = self.path("in.nhdr"), self.path("pic.nhdr")
        voxels = sic_tool_test.noise(2 * 16 ** 3)
        sic_tool_test.write_nrrd(surface_input, [16, 16, 16], voxels, data_file="s.vtp")
        sic_tool_test.write_nrrd(picture_input, [16, 16, 16], voxels, data_file="r.png")
        digests = {name: sic_tool_test.digest(self.path(name)) for name in ("s.vtp", "r.png")}
        for source, option, target in ((surface_input, "--surface", "s.vtp"),
                                       (surface_input, "--surface-before", "s.vtp"),
                                       (picture_input, "--render", "r.png")):
            with self.subTest(option=option):
                result = run(FILTER, source, self.path("out.nrrd"), "--isovalue", "0", "--quiet", option,
                             self.path(target))
                self.assertUsageError(result, "data file of the input image", target)
                self.assertFalse(os.path.exists(self.path("out.nrrd")))
        self.assertEqual({name: sic_tool_test.digest(self.path(name)) for name in digests}, digests)

    def test_label_surface_pieces_per_label(self):
        labels = self.path("labels.nrrd")
        write_label_map(labels)
        expected = expected_label_pieces()
        for tool, extra in ((LABEL_FILTER, []), (FILTER, ["--labels"])):
            with self.subTest(tool=os.path.basename(tool)):
                after, before, stats = self.path("after.vtp"), self.path("before.vtp"), self.path("stats.json")
                result = run(tool, labels, self.path("out.nrrd"), *extra, "--max-size", "5", "--surface", after,
                             "--surface-before", before, "--stats", stats)
                self.check(result)
                statistics = load_json(stats)["statistics"]
                for label, pieces in expected.items():
                    entry = statistics["labels"][label]
                    self.assertEqual(entry["surface_components_before"], pieces, label)
                    self.assertEqual(entry["surface_components_after"], 1, label)
                    self.assertEqual(entry["removed_surface_components"], pieces - 1, label)
                    self.assertIn("%s: %d -> 1;" % (label, pieces), result.stdout)
                # The background has no surface.
                self.assertNotIn("surface_components_before", statistics["labels"]["0"])
                self.assertEqual(statistics["surface_components_before"], sum(expected.values()))
                self.assertEqual(statistics["surface_components_after"], len(LABEL_BOXES))
                self.assertEqual(statistics["removed_surface_components"],
                                 sum(expected.values()) - len(LABEL_BOXES))
                for path in (after, before):
                    with open(path, "rb") as file:
                        header = file.read(4096)
                    self.assertIn(b'Name="label"', header, path)
                    self.assertIn(b'Name="colour"', header, path)

    def test_label_surfaces_in_every_format(self):
        labels = self.path("labels.nrrd")
        write_label_map(labels)
        triangles = {}
        for extension in (".stl", ".ply", ".obj"):
            with self.subTest(extension=extension):
                after, before = self.path("after" + extension), self.path("before" + extension)
                self.check(run(LABEL_FILTER, labels, self.path("out" + extension + ".nrrd"), "--max-size", "5",
                               "--surface", after, "--surface-before", before, "--quiet"))
                if extension == ".stl":
                    triangles[extension] = (self.stl_triangles(before), self.stl_triangles(after))
                elif extension == ".ply":
                    colours = {path: ply_face_colours(path) for path in (before, after)}
                    triangles[extension] = tuple(len(colours[path]) for path in (before, after))
                    # Each face has its label's colour: the palette's entries 3 and 5, both labels in both files.
                    for path in (before, after):
                        self.assertEqual(set(colours[path]), {(118, 183, 178), (237, 201, 72)}, path)
                else:
                    triangles[extension] = tuple(obj_faces(path) for path in (before, after))
        # Every format holds every label's triangles, the same ones; filtering removes some.
        self.assertEqual(len(set(triangles.values())), 1, triangles)
        self.assertGreater(*triangles[".stl"])

    def test_label_surface_failure_writes_nothing(self):
        labels = self.path("labels.nrrd")
        write_label_map(labels)
        disk = self.small_disk("disk", size="32k", full=True)
        for option, name in (("--surface", "s.vtp"), ("--surface-before", "b.vtp"), ("--render", "r.png")):
            with self.subTest(name=name):
                result = run(LABEL_FILTER, labels, self.path("out.nrrd"), "--quiet", "--stats",
                             self.path("stats.json"), "--removed-mask", self.path("mask.nrrd"), option,
                             os.path.join(disk, name))
                self.assertUsageError(result, os.path.join(disk, name))
                self.assertEqual(os.listdir(disk), ["filler"], "nothing may be left on the full disk")
                self.assertEqual(sorted(os.listdir(self.dir)), ["disk", "labels.nrrd"], "nothing may be written")

    def test_label_render_colours_each_label(self):
        labels = self.path("labels.nrrd")
        write_label_map(labels)
        picture = self.path("panels.png")
        environment = dict(os.environ)
        environment.pop("DISPLAY", None)  # no display: the tool starts Xvfb itself
        self.check(run(LABEL_FILTER, labels, self.path("out.nrrd"), "--max-size", "5", "--render", picture,
                       "--quiet", env=environment))
        counts = [{"3": sum(map(is_label_3, pixels)), "5": sum(map(is_label_5, pixels)),
                   "plain": sum(map(is_surface, pixels)), "red": sum(map(is_red, pixels))}
                  for pixels in self.panels(picture)]
        message = str(counts)
        # Every panel shows both labels in their own colours, none in the scalar surface's colours; the removed
        # pieces (islands of both labels) are small, the boxes large.
        for panel in range(4):
            self.assertGreater(counts[panel]["3"], 10, message)
            self.assertGreater(counts[panel]["5"], 10, message)
            self.assertEqual(counts[panel]["plain"], 0, message)
            self.assertEqual(counts[panel]["red"], 0, message)
        for panel in (0, 1):
            self.assertGreater(counts[panel]["3"], 10 * counts[2]["3"], message)
            self.assertGreater(counts[panel]["5"], 10 * counts[2]["5"], message)

    def test_report_counts_match_the_filter(self):
        phantom = self.phantom()
        report_path = self.path("report.json")
        self.check(run(REPORT, phantom, "--isovalue", PHANTOM_ISOVALUE, "--isovalue", "300", "--sizes", "0,5,20",
                       "--format", "json", "--output", report_path))
        report = load_json(report_path)
        for row in report["rows"]:
            isovalue = row["isovalue"]
            filtered = row["filtered"]
            self.assertEqual(filtered["side"], "both")
            for entry in filtered["by_size"]:
                stats = self.path("stats-%s-%d.json" % (isovalue, entry["max_size"]))
                self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", repr(isovalue), "--max-size",
                               entry["max_size"], "--surface", self.path("s.vtp"), "--surface-before",
                               self.path("b.vtp"), "--stats", stats, "--quiet"))
                statistics = load_json(stats)["statistics"]
                self.assertEqual(row["surface_components_before"], statistics["surface_components_before"])
                self.assertEqual(entry["surface_components_after"], statistics["surface_components_after"])
                self.assertEqual(entry["removed_components"],
                                 statistics["above"]["removed_components"] + statistics["below"]["removed_components"])
                self.assertEqual(entry["modified_voxels"], statistics["modified_voxels"])
                if entry["max_size"] == 0:
                    self.assertEqual(entry["surface_components_after"], row["surface_components_before"])
        self.assertGreater(report["rows"][0]["surface_components_before"],
                           report["rows"][0]["filtered"]["by_size"][-1]["surface_components_after"])

    def test_report_surface_columns_in_every_format(self):
        phantom = self.phantom("32")
        arguments = ["--isovalue", PHANTOM_ISOVALUE, "--isovalue", "120", "--sizes", "1,20"]
        report = json.loads(self.check(run(REPORT, phantom, "--format", "json", *arguments)).stdout)
        row = report["rows"][0]
        self.assertEqual(list(row), ["isovalue", "active_cubes", "total_components", "above", "below",
                                     "surface_components_before", "filtered"])
        self.assertEqual(list(row["filtered"]), ["side", "by_size"])
        self.assertEqual(list(row["filtered"]["by_size"][0]),
                         ["max_size", "removed_components", "modified_voxels", "surface_components_after"])
        lines = list(csv.DictReader(io.StringIO(self.check(run(REPORT, phantom, "--format", "csv",
                                                               *arguments)).stdout)))
        self.assertEqual(len(lines), 2 * 3 * 2)  # isovalues x (above, below, both) x sizes
        for line in lines:
            row = next(r for r in report["rows"] if r["isovalue"] == float(line["isovalue"]))
            self.assertEqual(int(line["surface_components_before"]), row["surface_components_before"])
            if line["side"] == "both":
                entry = next(e for e in row["filtered"]["by_size"] if e["max_size"] == int(line["max_size"]))
                self.assertEqual(int(line["surface_components_after"]), entry["surface_components_after"])
                self.assertEqual(int(line["removed_components"]), entry["removed_components"])
                self.assertEqual(int(line["modified_voxels"]), entry["modified_voxels"])
            else:
                self.assertEqual(line["surface_components_after"], "")
        markdown = self.check(run(REPORT, phantom, *arguments)).stdout
        table = [line for line in markdown.splitlines() if line.startswith("| ") and line[2].isdigit()]
        self.assertEqual(len(table), 4)
        for line in table:
            cells = [cell.strip() for cell in line.strip("|").split("|")]
            row = next(r for r in report["rows"] if r["isovalue"] == float(cells[0]))
            entry = next(e for e in row["filtered"]["by_size"] if e["max_size"] == int(cells[5]))
            self.assertEqual([int(c) for c in cells[-3:]], [entry["removed_components"],
                                                            row["surface_components_before"],
                                                            entry["surface_components_after"]])

    def test_report_without_surfaces(self):
        phantom = self.phantom("24")
        with_surfaces = self.check(run(REPORT, phantom, "--isovalue", PHANTOM_ISOVALUE, "--format", "json")).stdout
        without = self.check(run(REPORT, phantom, "--isovalue", PHANTOM_ISOVALUE, "--format", "json",
                                 "--no-surfaces")).stdout
        self.assertIn("surface_components_before", with_surfaces)
        self.assertNotIn("surface_components_before", without)
        self.assertNotIn("filtered", json.loads(without)["rows"][0])
        # Everything else is the same.
        full = json.loads(with_surfaces)
        for row in full["rows"]:
            del row["surface_components_before"]
            del row["filtered"]
        self.assertEqual(full, json.loads(without))


if __name__ == "__main__":
    unittest.main(verbosity=2)
