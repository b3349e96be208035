#!/usr/bin/env python3
# Copyright SmallIsoComponent contributors. Licensed under the Apache License, Version 2.0.
"""SmallIsoComponentFilter and SmallIsoComponentLabelFilter as 3D Slicer sees them: their --xml read by
Slicer's own parser (SlicerExecutionModel's ModuleDescriptionParser, through
SmallIsoComponentSlicerParserProbe), every parameter checked against the description the tool wrote,
then the tool run with the command line Slicer builds from the parsed description.

Environment:
  SIC_FILTER         the SmallIsoComponentFilter executable
  SIC_LABEL_FILTER   the SmallIsoComponentLabelFilter executable
  SIC_PHANTOM        the SmallIsoComponentPhantom executable
  SIC_PROBE          the SmallIsoComponentCLITestProbe executable (counts mask voxels)
  SIC_SLICER_PROBE   the parser probe; empty when no SlicerExecutionModel was found (then every
                     test says so and is skipped)
  SIC_SLICER_SOURCE  where SlicerExecutionModel came from, for the messages
  SIC_SCRATCH        a directory for scratch files
"""

import hashlib
import json
import os
import sys
import unittest
import xml.dom.minidom

from sic_tool_test import ToolTestCase, run

FILTER = os.environ.get("SIC_FILTER", "")
LABEL_FILTER = os.environ.get("SIC_LABEL_FILTER", "")
PHANTOM = os.environ.get("SIC_PHANTOM", "")
PROBE = os.environ.get("SIC_PROBE", "")
SLICER_PROBE = os.environ.get("SIC_SLICER_PROBE", "")
SLICER_SOURCE = os.environ.get("SIC_SLICER_SOURCE", "")

# What the description's elements are called for each field the parser reports.
FIELDS = ("name", "flag", "longflag", "label", "default", "channel", "index")
CONSTRAINTS = ("minimum", "maximum", "step")


def text(element, tag):
    found = [child for child in element.childNodes if child.nodeType == child.ELEMENT_NODE and child.tagName == tag]
    return found[0].firstChild.data.strip() if found and found[0].firstChild else ""


def digest(path):
    with open(path, "rb") as file:
        return hashlib.sha256(file.read()).hexdigest()


