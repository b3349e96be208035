#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""Tests of SmallIsoComponentReport, run by CTest one test method at a time.

Environment (set by apps/test/CMakeLists.txt):
  SIC_REPORT        the SmallIsoComponentReport executable
  SIC_REPORT_PROBE  the SmallIsoComponentReportTestProbe executable (random volumes, and the
                    report computed by brute force: flood fill and a test of every cell)
  SIC_SCRATCH       a directory for the tests' files
"""
import csv
import io
import json
import os
import shutil
import unittest

from sic_tool_test import USAGE_ERROR, ToolTestCase, run

REPORT = os.environ.get("SIC_REPORT", "")
PROBE = os.environ.get("SIC_REPORT_PROBE", "")

# Random volumes hold the values 0 to 9 (and NaN for float types): these isovalues fall
# between values, on values, and outside the range on both ends.
ISOVALUES = ["-1", "0", "0.5", "1", "2.5", "3", "4.5", "7", "9.5", "100"]
SIZES = "0,1,2,3,5,10,1000"


def isovalue_arguments(isovalues):
    arguments = []
    for value in isovalues:
        arguments += ["--isovalue", value]
    return arguments


class SmallIsoComponentReportTest(ToolTestCase):
    def random_image(self, pixel_type, dimension, seed):
        path = self.path("random-%s-%dd-%d.nrrd" % (pixel_type, dimension, seed))
        self.check(run(PROBE, "random", path, pixel_type, dimension, seed))
        return path

    def report_json(self, image, *arguments):
        return json.loads(self.check(run(REPORT, image, "--format", "json", *arguments)).stdout)

    def reference_json(self, image, connectivity, sizes, isovalues):
        return json.loads(self.check(run(PROBE, "reference", image, connectivity, sizes, *isovalues)).stdout)

    def check_exact(self, dimension):
        for pixel_type in ["uint8", "int16", "float32", "float64"]:
            for seed in range(1, 5):
                image = self.random_image(pixel_type, dimension, seed)
                for connectivity in ["face", "full"]:
                    options = ["--fully-connected"] if connectivity == "full" else []
                    with self.subTest(pixel_type=pixel_type, seed=seed, connectivity=connectivity):
                        # The surface pieces (tools built with VTK) are checked in SmallIsoComponentSurfaceCLITest.
                        got = self.report_json(image, "--sizes", SIZES, "--no-surfaces", *options,
                                               *isovalue_arguments(ISOVALUES))
                        expected = self.reference_json(image, connectivity, SIZES, ISOVALUES)
                        self.assertEqual(got, expected)

    def test_exact_counts_2d_match_brute_force(self):
        self.check_exact(2)

    def test_exact_counts_3d_match_brute_force(self):
        self.check_exact(3)

    def test_active_cubes_match_direct_count_over_a_sweep(self):
        isovalues = ["%g" % (-1 + 0.25 * i) for i in range(45)]
        active = 0
        for pixel_type, dimension in [("uint8", 3), ("float32", 3), ("int16", 2), ("float64", 2)]:
            for seed in range(20, 24):
                image = self.random_image(pixel_type, dimension, seed)
                got = self.report_json(image, "--isovalue-range", "-1:10:0.25")
                expected = self.reference_json(image, "face", "1", isovalues)
                self.assertEqual([r["isovalue"] for r in got["rows"]], [r["isovalue"] for r in expected["rows"]])
                self.assertEqual([r["active_cubes"] for r in got["rows"]],
                                 [r["active_cubes"] for r in expected["rows"]])
                active += sum(r["active_cubes"] for r in got["rows"])
        self.assertGreater(active, 0)

    def test_json_has_the_documented_form(self):
        image = self.random_image("uint8", 3, 11)
        got = self.report_json(image, "--isovalue", "4.5", "--sizes", "1,5", "--no-surfaces")
        self.assertEqual(list(got), ["input", "size", "connectivity", "rows"])
        self.assertEqual(got["input"], image)
        self.assertEqual(got["connectivity"], "face")
        row = got["rows"][0]
        self.assertEqual(list(row), ["isovalue", "active_cubes", "total_components", "above", "below"])
        self.assertEqual(row["total_components"], row["above"]["components"] + row["below"]["components"])
        for side in ["above", "below"]:
            self.assertEqual(list(row[side]), ["components", "by_size"])
            self.assertEqual([b["max_size"] for b in row[side]["by_size"]], [1, 5])
            self.assertEqual(list(row[side]["by_size"][0]), ["max_size", "removed_components", "modified_voxels"])

    def test_thread_count_does_not_change_the_report(self):
        image = self.random_image("float32", 3, 3)
        arguments = ["--isovalue-range", "0:9:0.5", "--fully-connected"]
        self.assertEqual(self.report_json(image, "--threads", "1", *arguments),
                         self.report_json(image, "--threads", "2", *arguments))

    def test_csv_parses_back_to_the_json_numbers(self):
        image = self.random_image("int16", 3, 5)
        arguments = ["--isovalue", "2.5", "--isovalue", "6", "--sizes", "1,3,10", "--no-surfaces"]
        expected = self.report_json(image, *arguments)
        text = self.check(run(REPORT, image, "--format", "csv", *arguments)).stdout
        rows = list(csv.DictReader(io.StringIO(text)))
        self.assertEqual(len(rows), 2 * 2 * 3)
        for line in rows:
            row = next(r for r in expected["rows"] if r["isovalue"] == float(line["isovalue"]))
            side = row[line["side"]]
            by_size = next(b for b in side["by_size"] if b["max_size"] == int(line["max_size"]))
            self.assertEqual(line["input"], image)
            self.assertEqual(line["connectivity"], "face")
            self.assertEqual(int(line["active_cubes"]), row["active_cubes"])
            self.assertEqual(int(line["total_components"]), row["total_components"])
            self.assertEqual(int(line["components"]), side["components"])
            self.assertEqual(int(line["removed_components"]), by_size["removed_components"])
            self.assertEqual(int(line["modified_voxels"]), by_size["modified_voxels"])
            self.assertAlmostEqual(float(line["removed_percent"]),
                                   100.0 * by_size["removed_components"] / row["total_components"])

    def test_markdown_table_parses_back_to_the_json_numbers(self):
        image = self.random_image("uint8", 2, 9)
        arguments = ["--isovalue", "1.5", "--isovalue", "5", "--sizes", "2,20", "--fully-connected"]
        expected = self.report_json(image, *arguments)
        text = self.check(run(REPORT, image, *arguments)).stdout
        self.assertIn("full connectivity", text)
        lines = [line for line in text.splitlines() if line.startswith("|")]
        header = [cell.strip() for cell in lines[0].strip("|").split("|")]
        self.assertTrue(all(set(cell.strip()) <= set("-:") for cell in lines[1].strip("|").split("|")))
        table = [dict(zip(header, (cell.strip() for cell in line.strip("|").split("|")))) for line in lines[2:]]
        self.assertEqual(len(table), 2 * 2)
        for line in table:
            row = next(r for r in expected["rows"] if r["isovalue"] == float(line["isovalue"]))
            k = [b["max_size"] for b in row["above"]["by_size"]].index(int(line["K"]))
            self.assertEqual(int(line["active cubes"]), row["active_cubes"])
            self.assertEqual(int(line["components"]), row["total_components"])
            for side in ["above", "below"]:
                by_size = row[side]["by_size"][k]
                self.assertEqual(int(line[side]), row[side]["components"])
                self.assertEqual(int(line[side + " removed"]), by_size["removed_components"])
                self.assertEqual(int(line[side + " voxels"]), by_size["modified_voxels"])
                self.assertAlmostEqual(float(line[side + " %"]),
                                       100.0 * by_size["removed_components"] / row["total_components"], places=2)

    def test_isovalue_range_includes_stop_and_merges_with_isovalues(self):
        image = self.random_image("uint8", 2, 1)
        got = self.report_json(image, "--isovalue-range", "0:1:0.1", "--isovalue", "0.5", "--isovalue", "-2")
        isovalues = [r["isovalue"] for r in got["rows"]]
        self.assertEqual(len(isovalues), 12)
        self.assertEqual(isovalues[0], -2)
        self.assertEqual(isovalues[-1], 1.0)
        self.assertEqual(isovalues, sorted(isovalues))
        got = self.report_json(image, "--isovalue-range", "0:1:0.3")
        self.assertEqual(len(got["rows"]), 4)

    def test_sizes_range_adds_sizes(self):
        image = self.random_image("uint8", 2, 1)
        got = self.report_json(image, "--isovalue", "3", "--sizes-range", "0:10:4", "--sizes", "7")
        self.assertEqual([b["max_size"] for b in got["rows"][0]["above"]["by_size"]], [0, 4, 7, 8])
        got = self.report_json(image, "--isovalue", "3")
        self.assertEqual([b["max_size"] for b in got["rows"][0]["below"]["by_size"]], [1, 5, 10, 20, 50])

    def test_output_file_holds_the_report_and_a_failure_writes_nothing(self):
        image = self.random_image("uint8", 3, 2)
        output = self.path("report.json")
        self.check(run(REPORT, image, "--isovalue", "4.5", "--format", "json", "--output", output))
        with open(output, encoding="utf-8") as file:
            self.assertEqual(json.load(file), self.report_json(image, "--isovalue", "4.5"))
        failed = self.path("failed.json")
        result = run(REPORT, image, "--isovalue", "4.5", "--output", failed, "--plot", self.path("p.png"),
                     "--plot-size", "3")
        self.assertEqual(result.returncode, USAGE_ERROR)
        self.assertFalse(os.path.exists(failed))
        self.assertEqual(run(REPORT, image, "--isovalue", "1", "--output", image).returncode, USAGE_ERROR)

    def vector_image(self):
        path = self.path("vector.nrrd")
        with open(path, "wb") as file:
            file.write(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 3 4 5\nkinds: vector domain domain\n"
                       b"encoding: raw\n\n" + bytes(3 * 4 * 5))
        return path

    def test_bad_input_is_one_line_and_exit_status_2(self):
        image = self.random_image("uint8", 2, 1)
        cases = [
            ([image], "no isovalue"),
            ([image, "--isovalue", "3", "--sizes", "1,-5"], "negative"),
            ([image, "--isovalue", "3", "--sizes", "1,abc"], "not a whole number"),
            ([image, "--isovalue", "3", "--sizes", "1,,5"], "empty item"),
            ([image, "--isovalue", "abc"], "not a number"),
            ([image, "--isovalue-range", "1:5"], "START:STOP:STEP"),
            ([image, "--isovalue-range", "1:5:0"], "STEP <= 0"),
            ([image, "--isovalue-range", "5:1:1"], "START > STOP"),
            ([image, "--isovalue", "3", "--sizes-range", "1:x:1"], "not a whole number"),
            ([image, "--isovalue", "3", "--format", "xml"], "--format"),
            ([self.path("missing.nrrd"), "--isovalue", "3"], "missing.nrrd"),
            ([self.vector_image(), "--isovalue", "3"], "vector.nrrd"),
            ([image, "--isovalue", "3", "--plot-isovalue", "4", "--plot", self.path("p.png")], "--plot-isovalue"),
            ([image, "--isovalue", "3", "--threads", "1000000"], "--threads 1000000 is too many"),
            ([image, "--isovalue", "3", "--output="], "--output is empty; expected a file path"),
        ]
        for arguments, words in cases:
            with self.subTest(arguments=arguments[1:]):
                result = run(REPORT, *arguments)
                self.assertEqual(result.returncode, USAGE_ERROR, result.stderr)
                self.assertEqual(result.stdout, "")
                self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
                self.assertIn(words, result.stderr)

    def test_plot_writes_a_png(self):
        if shutil.which("gnuplot") is None:
            self.skipTest("gnuplot is not installed (Debian: gnuplot-nox); --plot cannot be tested")
        image = self.random_image("float32", 3, 4)
        plot = self.path("curves.png")
        self.check(run(REPORT, image, "--isovalue-range", "0:9:0.5", "--sizes-range", "0:20:1", "--plot", plot,
                       "--plot-size", "5", "--plot-isovalue", "4.5"))
        with open(plot, "rb") as file:
            content = file.read()
        self.assertEqual(content[:8], b"\x89PNG\r\n\x1a\n")
        self.assertGreater(len(content), 1000)

    def test_plot_without_gnuplot_is_a_clear_error(self):
        image = self.random_image("uint8", 2, 1)
        empty = self.path("empty-bin")
        os.mkdir(empty)
        plot = self.path("curves.png")
        result = run(os.path.abspath(REPORT), image, "--isovalue", "3", "--plot", plot,
                     env=dict(os.environ, PATH=empty))
        self.assertEqual(result.returncode, USAGE_ERROR)
        self.assertIn("gnuplot", result.stderr)
        self.assertFalse(os.path.exists(plot))

    def test_help_lists_every_option(self):
        text = self.check(run(REPORT, "--help")).stdout
        for flag in ["--isovalue", "--isovalue-range", "--sizes", "--sizes-range", "--fully-connected", "--format",
                     "--output", "--plot", "--plot-size", "--plot-isovalue", "--threads"]:
            self.assertIn(flag, text)


if __name__ == "__main__":
    unittest.main()
