#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""Label maps in the filter tools: SmallIsoComponentFilter --labels and SmallIsoComponentLabelFilter,
compared voxel for voxel with SmallIsoComponentLabelImageFilter run directly by the test probe
(label-reference), on the probe's random label maps; and SmallIsoComponentReport --labels, compared
with that filter run at each K.

Environment (set by apps/test/CMakeLists.txt):
  SIC_FILTER        the SmallIsoComponentFilter executable
  SIC_LABEL_FILTER  the SmallIsoComponentLabelFilter executable
  SIC_PROBE         the SmallIsoComponentCLITestProbe executable
  SIC_REPORT        the SmallIsoComponentReport executable
  SIC_SCRATCH       a directory for the tests' files
"""
import json
import os
import re
import struct
import sys
import unittest
import xml.dom.minidom

from sic_tool_test import USAGE_ERROR, ToolTestCase, run, write_nrrd, write_segmentation

FILTER = os.environ.get("SIC_FILTER", "")
LABEL_FILTER = os.environ.get("SIC_LABEL_FILTER", "")
PROBE = os.environ.get("SIC_PROBE", "")
REPORT = os.environ.get("SIC_REPORT", "")
# Under AddressSanitizer the process's own memory is mostly the sanitizer's and varies too much from one run to
# the next for the thinnest slabs.
MEMORY_UNMEASURABLE = os.environ.get("SIC_SANITIZER", "") == "address"

# The probe's label maps hold 0, 1, 2, 5 and a label of their type's own (uint8: 255, int16: -3000,
# uint32 and uint64: the largest value, int64: -2^40, floats: -12).
CASES = [
    # type, dimension, extension, select, background, K, keep-largest, connectivity, per-label K
    ("uint8", 3, ".nrrd", "all", "0", 3, 0, "face", "-"),
    ("int16", 2, ".nii.gz", "islands", "0", 4, 0, "full", "-"),
    ("uint32", 3, ".mha", "holes", "0", 5, 0, "face", "-"),
    ("float32", 3, ".nrrd", "1,5", "0", 2, 0, "full", "2=0,5=6"),
    ("int16", 3, ".mha", "-3000,2", "2", 3, 1, "face", "-3000=10"),
    ("float32", 2, ".nii", "all", "5", 0, 2, "face", "-"),
    ("uint8", 2, ".nrrd", "islands", "5", 3, 1, "full", "1=0,255=9"),
    ("int64", 3, ".nii.gz", "all", "0", 3, 0, "face", "-1099511627776=8"),
    ("uint64", 3, ".nrrd", "18446744073709551615,0", "0", 4, 0, "full", "-"),
    ("float64", 3, ".mha", "holes", "-12", 6, 1, "face", "-"),
]


def load_json(path):
    with open(path, encoding="utf-8") as file:
        return json.load(file)


class SmallIsoComponentLabelCLITest(ToolTestCase):
    def make_labels(self, name, pixel_type, dimension, seed=1, *sizes):
        path = self.path(name)
        self.check(run(PROBE, "make-labels", path, pixel_type, dimension, seed, *sizes))
        return path

    def reference(self, source, select="all", background="0", k=20, keep=0, connectivity="face", sizes="-"):
        output, mask = self.path("reference.nrrd"), self.path("reference-mask.nrrd")
        result = self.check(run(PROBE, "label-reference", source, output, mask, select, background, k, keep,
                                connectivity, sizes))
        return output, mask, json.loads(result.stdout)

    def assertEqualImages(self, first, second, message):
        self.check(run(PROBE, "equal", first, second), message)

    def test_output_and_mask_equal_the_filter_run_directly(self):
        for seed, (pixel_type, dimension, extension, select, background, k, keep, connectivity, sizes) in enumerate(
                CASES, 1):
            case = "%s %d-D %s select %s" % (pixel_type, dimension, extension, select)
            with self.subTest(case=case):
                source = self.make_labels("in-%d%s" % (seed, extension), pixel_type, dimension, seed)
                output, mask, stats = (self.path("out-%d%s" % (seed, extension)), self.path("mask-%d.nrrd" % seed),
                                       self.path("stats-%d.json" % seed))
                options = ["--select", select, "--background", background, "--max-size", k,
                           "--removed-mask", mask, "--stats", stats, "--quiet"]
                options += ["--keep-largest", keep] if keep else []
                options += ["--fully-connected"] if connectivity == "full" else []
                # Per-label sizes given one by one, or as one list.
                for pair in ([] if sizes == "-" else sizes.split(",") if seed % 2 else [sizes]):
                    options += ["--max-size-of", pair]
                tool = [LABEL_FILTER] if seed % 2 else [FILTER, "--labels"]
                self.check(run(*tool, source, output, *options), case)
                expected, expected_mask, statistics = self.reference(source, select, background, k, keep,
                                                                     connectivity, sizes)
                self.assertGreater(statistics["modified_voxels"], 0, case)
                self.assertEqualImages(output, expected, case)
                self.assertEqualImages(mask, expected_mask, case)
                document = load_json(stats)
                self.assertEqual(document["input"]["pixel_type"], pixel_type)
                self.assertEqual(document["statistics"]["labels"], statistics["labels"], case)
                for key in ("modified_voxels", "unrepairable_voxels"):
                    self.assertEqual(document["statistics"][key], statistics[key], key)
                self.assertEqual(document["parameters"]["effective_max_size"], statistics["effective_max_size"])

    def test_max_volume_and_threads(self):
        source = self.make_labels("in.nrrd", "uint16", 3, 7)
        expected, _, statistics = self.reference(source, k=4)
        for threads in ("1", "3"):
            with self.subTest(threads=threads):
                output, stats = self.path("out-%s.nrrd" % threads), self.path("stats-%s.json" % threads)
                # The probe's maps have voxels of 1 mm³: 4.5 mm³ is K = 4.
                self.check(run(LABEL_FILTER, source, output, "--max-size", "0", "--max-volume", "4.5",
                               "--threads", threads, "--stats", stats, "--quiet"))
                self.assertEqualImages(output, expected, threads)
                self.assertEqual(load_json(stats)["statistics"]["labels"], statistics["labels"])

    def test_stats_json_keys_each_label_by_its_id(self):
        source = self.make_labels("in.nrrd", "uint64", 2, 3)
        stats = self.path("stats.json")
        self.check(run(FILTER, source, self.path("out.nrrd"), "--labels", "--select", "+05,01",
                       "--background", "-0", "--max-size-of", "05=7", "--keep-largest", "1", "--stats", stats,
                       "--quiet"))
        document = load_json(stats)
        parameters = document["parameters"]
        self.assertTrue(parameters["labels"])
        self.assertNotIn("isovalue", parameters)
        self.assertNotIn("side", parameters)
        self.assertEqual(parameters["selection"], "listed")
        self.assertEqual(parameters["selected_labels"], ["5", "1"])
        self.assertEqual(parameters["background"], "0")
        self.assertEqual(parameters["max_size_of"], {"5": 7})
        self.assertEqual(parameters["keep_largest"], 1)
        self.assertEqual(parameters["max_size"], 20)
        self.assertEqual(parameters["effective_max_size"], 20)
        self.assertEqual(parameters["connectivity"], "face")
        statistics = document["statistics"]
        labels = statistics["labels"]
        # Every label of the input, in ascending order, the largest uint64 exactly.
        self.assertEqual(list(labels), ["0", "1", "2", "5", "18446744073709551615"])
        for label, entry in labels.items():
            self.assertEqual(list(entry), ["components", "removed_components", "removed_voxels", "gained_voxels",
                                           "size_histogram"], label)
            self.assertEqual(sum(count for _, count in entry["size_histogram"]), entry["components"], label)
        for label in ("0", "2", "18446744073709551615"):
            self.assertEqual(labels[label]["removed_components"], 0, label)
        self.assertGreater(labels["5"]["removed_components"], 0)
        removed = sum(entry["removed_voxels"] for entry in labels.values())
        self.assertEqual(removed, statistics["modified_voxels"] + statistics["unrepairable_voxels"])
        self.assertEqual(sum(entry["gained_voxels"] for entry in labels.values()), statistics["modified_voxels"])
        self.assertEqual(statistics["mode"], "in-memory")
        for key in ("seconds", "total_seconds", "peak_resident_bytes"):
            self.assertGreaterEqual(statistics[key], 0, key)

    def test_summary_names_the_label_map(self):
        source = self.make_labels("in.nrrd", "uint8", 3)
        summary = self.check(run(LABEL_FILTER, source, self.path("out.nrrd"))).stdout.strip()
        self.assertEqual(len(summary.splitlines()), 1, summary)
        for words in ("Label map of 5 labels", "K = 20 voxels", "selection all", "components", "voxels modified"):
            self.assertIn(words, summary)

    def test_help_and_xml_of_the_label_tool(self):
        help_text = self.check(run(LABEL_FILTER, "--help")).stdout
        for word in ("--select", "--background", "--max-size-of", "--keep-largest", "--removed-mask", "--stats",
                     "Default: all", "Exit status", "Example", "uint64"):
            self.assertIn(word, help_text)
        for word in ("--isovalue", "--side"):
            self.assertNotIn(word, help_text)
        scalar_help = self.check(run(FILTER, "--help")).stdout
        # The label surfaces exist where the scalar ones do (tools built with VTK).
        for word in ("--surface", "--surface-before", "--render"):
            self.assertEqual(word in help_text, word in scalar_help, word)
        for word in ("--labels", "--select", "--max-size-of", "SmallIsoComponentLabelFilter"):
            self.assertIn(word, scalar_help)
        document = xml.dom.minidom.parseString(self.check(run(LABEL_FILTER, "--xml")).stdout)
        images = {element.getElementsByTagName("name")[0].firstChild.data: element
                  for element in document.getElementsByTagName("image")}
        self.assertEqual(sorted(images), ["inputVolume", "outputVolume", "removedMask"])
        for element in images.values():
            self.assertEqual(element.getAttribute("type"), "label")
        longflags = {element.firstChild.data for element in document.getElementsByTagName("longflag")}
        help_flags = {line.split()[0] for line in help_text.splitlines() if line.startswith("  --")}
        self.assertEqual({flag.replace("_", "-") for flag in longflags},
                         help_flags - {"--help", "--xml", "--no-compression", "--labels", "--memory-limit"})

    # Errors: one line, exit status 2, nothing written.

    def test_options_of_the_other_kind_are_refused(self):
        source = self.make_labels("in.nrrd", "uint8", 3)
        output = self.path("out.nrrd")
        cases = [
            ([FILTER, "--labels", "--isovalue", "3"], ["--isovalue has no meaning for a label map", "expected no"]),
            ([FILTER, "--labels", "--side", "above"], ["--side has no meaning", "expected --select"]),
            ([FILTER, "--labels", "--keep-largest", "1", "--memory-limit", "1G"],
             ["--keep-largest needs every component whole", "cannot be combined with --memory-limit"]),
            ([LABEL_FILTER, "--memory-limit", "1G", "--removed-mask", "m.nii"], ["stream", "MetaImage", "NRRD"]),
            ([FILTER, "--isovalue", "3", "--select", "all"], ["--select applies to label maps only",
                                                             "expected --labels"]),
            ([FILTER, "--isovalue", "3", "--background", "1"], ["--background applies to label maps only"]),
            ([FILTER, "--isovalue", "3", "--max-size-of", "1=2"], ["--max-size-of applies to label maps only"]),
            ([FILTER, "--isovalue", "3", "--keep-largest", "1"], ["--keep-largest applies to label maps only"]),
            ([LABEL_FILTER, "--isovalue", "3"], ["unknown option '--isovalue'"]),
            ([LABEL_FILTER, "--side", "both"], ["unknown option '--side'"]),
        ]
        for arguments, words in cases:
            with self.subTest(arguments=arguments):
                self.assertUsageError(run(arguments[0], source, output, *arguments[1:]), *words)
                self.assertEqual(os.listdir(self.dir), ["in.nrrd"])

    def test_label_option_errors(self):
        source = self.make_labels("in.nrrd", "uint8", 3)
        floats = self.make_labels("float.nrrd", "float32", 3)
        output = self.path("out.nrrd")
        cases = [
            (source, ["--select", "some"], ["--select 'some' is not a valid choice",
                                            "expected all, islands, holes or label ids"]),
            (source, ["--select", "3,,5"], ["--select '' is not a label id", "expected a whole number"]),
            (source, ["--select", "2.5"], ["--select '2.5' is not a label id"]),
            (source, ["--background", "x"], ["--background 'x' is not a label id"]),
            (source, ["--max-size-of", "7"], ["--max-size-of '7' is not L=K", "such as 7=500"]),
            (source, ["--max-size-of", "7=1", "--max-size-of", "+7=2"], ["gives label 7 more than one K"]),
            (source, ["--max-size-of", "7=-1"], ["--max-size-of '-1' is negative"]),
            (source, ["--keep-largest", "1.5"], ["--keep-largest '1.5' is not a whole number"]),
            (source, ["--max-size", "3", "--max-volume", "2"], ["both --max-size"]),
            (source, ["--background", "256"], ["--background label 256 is not a value of the input's pixel type "
                                               "uint8", "expected a label id the input can hold"]),
            (source, ["--select", "1,-1"], ["--select label -1 is not a value", "uint8"]),
            (source, ["--max-size-of", "300=1"], ["--max-size-of label 300 is not a value", "uint8"]),
            (floats, ["--select", "16777217"], ["--select label 16777217 is not a value", "float32"]),
        ]
        for image, options, words in cases:
            with self.subTest(options=options):
                self.assertUsageError(run(LABEL_FILTER, image, output, *options, "--quiet"), *words)
                self.assertEqual(sorted(os.listdir(self.dir)), ["float.nrrd", "in.nrrd"])

    def test_input_that_is_not_a_label_map(self):
        cases = [
            ("fraction.nrrd", "float", struct.pack("<4f", 1, 2, 2.5, 0), ["[0, 1] is 2.5", "whole numbers only"]),
            ("nan.nrrd", "double", struct.pack("<4d", 1, float("nan"), 2, 0), ["[1, 0] is nan",
                                                                              "whole numbers only"]),
            ("infinite.nrrd", "float", struct.pack("<4f", 1, 2, 0, float("inf")), ["is inf", "whole numbers"]),
        ]
        for name, kind, data, words in cases:
            write_nrrd(self.path(name), [2, 2], data, kind=kind)
        for name, kind, data, words in cases:
            with self.subTest(name=name):
                for name_out in ("out.nrrd", "mask.nrrd", "stats.json"):
                    with open(self.path(name_out), "w") as file:
                        file.write("previous")
                result = run(LABEL_FILTER, self.path(name), self.path("out.nrrd"), "--removed-mask",
                             self.path("mask.nrrd"), "--stats", self.path("stats.json"), "--quiet")
                self.assertUsageError(result, "cannot filter input", name, "as a label map", *words)
                for name_out in ("out.nrrd", "mask.nrrd", "stats.json"):
                    with open(self.path(name_out)) as file:
                        self.assertEqual(file.read(), "previous")
                self.assertEqual(self.staging_leftovers(self.dir), [])

    def test_report_gives_what_the_filter_removes_at_each_k(self):
        sizes = [0, 1, 2, 3, 5, 1000]
        maps = [("uint8", 3, ".nrrd"), ("int16", 2, ".nii.gz"), ("float32", 3, ".mha"), ("uint64", 3, ".nrrd")]
        for seed, (pixel_type, dimension, extension) in enumerate(maps, 1):
            source = self.make_labels("report-%d%s" % (seed, extension), pixel_type, dimension, seed)
            for connectivity in ("face", "full"):
                case = "%s %d-D %s connectivity" % (pixel_type, dimension, connectivity)
                options = ["--fully-connected"] if connectivity == "full" else []
                report = json.loads(self.check(run(REPORT, source, "--labels", "--sizes", ",".join(map(str, sizes)),
                                                   "--format", "json", "--threads", seed, *options), case).stdout)
                self.assertEqual(report["connectivity"], connectivity, case)
                for index, k in enumerate(sizes):
                    _, _, statistics = self.reference(source, k=k, connectivity=connectivity)
                    self.assertEqual(list(report["labels"]), list(statistics["labels"]), case)
                    for label, entry in statistics["labels"].items():
                        row = report["labels"][label]
                        self.assertEqual(row["components"], entry["components"], case)
                        self.assertEqual(row["by_size"][index], {"max_size": k,
                                                                 "removed_components": entry["removed_components"],
                                                                 "removed_voxels": entry["removed_voxels"]},
                                         "%s, label %s, K = %d" % (case, label, k))
                self.assertGreater(sum(row["by_size"][1]["removed_components"] for row in report["labels"].values()),
                                   0, case)

    def test_report_forms_agree(self):
        source = self.make_labels("report.nrrd", "int16", 3, 4)
        report = json.loads(self.check(run(REPORT, source, "--labels", "--sizes", "2,4", "--format", "json")).stdout)
        lines = self.check(run(REPORT, source, "--labels", "--sizes", "2,4", "--format", "csv")).stdout.splitlines()
        self.assertEqual(lines[0], "input,connectivity,label,components,max_size,removed_components,"
                                   "removed_percent,removed_voxels")
        rows = [line.split(",") for line in lines[1:]]
        self.assertEqual(len(rows), 2 * len(report["labels"]))
        markdown = self.check(run(REPORT, source, "--labels", "--sizes", "2,4")).stdout
        self.assertIn("# Small components of the label map", markdown)
        for (label, entry), pair in zip(report["labels"].items(), zip(rows[0::2], rows[1::2])):
            for by_size, row in zip(entry["by_size"], pair):
                self.assertEqual(row[1:5], ["face", label, str(entry["components"]), str(by_size["max_size"])])
                self.assertEqual([int(row[5]), int(row[7])], [by_size["removed_components"], by_size["removed_voxels"]])
                self.assertAlmostEqual(float(row[6]), 100.0 * by_size["removed_components"] / entry["components"])
                self.assertIn("| %s | %d | %d | %d |" % (label, entry["components"], by_size["max_size"],
                                                        by_size["removed_components"]), markdown)

    def test_report_option_errors(self):
        source = self.make_labels("report.nrrd", "uint8", 2)
        for options, words in ((["--isovalue", "1"], ["--isovalue is not taken with --labels"]),
                               (["--isovalue-range", "1:2:1"], ["--isovalue-range is not taken with --labels"]),
                               (["--plot", self.path("plot.png")], ["--plot is not taken with --labels"])):
            with self.subTest(options=options):
                self.assertUsageError(run(REPORT, source, "--labels", *options), *words)
        write_nrrd(self.path("fraction.nrrd"), [2, 2], struct.pack("<4f", 1, 2, 2.5, 0), kind="float")
        with open(self.path("report.md"), "w") as file:
            file.write("previous")
        result = run(REPORT, self.path("fraction.nrrd"), "--labels", "--output", self.path("report.md"))
        self.assertUsageError(result, "as a label map", "[0, 1] is 2.5", "whole numbers only")
        with open(self.path("report.md")) as file:
            self.assertEqual(file.read(), "previous")
        self.assertEqual(self.staging_leftovers(self.dir), [])

    def streamed_run(self, source, output, limit, options):
        """Streams source under limit (a MiB count) with a mask and statistics: the statistics, or None when the
        tool refused the limit, in one line and without writing anything."""
        stem = os.path.splitext(output)[0]
        before = os.listdir(self.dir)
        result = run(LABEL_FILTER, source, output, "--removed-mask", stem + "-mask.nrrd", "--stats", stem + ".json",
                     "--memory-limit", "%dM" % limit, "--quiet", *options)
        if result.returncode == USAGE_ERROR:
            self.assertUsageError(result, "MiB is too small to stream this label map", "expected a larger limit")
            self.assertEqual(os.listdir(self.dir), before)
            return None
        self.check(result)
        return load_json(stem + ".json")

    def assertStreamedAsInMemory(self, source, depth, options):
        """Streams source under limits from the smallest the tool asks for up: every run that does not refuse its
        limit gives the in-memory run's output, mask and voxel counts, and thin slabs are among them."""
        expected, expected_mask = self.path("memory.nrrd"), self.path("memory-mask.nrrd")
        self.check(run(LABEL_FILTER, source, expected, "--removed-mask", expected_mask, "--stats",
                       self.path("memory.json"), "--quiet", *options))
        in_memory = load_json(self.path("memory.json"))["statistics"]
        self.assertGreater(in_memory["modified_voxels"], 0)
        refusal = self.assertUsageError(run(LABEL_FILTER, source, self.path("none.nrrd"), "--memory-limit", "1M",
                                            "--quiet", *options), "too small", "with the process itself")
        smallest = int(re.search(r"take about (\d+) MiB", refusal).group(1))
        slabs = set()
        for extra in (-2, -1, 0, 1, 2, 3, 5, 8, 12, 20, 40, 200):
            output = self.path("streamed-%d%s" % (extra, (".mha", ".nrrd", ".nhdr")[extra % 3]))
            streamed = self.streamed_run(source, output, smallest + extra, options)
            if streamed is None:
                continue
            statistics = streamed["statistics"]
            slabs.add(statistics["slab_planes"])
            self.assertEqual(statistics["mode"], "streaming")
            self.assertEqual(statistics["memory_limit_bytes"], (smallest + extra) << 20)
            self.assertEqualImages(output, expected, output)
            self.assertEqualImages(os.path.splitext(output)[0] + "-mask.nrrd", expected_mask, output)
            for key in ("modified_voxels", "unrepairable_voxels"):
                self.assertEqual(statistics[key], in_memory[key], key)
            self.assertEqual(list(statistics["labels"]), list(in_memory["labels"]))
            for label, entry in statistics["labels"].items():
                for key in ("removed_voxels", "gained_voxels"):
                    self.assertEqual(entry[key], in_memory["labels"][label][key], (label, key))
                for key in ("components", "removed_components", "size_histogram"):
                    self.assertIsNone(entry[key], (label, key))
        self.assertIn(depth, slabs, "the largest limit streams the map in one slab")
        if not MEMORY_UNMEASURABLE:
            self.assertGreaterEqual(len([slab for slab in slabs if slab < depth]), 2, slabs)

    def test_streamed_label_maps_give_the_in_memory_result(self):
        source = self.path("segmentation.nrrd")
        write_segmentation(source, [160, 150, 40], 1)
        for options in (["--max-size", "4"], ["--max-size", "2", "--max-size-of", "9=6,3=1", "--fully-connected"],
                        ["--max-volume", "3.5", "--select", "islands"], ["--max-size", "5", "--select", "0,9"]):
            with self.subTest(options=options):
                self.assertStreamedAsInMemory(source, 40, options)

    def test_streamed_2d_label_maps_give_the_in_memory_result(self):
        source = self.path("segmentation.nrrd")
        write_segmentation(source, [3000, 400], 2)
        self.assertStreamedAsInMemory(source, 400, ["--max-size", "3"])

    def test_streaming_keeps_every_pixel_type(self):
        for pixel_type in ("int8", "float32", "uint64", "int64"):
            with self.subTest(pixel_type=pixel_type):
                source = self.make_labels("in-%s.mha" % pixel_type, pixel_type, 3, 5, 40, 30, 24)
                expected, _, statistics = self.reference(source, k=3)
                streamed = self.streamed_run(source, self.path("out-%s.nrrd" % pixel_type), 512, ["--max-size", "3"])
                self.assertEqualImages(self.path("out-%s.nrrd" % pixel_type), expected, pixel_type)
                self.assertEqual(streamed["statistics"]["modified_voxels"], statistics["modified_voxels"])
                info = json.loads(self.check(run(PROBE, "info", self.path("out-%s.nrrd" % pixel_type))).stdout)
                self.assertEqual(info["pixel_type"], pixel_type)

    def test_refuses_to_overwrite_the_input(self):
        source = self.make_labels("in.nrrd", "int16", 2)
        with open(source, "rb") as file:
            before = file.read()
        for arguments in ([source], [self.path("out.nrrd"), "--removed-mask", source],
                          [self.path("out.nrrd"), "--stats", source]):
            with self.subTest(arguments=arguments):
                self.assertUsageError(run(FILTER, source, *arguments, "--labels"), "input")
                with open(source, "rb") as file:
                    self.assertEqual(file.read(), before)
                self.assertEqual(os.listdir(self.dir), ["in.nrrd"])


if __name__ == "__main__":
    unittest.main(verbosity=2, argv=sys.argv[:1] + sys.argv[1:])