class SmallIsoComponentSlicerTest(ToolTestCase):
    def setUp(self):
        if not SLICER_PROBE:
            print("skipped: no SlicerExecutionModel to build Slicer's parser from (" + SLICER_SOURCE + ")")
            raise unittest.SkipTest("no SlicerExecutionModel")
        super().setUp()
        self.describe(FILTER)

    def describe(self, tool):
        """Reads the tool's --xml, as written and as Slicer's parser reads it."""
        self.xml = self.check(run(tool, "--xml")).stdout
        self.xml_path = self.path("description.xml")
        with open(self.xml_path, "w", encoding="utf-8") as file:
            file.write(self.xml)
        self.parsed = json.loads(self.check(run(SLICER_PROBE, self.xml_path)).stdout)

    def written(self):
        """The parameters as the tool wrote them, read with Python's own XML parser."""
        document = xml.dom.minidom.parseString(self.xml)
        parameters = []
        for group in document.getElementsByTagName("parameters"):
            label = text(group, "label")
            for element in group.childNodes:
                if element.nodeType != element.ELEMENT_NODE or element.tagName in ("label", "description"):
                    continue
                entry = {"group": label, "tag": element.tagName}
                for field in FIELDS:
                    entry[field] = text(element, field)
                # Slicer's parser keeps flags without their dashes.
                entry["flag"] = entry["flag"].lstrip("-")
                entry["longflag"] = entry["longflag"].lstrip("-")
                constraints = [child for child in element.childNodes
                               if child.nodeType == child.ELEMENT_NODE and child.tagName == "constraints"]
                for field in CONSTRAINTS:
                    entry[field] = text(constraints[0], field) if constraints else ""
                entry["elements"] = [e.firstChild.data.strip() for e in element.getElementsByTagName("element")]
                entry["hidden"] = element.getAttribute("hidden") or "false"
                parameters.append(entry)
        return document, parameters

    def test_parser_reads_every_parameter_as_written(self):
        self.assertParsedAsWritten()

    def test_parser_reads_the_label_tool_as_written(self):
        self.describe(LABEL_FILTER)
        self.assertParsedAsWritten()
        images = {p["name"]: p for p in self.parsed["parameters"] if p["tag"] == "image"}
        self.assertEqual(sorted(images), ["inputVolume", "outputVolume", "removedMask"])
        document = xml.dom.minidom.parseString(self.xml)
        for element in document.getElementsByTagName("image"):
            self.assertEqual(element.getAttribute("type"), "label")

    def assertParsedAsWritten(self):
        document, written = self.written()
        root = document.documentElement
        self.assertEqual(self.parsed["title"], text(root, "title"))
        self.assertEqual(self.parsed["category"], text(root, "category"))
        self.assertEqual(self.parsed["version"], text(root, "version"))
        parsed = self.parsed["parameters"]
        self.assertEqual([p["name"] for p in parsed], [p["name"] for p in written])
        for mine, slicers in zip(written, parsed):
            for field in ("group", "tag", "hidden", "elements") + FIELDS + CONSTRAINTS:
                self.assertEqual(slicers[field], mine[field], "%s of parameter %s" % (field, mine["name"]))
            # Every parameter is one Slicer can pass: an index, or a flag.
            self.assertTrue(slicers["index"] or slicers["longflag"] or slicers["flag"], mine["name"])
            if slicers["tag"] in ("image", "file"):
                self.assertIn(slicers["channel"], ("input", "output"), mine["name"])

    def slicer_command_line(self, values):
        """The command line Slicer builds from the parsed description: every flagged parameter in
        description order with its value (booleans as a bare flag when true), then the indexed ones
        in index order."""
        arguments, indexed = [], {}
        for parameter in self.parsed["parameters"]:
            value = values.get(parameter["name"], parameter["default"])
            if parameter["index"]:
                indexed[int(parameter["index"])] = value
                continue
            flag = "--" + parameter["longflag"] if parameter["longflag"] else "-" + parameter["flag"]
            if parameter["tag"] == "boolean":
                arguments += [flag] if value == "true" else []
            elif value != "":
                arguments += [flag, value]
        return arguments + [indexed[i] for i in sorted(indexed)]

    def test_the_command_line_slicer_builds_runs(self):
        phantom = self.path("phantom.nrrd")
        self.check(run(PHANTOM, phantom, "--size", "40"))
        values = {"inputVolume": phantom, "outputVolume": self.path("out.nrrd"),
                  "removedMask": self.path("mask.nrrd"), "statsFile": self.path("stats.json"),
                  "isovalue": "150", "maximumSize": "20"}
        if any(p["name"] == "render" for p in self.parsed["parameters"]):
            values.update({"surface": self.path("surface.vtp"), "surfaceBefore": self.path("before.vtp"),
                           "render": self.path("panels.png")})
        arguments = self.slicer_command_line(values)
        result = self.check(run(FILTER, *arguments), " ".join(arguments))
        self.assertIn("<filter-progress>", result.stdout)
        # The same work asked for with the tool's own flags gives the same files.
        direct = self.path("direct.nrrd")
        self.check(run(FILTER, phantom, direct, "--isovalue", "150", "--max-size", "20", "--quiet"))
        self.assertEqual(digest(self.path("out.nrrd")), digest(direct))
        with open(self.path("stats.json"), encoding="utf-8") as file:
            modified = json.load(file)["statistics"]["modified_voxels"]
        self.assertGreater(modified, 0)
        self.assertEqual(int(self.check(run(PROBE, "count-nonzero", self.path("mask.nrrd"))).stdout), modified)
        for name in ("surface", "surfaceBefore", "render"):
            if name in values:
                self.assertTrue(os.path.exists(values[name]), name)

    def test_the_command_line_slicer_builds_runs_the_label_tool(self):
        self.describe(LABEL_FILTER)
        labels = self.path("labels.nrrd")
        self.check(run(PROBE, "make-labels", labels, "int16", 3, 5))
        values = {"inputVolume": labels, "outputVolume": self.path("out.nrrd"), "removedMask": self.path("mask.nrrd"),
                  "statsFile": self.path("stats.json"), "maxSize": "4", "maxSizePerLabel": "2=1",
                  "keepLargest": "1"}
        arguments = self.slicer_command_line(values)
        result = self.check(run(LABEL_FILTER, *arguments), " ".join(arguments))
        self.assertIn("<filter-progress>", result.stdout)
        direct = self.path("direct.nrrd")
        self.check(run(FILTER, labels, direct, "--labels", "--max-size", "4", "--max-size-of", "2=1",
                       "--keep-largest", "1", "--quiet"))
        self.assertEqual(digest(self.path("out.nrrd")), digest(direct))
        with open(self.path("stats.json"), encoding="utf-8") as file:
            statistics = json.load(file)["statistics"]
        removed = sum(label["removed_voxels"] for label in statistics["labels"].values())
        self.assertGreater(removed, 0)
        self.assertEqual(int(self.check(run(PROBE, "count-nonzero", self.path("mask.nrrd"))).stdout), removed)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
