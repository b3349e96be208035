#!/usr/bin/env python3
"""smalliso.remove_small_components against scikit-image on the jobs where they overlap:

  above  smalliso side "above"   remove_small_objects(volume >= S, min_size=K + 1, connectivity=1)
  below  smalliso side "below"   remove_small_holes(volume >= S, area_threshold=K + 1, connectivity=1)
  both   smalliso side "both"    remove_small_holes(remove_small_objects(...), ...)

scikit-image does less: it gives a binary image and repairs no values (its time includes the
threshold that makes its input). The binary results are checked against each other (smalliso's
filtered volume >= S against scikit-image's), and each measurement runs in a fresh process: the
median wall time of --repeat runs after one warm-up run, and the peak resident memory beyond the
loaded volume (Linux's VmHWM, reset after loading, so C++ allocations count). smalliso runs with
ITK's default threads (the machine's cores) and with one; scikit-image uses one.

  PYTHONPATH=build/python python3 benchmark/python/compare.py [--data-dir DATA_DIR] [--json FILE]
"""

import argparse
import json
import os
import sys

import numpy as np
import smalliso
from skimage.morphology import remove_small_holes, remove_small_objects

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import memory  # noqa: E402
import volumes  # noqa: E402

JOBS = ("above", "below", "both")
TOOLS = ("smalliso", "smalliso-1-thread", "skimage")


def run_job(tool, job, volume, isovalue, k):
    """The tool's result: smalliso's filtered volume, scikit-image's binary image."""
    if tool.startswith("smalliso"):
        threads = 1 if tool == "smalliso-1-thread" else None
        return smalliso.remove_small_components(volume, isovalue, k, job, threads=threads)
    above = volume >= isovalue
    if job in ("above", "both"):
        above = remove_small_objects(above, min_size=k + 1, connectivity=1)
    if job in ("below", "both"):
        above = remove_small_holes(above, area_threshold=k + 1, connectivity=1)
    return above


def measure(arguments):
    """One measurement, in this (fresh) process: prints its JSON on stdout."""
    volume, isovalue = volumes.load(arguments.volume, arguments.data_dir, arguments.size)
    result = memory.time_and_peak(lambda: run_job(arguments.tool, arguments.job, volume, isovalue, arguments.k),
                                  arguments.repeat)
    json.dump(dict(result, volume_bytes=volume.nbytes), sys.stdout)


def agree(name, arguments):
    """Whether smalliso's and scikit-image's binary results are equal for every job."""
    volume, isovalue = volumes.load(name, arguments.data_dir, arguments.size)
    return {job: bool(np.array_equal(run_job("smalliso", job, volume, isovalue, arguments.k) >= isovalue,
                                     run_job("skimage", job, volume, isovalue, arguments.k))) for job in JOBS}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    memory.add_options(parser, "edge of the synthetic volumes")
    parser.add_argument("--measure", nargs=3, metavar=("VOLUME", "JOB", "TOOL"), help=argparse.SUPPRESS)
    arguments = parser.parse_args()
    if arguments.measure:
        arguments.volume, arguments.job, arguments.tool = arguments.measure
        measure(arguments)
        return 0

    names = ["noise", "blobs"]
    if arguments.data_dir:
        names += [name for name in volumes.REAL_VOLUMES
                  if os.path.exists(os.path.join(arguments.data_dir, name + ".nrrd"))]
    else:
        print("compare: no --data-dir: the real volumes are left out", file=sys.stderr)
    results = []
    print("| volume | job | tool | seconds | peak extra MiB | binary results agree |")
    print("|---|---|---|---|---|---|")
    for name in names:
        agreement = agree(name, arguments)
        for job in JOBS:
            for tool in TOOLS:
                result = memory.in_fresh_process(os.path.abspath(__file__), arguments, name, job, tool)
                result.update(volume=name, job=job, tool=tool, agree=agreement[job])
                results.append(result)
                print(f"| {name} | {job} | {tool} | {result['seconds']:.3f} | "
                      f"{result['peak_extra_bytes'] / 2**20:.0f} | {'yes' if agreement[job] else 'NO'} |", flush=True)
    memory.write_json(arguments, results)
    return 0 if all(result["agree"] for result in results) else 1


if __name__ == "__main__":
    sys.exit(main())
