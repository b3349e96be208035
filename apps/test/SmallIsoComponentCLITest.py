#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""Tests of the command-line tools, run by CTest one test method at a time.

Environment (set by apps/test/CMakeLists.txt):
  SIC_FILTER   the SmallIsoComponentFilter executable
  SIC_PHANTOM  the SmallIsoComponentPhantom executable
  SIC_PROBE    the SmallIsoComponentCLITestProbe executable (makes and inspects images,
               runs the filter directly in C++ for reference statistics)
  SIC_SCRATCH  a directory for the tests' files
"""
import json
import math
import os
import subprocess
import sys
import unittest
import xml.dom.minidom

from sic_tool_test import ToolTestCase, digest, run

try:
    import pty  # POSIX only
except ImportError:
    pty = None

FILTER = os.environ.get("SIC_FILTER", "")
PHANTOM = os.environ.get("SIC_PHANTOM", "")
PROBE = os.environ.get("SIC_PROBE", "")

PIXEL_TYPES = ["uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64"]
# The probe's test images: isovalue 50 separates background (10) from object (100).
TEST_ISOVALUE = "50"
PHANTOM_ISOVALUE = "150"


def reject_constant(name):
    raise ValueError("not valid JSON: " + name)


def load_json(path):
    with open(path, encoding="utf-8") as file:
        return json.load(file, parse_constant=reject_constant)


class SmallIsoComponentCLITest(ToolTestCase):
    phantom = None

    def make_image(self, name, pixel_type="int16", dimension=3):
        path = self.path(name)
        self.check(run(PROBE, "make", path, pixel_type, dimension))
        return path

    def make_phantom(self, name="phantom.nrrd", *options):
        path = self.path(name)
        self.check(run(PHANTOM, path, "--size", "48", *options))
        return path

    def info(self, path):
        return json.loads(self.check(run(PROBE, "info", path)).stdout)

    def reference(self, path, isovalue, k, side="both", connectivity="face"):
        return json.loads(self.check(run(PROBE, "reference", path, isovalue, k, side, connectivity)).stdout)

    def nonzero(self, path):
        return int(self.check(run(PROBE, "count-nonzero", path)).stdout)

    def assertSameStatistics(self, stats, reference):
        for side in ("above", "below"):
            self.assertEqual(stats["statistics"][side], reference[side], side)
        for key in ("modified_voxels", "unrepairable_voxels"):
            self.assertEqual(stats["statistics"][key], reference[key], key)
        self.assertEqual(stats["parameters"]["effective_max_size"], reference["effective_max_size"])

    def assertOnlyFiles(self, *names):
        """The scratch directory holds exactly these files: no output, no staging leftovers."""
        self.assertEqual(sorted(os.listdir(self.dir)), sorted(names))

    # Pixel types and formats.

    def test_round_trip_keeps_pixel_type(self):
        for pixel_type in PIXEL_TYPES:
            for dimension in (2, 3):
                with self.subTest(pixel_type=pixel_type, dimension=dimension):
                    source = self.make_image("in-%s-%d.nrrd" % (pixel_type, dimension), pixel_type, dimension)
                    output = self.path("out-%s-%d.nrrd" % (pixel_type, dimension))
                    stats = self.path("stats-%s-%d.json" % (pixel_type, dimension))
                    self.check(run(FILTER, source, output, "--isovalue", TEST_ISOVALUE, "--stats", stats, "--quiet"))
                    before, after = self.info(source), self.info(output)
                    self.assertEqual(after, before)
                    self.assertEqual(after["pixel_type"], pixel_type)
                    self.assertEqual(after["dimension"], dimension)
                    self.assertEqual(load_json(stats)["input"]["pixel_type"], pixel_type)
                    reference = self.reference(source, TEST_ISOVALUE, 20)
                    self.assertGreater(reference["above"]["removed_components"], 0)
                    self.assertGreater(reference["below"]["removed_components"], 0)
                    self.assertSameStatistics(load_json(stats), reference)

    def test_formats_in_and_out(self):
        extensions = [".nrrd", ".nhdr", ".nii", ".nii.gz", ".mha", ".mhd"]
        source = self.make_image("source.nrrd", "int16", 3)
        expected = self.path("expected.nrrd")
        self.check(run(FILTER, source, expected, "--isovalue", TEST_ISOVALUE, "--quiet"))
        for extension in extensions:
            with self.subTest(input=extension):
                converted = self.path("in" + extension)
                self.check(run(PROBE, "make", converted, "int16", 3))
                self.assertEqual(self.info(converted)["pixel_type"], "int16")
                for out_extension in extensions:
                    output = self.path("out-from-%s%s" % (extension.replace(".", ""), out_extension))
                    self.check(run(FILTER, converted, output, "--isovalue", TEST_ISOVALUE, "--quiet"))
                    self.assertEqual(self.info(output)["pixel_type"], "int16")
                    self.check(run(PROBE, "equal", output, expected), extension + " -> " + out_extension)

    def test_png_two_dimensional(self):
        source = self.make_image("in.png", "uint8", 2)
        output = self.path("out.png")
        self.check(run(FILTER, source, output, "--isovalue", TEST_ISOVALUE, "--quiet"))
        self.assertEqual(self.info(output)["pixel_type"], "uint8")
        self.assertEqual(self.info(output)["size"], [24, 20])

    # Statistics.

    def test_stats_equal_the_filter_run_directly(self):
        phantom = self.make_phantom()
        cases = [
            ("both", "face", []),
            ("above", "face", []),
            ("below", "full", ["--fully-connected"]),
            ("both", "full", ["--fully-connected", "--max-size", "7"]),
        ]
        for side, connectivity, options in cases:
            with self.subTest(side=side, connectivity=connectivity, options=options):
                output, mask, stats = self.path("out.nrrd"), self.path("mask.nrrd"), self.path("stats.json")
                self.check(run(FILTER, phantom, output, "--isovalue", PHANTOM_ISOVALUE, "--side", side,
                               "--removed-mask", mask, "--stats", stats, "--quiet", *options))
                document = load_json(stats)
                k = 7 if "--max-size" in options else 20
                self.assertSameStatistics(document, self.reference(phantom, PHANTOM_ISOVALUE, k, side, connectivity))
                self.assertEqual(self.nonzero(mask), document["statistics"]["modified_voxels"])
                parameters = document["parameters"]
                self.assertEqual(parameters["side"], side)
                self.assertEqual(parameters["connectivity"], connectivity)
                self.assertEqual(parameters["max_size"], k)
                self.assertEqual(parameters["isovalue"], 150)

    def test_stats_json_is_complete(self):
        phantom = self.make_phantom()
        stats = self.path("stats.json")
        self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", "149.5", "--stats", stats,
                       "--threads", "2", "--quiet"))
        document = load_json(stats)
        self.assertEqual(document["input"]["path"], phantom)
        self.assertEqual(document["input"]["size"], [48, 48, 48])
        self.assertEqual(document["input"]["spacing"], [0.8, 0.8, 1.0])
        self.assertEqual(document["input"]["pixel_type"], "int16")
        self.assertEqual(document["parameters"]["isovalue"], 149.5)
        self.assertEqual(document["parameters"]["threads"], 2)
        self.assertNotIn("max_volume", document["parameters"])
        statistics = document["statistics"]
        for side in ("above", "below"):
            histogram = statistics[side]["size_histogram"]
            self.assertTrue(all(len(pair) == 2 and pair[1] > 0 for pair in histogram))
            self.assertEqual(sum(count for _, count in histogram), statistics[side]["components"])
        for key in ("modified_voxels", "unrepairable_voxels", "seconds", "peak_extra_bytes"):
            self.assertGreaterEqual(statistics[key], 0, key)

    def test_json_numbers_are_exact_and_never_nan(self):
        text = self.check(run(PROBE, "json-sample")).stdout
        document = json.loads(text, parse_constant=reject_constant)
        self.assertIsNone(document["nan"])
        self.assertEqual(document["infinities"], [None, None])
        self.assertEqual(document["doubles"], [0.1, 1 / 3, 2 / 3 * 1e300, 5e-324, -0.0, 150, 0.6400000000000001])
        self.assertEqual(document["integers"], [2**64 - 1, -2**63])
        self.assertEqual(document['text "quoted"'], "back\\slash, tab\t, newline\n, bell\a, mm³")
        self.assertEqual(document["nested"], [[1, 2], {"empty": []}])
        # Bytes that are not UTF-8 (a path can hold them) become U+FFFD: the document stays valid JSON.
        self.assertEqual(document["not UTF-8"], "a\ufffd\ufffd b")

    def test_stats_json_stays_valid_for_a_path_that_is_not_utf8(self):
        # A file name may hold any bytes; in the JSON those that are not UTF-8 become U+FFFD.
        phantom = self.path(os.fsdecode(b"phantom-\xff.nrrd"))
        os.rename(self.make_phantom(), phantom)
        stats = self.path("stats.json")
        self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--stats", stats,
                       "--quiet"))
        self.assertEqual(load_json(stats)["input"]["path"], phantom.replace("\udcff", "\ufffd"))

    def test_max_volume_in_cubic_millimetres(self):
        phantom = self.make_phantom()
        stats = self.path("stats.json")
        self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE,
                       "--max-volume", "10", "--stats", stats, "--quiet"))
        document = load_json(stats)
        k = math.floor(10 / (0.8 * 0.8 * 1.0))
        self.assertEqual(document["parameters"]["max_volume"], 10)
        self.assertIsNone(document["parameters"]["max_size"])
        self.assertEqual(document["parameters"]["effective_max_size"], k)
        self.assertSameStatistics(document, self.reference(phantom, PHANTOM_ISOVALUE, k))

    def test_result_does_not_depend_on_threads(self):
        phantom = self.make_phantom()
        documents = []
        for threads in ("1", "3"):
            output, stats = self.path("out-%s.nrrd" % threads), self.path("stats-%s.json" % threads)
            self.check(run(FILTER, phantom, output, "--isovalue", PHANTOM_ISOVALUE, "--threads", threads,
                           "--stats", stats, "--quiet"))
            documents.append(load_json(stats))
        self.check(run(PROBE, "equal", self.path("out-1.nrrd"), self.path("out-3.nrrd")))
        for side in ("above", "below"):
            self.assertEqual(documents[0]["statistics"][side], documents[1]["statistics"][side])

    # What the user sees.

    def test_summary_printed_and_quiet_prints_nothing(self):
        phantom = self.make_phantom()
        result = self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE))
        summary = result.stdout.strip()
        self.assertEqual(len(summary.splitlines()), 1, summary)
        for words in ("K = 20 voxels", "above components", "below components", "voxels modified", "unrepairable",
                      " s"):
            self.assertIn(words, summary)
        self.assertLessEqual(len(result.stderr.splitlines()), 5, result.stderr)
        quiet = self.check(run(FILTER, phantom, self.path("quiet.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--quiet"))
        self.assertEqual(quiet.stdout, "")
        self.assertEqual(quiet.stderr, "")

    def test_progress_bar_on_a_terminal(self):
        if pty is None:
            self.skipTest("skipped: this platform has no pseudo-terminals (Python's pty module)")
        phantom = self.make_phantom()
        controller, terminal = pty.openpty()
        try:
            result = subprocess.run([FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE],
                                    stdout=subprocess.PIPE, stderr=terminal, text=True, timeout=300)
            os.close(terminal)
            terminal = None
            shown = b""
            while True:
                try:
                    chunk = os.read(controller, 65536)
                except OSError:  # the terminal's other end is closed: all was read
                    break
                if not chunk:
                    break
                shown += chunk
        finally:
            if terminal is not None:
                os.close(terminal)
            os.close(controller)
        self.assertEqual(result.returncode, 0)
        shown = shown.decode()
        self.assertIn("\r", shown)
        self.assertIn("] 100%", shown)
        self.assertIn("[" + "#" * 30 + "]", shown)
        self.assertTrue(shown.endswith("\r\x1b[K"), repr(shown[-40:]))  # the bar is cleared at the end
        self.assertIn("above components", result.stdout)

    def test_progress_xml_lines(self):
        phantom = self.make_phantom()
        result = self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE,
                                "--progress-xml"))
        lines = result.stdout.splitlines()
        self.assertRegex(lines[0], r"^<filter-start><filter-name>SmallIsoComponentFilter</filter-name>"
                                   r"<filter-comment>.+</filter-comment></filter-start>$")
        progress = [float(line[len("<filter-progress>"):-len("</filter-progress>")])
                    for line in lines if line.startswith("<filter-progress>")]
        self.assertGreater(len(progress), 3)
        self.assertEqual(progress, sorted(progress))
        self.assertTrue(all(0.0 <= value <= 1.0 for value in progress))
        self.assertEqual(progress[-1], 1.0)
        self.assertTrue(any(line.startswith("<filter-end>") for line in lines))
        self.assertEqual(result.stderr, "")

    def test_help_explains_every_flag(self):
        result = self.check(run(FILTER, "--help"))
        for word in ("--isovalue", "--max-size", "--max-volume", "--side", "--fully-connected", "--removed-mask",
                     "--stats", "--threads", "--quiet", "--progress-xml", "--xml", "--help", "voxels", "mm³",
                     "Default: 20", "Default: both", "Exit status", "Example"):
            self.assertIn(word, result.stdout)
        self.assertIn(PHANTOM_ISOVALUE, self.check(run(PHANTOM, "--help")).stdout)

    # Slicer.

    def slicer_description(self):
        return xml.dom.minidom.parseString(self.check(run(FILTER, "--xml")).stdout)

    def test_xml_is_well_formed_and_lists_every_flag(self):
        document = self.slicer_description()
        root = document.documentElement
        self.assertEqual(root.tagName, "executable")
        for tag in ("category", "title", "description", "version", "contributor"):
            self.assertTrue(root.getElementsByTagName(tag)[0].firstChild.data.strip(), tag)
        longflags = {element.firstChild.data for element in document.getElementsByTagName("longflag")}
        for flag in longflags:
            self.assertRegex(flag, r"^--[A-Za-z_][A-Za-z0-9_]*$")  # what Slicer's parser accepts
        help_flags = {line.split()[0] for line in self.check(run(FILTER, "--help")).stdout.splitlines()
                      if line.startswith("  --")}
        # Options for a shell only: Slicer handles memory and files itself, and label maps have their own
        # executable, SmallIsoComponentLabelFilter.
        not_for_slicer = {"--help", "--xml", "--memory-limit", "--no-compression", "--labels", "--select",
                          "--background", "--max-size-of", "--keep-largest"}
        self.assertEqual({flag.replace("_", "-") for flag in longflags}, help_flags - not_for_slicer)
        images = {element.getElementsByTagName("name")[0].firstChild.data: element
                  for element in document.getElementsByTagName("image")}
        for name, channel, index in (("inputVolume", "input", "0"), ("outputVolume", "output", "1")):
            self.assertEqual(images[name].getElementsByTagName("channel")[0].firstChild.data, channel)
            self.assertEqual(images[name].getElementsByTagName("index")[0].firstChild.data, index)
        self.assertEqual(images["removedMask"].getElementsByTagName("channel")[0].firstChild.data, "output")
        tags = {element.tagName for element in root.getElementsByTagName("*")}
        for tag in ("double", "integer", "string-enumeration", "boolean", "file", "image"):
            self.assertIn(tag, tags)

    def test_slicer_command_line_runs(self):
        """Builds the command line the way Slicer does from --xml: flagged parameters in the
        order of the description, with their defaults, then the indexed ones."""
        phantom = self.make_phantom()
        document = self.slicer_description()
        # Every output Slicer offers gets a file (the surface ones exist in tools built with VTK).
        outputs = {"removedMask": self.path("mask.nrrd"), "statsFile": self.path("stats.json"),
                   "surface": self.path("surface.vtp"), "surfaceBefore": self.path("surface-before.vtp"),
                   "render": self.path("panels.png")}
        arguments, indexed = [], {}
        for group in document.getElementsByTagName("parameters"):
            for element in group.childNodes:
                if element.nodeType != element.ELEMENT_NODE or element.tagName in ("label", "description"):
                    continue
                name = element.getElementsByTagName("name")[0].firstChild.data
                defaults = element.getElementsByTagName("default")
                default = defaults[0].firstChild.data if defaults else ""
                indices = element.getElementsByTagName("index")
                if indices:
                    indexed[int(indices[0].firstChild.data)] = element
                    continue
                flag = element.getElementsByTagName("longflag")[0].firstChild.data
                if element.tagName == "boolean":
                    arguments += [flag] if default == "true" else []
                elif element.tagName in ("image", "file", "geometry"):
                    arguments += [flag, outputs[name]]
                else:
                    arguments += [flag, default]
        arguments += [phantom, self.path("out.nrrd")]
        self.assertEqual(sorted(indexed), [0, 1])
        result = self.check(run(FILTER, *arguments), " ".join(arguments))
        self.assertIn("<filter-progress>", result.stdout)
        self.assertTrue(os.path.exists(self.path("out.nrrd")))
        for name in ("surface", "surfaceBefore", "render"):
            if ("<name>%s</name>" % name) in document.toxml():
                self.assertTrue(os.path.exists(outputs[name]), name)
        self.assertEqual(self.nonzero(self.path("mask.nrrd")), load_json(self.path("stats.json"))["statistics"]["modified_voxels"])

    # Errors: one line, exit status 2, nothing written.

    def test_command_line_errors(self):
        source = self.make_image("in.nrrd")
        output = self.path("out.nrrd")
        cases = [
            ([], "missing INPUT"),
            ([source], "missing OUTPUT"),
            ([source, output], "missing --isovalue"),
            ([source, output, "--isovalue", "abc"], "not a number"),
            ([source, output, "--isovalue", "nan"], "not a number"),
            ([source, output, "--isovalue", "inf"], "not finite"),
            ([source, output, "--isovalue"], "needs a value"),
            ([source, output, "--isovalue", "50", "--max-size", "-3"], "negative"),
            ([source, output, "--isovalue", "50", "--max-size", "2.5"], "whole number"),
            ([source, output, "--isovalue", "50", "--max-volume", "-1"], "negative"),
            ([source, output, "--isovalue", "50", "--max-size", "10", "--max-volume", "5"], "both --max-size"),
            ([source, output, "--isovalue", "50", "--side", "up"], "expected one of above, below, both"),
            ([source, output, "--isovalue", "50", "--bogus"], "unknown option '--bogus'"),
            ([source, output, "--isovalue", "50", "--quiet=yes"], "takes no value"),
            ([source, output, "--isovalue", "50", "--isovalue", "60"], "given twice"),
            ([source, output, "extra", "--isovalue", "50"], "unexpected extra argument"),
            ([source, output, "--isovalue", "50", "--threads", "many"], "--threads"),
            ([source, output, "--isovalue", "50", "--threads", "1000000"], "--threads 1000000 is too many"),
            ([source, output, "--isovalue", "50", "--stats="], "--stats is empty; expected a file path"),
        ]
        for arguments, words in cases:
            with self.subTest(arguments=arguments):
                self.assertUsageError(run(FILTER, *arguments), words)
                self.assertOnlyFiles("in.nrrd")

    def test_input_errors(self):
        garbage = self.path("garbage.nrrd")
        with open(garbage, "w") as file:
            file.write("this is not an image\n")
        rgb = self.path("rgb.png")
        self.check(run(PROBE, "make", rgb, "rgb", 2))
        cases = [
            (self.path("missing.nrrd"), ["no such file"]),
            (self.dir, ["is a directory"]),
            (garbage, ["cannot read input"]),
            (rgb, ["3 components", "expected a scalar image"]),
        ]
        for source, words in cases:
            with self.subTest(source=source):
                self.assertUsageError(run(FILTER, source, self.path("out.nrrd"), "--isovalue", "50"), *words)
                self.assertOnlyFiles("garbage.nrrd", "rgb.png")

    def test_output_errors_leave_nothing(self):
        source = self.make_image("in.nrrd")
        os.mkdir(self.path("subdir"))
        cases = [
            ([self.path("out.xyz")], ["no ITK image writer", ".xyz"]),
            ([self.path("no-such-dir", "out.nrrd")], ["does not exist"]),
            ([self.path("subdir")], ["is a directory"]),
            ([self.path("out.nrrd"), "--removed-mask", self.path("mask.xyz")], ["removed-voxel mask"]),
            ([self.path("out.nrrd"), "--removed-mask", self.path("out.nrrd")], ["both"]),
            ([self.path("out.nrrd"), "--stats", self.path("nowhere", "stats.json")], ["statistics", "does not exist"]),
            ([self.path("out.png")], ["2-D images only", "out.png"]),
            ([self.path("out.nrrd"), "--removed-mask", self.path("mask.png")], ["2-D images only", "3-D"]),
        ]
        float_source = self.path("float.nrrd")
        self.check(run(PROBE, "make", float_source, "float32", 3))
        for arguments, words in cases:
            with self.subTest(arguments=arguments):
                image = float_source if arguments[0].endswith(".png") else source
                self.assertUsageError(run(FILTER, image, *arguments, "--isovalue", "50", "--quiet"), *words)
                self.assertOnlyFiles("in.nrrd", "float.nrrd", "subdir")
                self.assertEqual(os.listdir(self.path("subdir")), [])

    def test_late_failure_keeps_previous_outputs(self):
        # A 2-D float image passes every check but cannot be written as PNG: the failure
        # comes after the filter ran, and must leave the files that were there untouched.
        source = self.make_image("in.nrrd", "float32", 2)
        for name in ("out.png", "mask.nrrd", "stats.json"):
            with open(self.path(name), "w") as file:
                file.write("previous " + name)
        result = run(FILTER, source, self.path("out.png"), "--isovalue", "50",
                     "--removed-mask", self.path("mask.nrrd"), "--stats", self.path("stats.json"), "--quiet")
        self.assertUsageError(result, "cannot write output image", "out.png")
        for name in ("out.png", "mask.nrrd", "stats.json"):
            with open(self.path(name)) as file:
                self.assertEqual(file.read(), "previous " + name)
        self.assertOnlyFiles("in.nrrd", "out.png", "mask.nrrd", "stats.json")

    def test_refuses_to_overwrite_the_input(self):
        source = self.make_image("in.nrrd")
        os.symlink("in.nrrd", self.path("link.nrrd"))
        before = digest(source)
        same_file = [source, os.path.join(self.dir, ".", "in.nrrd"), self.path("link.nrrd")]
        cases = [[path] for path in same_file]
        cases += [[self.path("out.nrrd"), "--removed-mask", path] for path in same_file]
        cases += [[self.path("out.nrrd"), "--stats", path] for path in same_file]
        for arguments in cases:
            with self.subTest(arguments=arguments):
                self.assertUsageError(run(FILTER, source, *arguments, "--isovalue", "50"), "input")
                self.assertEqual(digest(source), before)
                self.assertOnlyFiles("in.nrrd", "link.nrrd")

    # The phantom.

    def test_phantom_is_deterministic(self):
        first = self.make_phantom("first.nrrd", "--seed", "7")
        second = self.make_phantom("second.nrrd", "--seed", "7")
        other = self.make_phantom("other.nrrd", "--seed", "8")
        self.assertEqual(digest(first), digest(second))
        self.assertNotEqual(digest(first), digest(other))
        os.mkdir(self.path("dir"))
        self.check(run(PHANTOM, self.path("dir"), "--size", "48", "--seed", "7"))
        self.assertEqual(digest(self.path("dir", "phantom.nrrd")), digest(first))
        info = self.info(first)
        self.assertEqual(info["pixel_type"], "int16")
        self.assertEqual(info["size"], [48, 48, 48])

    def test_phantom_has_specks_and_bubbles(self):
        phantom = self.path("phantom.nrrd")
        self.check(run(PHANTOM, phantom))
        self.assertEqual(self.info(phantom)["size"], [96, 96, 96])
        stats = self.path("stats.json")
        self.check(run(FILTER, phantom, self.path("out.nrrd"), "--isovalue", PHANTOM_ISOVALUE, "--stats", stats,
                       "--quiet"))
        statistics = load_json(stats)["statistics"]
        self.assertGreater(statistics["above"]["removed_components"], 100)
        self.assertGreater(statistics["below"]["removed_components"], 100)
        # The object itself stays: some components on each side are larger than K.
        self.assertGreater(statistics["above"]["components"], statistics["above"]["removed_components"])
        self.assertGreater(statistics["below"]["components"], statistics["below"]["removed_components"])

    def test_phantom_errors(self):
        self.assertUsageError(run(PHANTOM, self.path("p.nrrd"), "--size", "3"), "--size")
        self.assertUsageError(run(PHANTOM, self.path("p.nrrd"), "--seed", "x"), "--seed")
        self.assertUsageError(run(PHANTOM, self.path("none", "p.nrrd")), "does not exist")
        self.assertUsageError(run(PHANTOM), "missing OUTPUT_DIR_OR_FILE")
        self.assertOnlyFiles()


if __name__ == "__main__":
    unittest.main(verbosity=2)
