#!/usr/bin/env python3
"""smalliso.remove_small_label_components against the ways Python users clean label maps today, on
one job: the islands of every label but 0 of at most K voxels, face connectivity.

  smalliso        remove_small_label_components(map, K, select="islands"): removed voxels repaired
  scipy-per-label TotalSegmentator's way: scipy.ndimage.label(map == l) for each label l, the
                  components of at most K voxels set to 0
  skimage         skimage.measure.label(map, background=0, connectivity=1) (components of equal
                  labels), then remove_small_objects(min_size=K + 1): removed voxels set to 0

The peers do less: they set removed voxels to 0 and fill no holes. The command checks that all of
them remove the same voxels (smalliso's removed mask against the voxels a peer set to 0), and
measures each tool as compare.py does: in a fresh process, the median wall time of --repeat runs
after one warm-up run, and the peak resident memory beyond the loaded map. smalliso runs with
ITK's default threads (the machine's cores) and with one; the peers use one.

  PYTHONPATH=build/python python3 benchmark/python/compare_labels.py [--data-dir DATA_DIR] [--json FILE]
"""

import argparse
import json
import os
import sys

import numpy as np
import smalliso
from scipy import ndimage
from skimage.measure import label
from skimage.morphology import remove_small_objects

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import memory  # noqa: E402
import volumes  # noqa: E402

TOOLS = ("smalliso", "smalliso-1-thread", "scipy-per-label", "skimage")


def removed_voxels(tool, labels, k):
    """The voxels the tool removes from the islands of every label but 0."""
    if tool.startswith("smalliso"):
        threads = 1 if tool == "smalliso-1-thread" else None
        _, mask = smalliso.remove_small_label_components(labels, k, select="islands", return_mask=True,
                                                          threads=threads)
        return mask.astype(bool)
    if tool == "scipy-per-label":
        output = labels.copy()
        for value in np.unique(labels):
            if value == 0:
                continue
            components, _ = ndimage.label(labels == value)
            small = np.bincount(components.ravel()) <= k
            small[0] = False
            output[small[components]] = 0
        return (labels != 0) & (output == 0)
    components = label(labels, background=0, connectivity=1)
    return (components != 0) & (remove_small_objects(components, min_size=k + 1) == 0)


def measure(arguments):
    """One measurement, in this (fresh) process: prints its JSON on stdout."""
    labels = volumes.load_labels(arguments.map, arguments.data_dir, arguments.size)
    result = memory.time_and_peak(lambda: removed_voxels(arguments.tool, labels, arguments.k), arguments.repeat)
    json.dump(dict(result, voxels=labels.size, labels=len(np.unique(labels))), sys.stdout)


def agree(name, arguments):
    """Whether every tool removes the voxels smalliso removes."""
    labels = volumes.load_labels(name, arguments.data_dir, arguments.size)
    ours = removed_voxels("smalliso", labels, arguments.k)
    return all(np.array_equal(ours, removed_voxels(tool, labels, arguments.k)) for tool in TOOLS[1:])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    memory.add_options(parser, "edge of the synthetic map")
    parser.add_argument("--measure", nargs=2, metavar=("MAP", "TOOL"), help=argparse.SUPPRESS)
    arguments = parser.parse_args()
    if arguments.measure:
        arguments.map, arguments.tool = arguments.measure
        measure(arguments)
        return 0

    names = []
    if arguments.data_dir:
        names = [name for name in volumes.REAL_LABEL_MAPS
                 if os.path.exists(os.path.join(arguments.data_dir, "labels", name + ".nii.gz"))]
    else:
        print("compare_labels: no --data-dir: the real label maps are left out", file=sys.stderr)
    names.append("synthetic")
    results = []
    print("| map | voxels | labels | tool | seconds | ratio to smalliso | peak extra MiB | same voxels removed |")
    print("|---|---|---|---|---|---|---|---|")
    for name in names:
        same = agree(name, arguments)
        ours = None
        for tool in TOOLS:
            result = memory.in_fresh_process(os.path.abspath(__file__), arguments, name, tool)
            ours = ours or result["seconds"]
            result.update(map=name, tool=tool, agree=same)
            results.append(result)
            print(f"| {name} | {result['voxels']} | {result['labels']} | {tool} | {result['seconds']:.4f} | "
                  f"{result['seconds'] / ours:.1f} | {result['peak_extra_bytes'] / 2**20:.0f} | "
                  f"{'yes' if same else 'NO'} |", flush=True)
    memory.write_json(arguments, results)
    return 0 if all(result["agree"] for result in results) else 1


if __name__ == "__main__":
    sys.exit(main())
