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
import subprocess
import sys
import time

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
    baseline, _ = memory.resident_bytes()
    memory.reset_peak()
    run_job(arguments.tool, arguments.job, volume, isovalue, arguments.k)
    _, peak = memory.resident_bytes()
    seconds = []
    for _ in range(arguments.repeat):
        begin = time.perf_counter()
        run_job(arguments.tool, arguments.job, volume, isovalue, arguments.k)
        seconds.append(time.perf_counter() - begin)
    json.dump({"seconds": float(np.median(seconds)), "runs": seconds, "peak_extra_bytes": peak - baseline,
               "volume_bytes": volume.nbytes}, sys.stdout)


def agree(name, arguments):
    """Whether smalliso's and scikit-image's binary results are equal for every job."""
    volume, isovalue = volumes.load(name, arguments.data_dir, arguments.size)
    return {job: bool(np.array_equal(run_job("smalliso", job, volume, isovalue, arguments.k) >= isovalue,
                                     run_job("skimage", job, volume, isovalue, arguments.k))) for job in JOBS}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--data-dir", metavar="DATA_DIR", help="folder of the real volumes (aneurism, bonsai, lobster)")
    parser.add_argument("--size", type=int, default=256, help="edge of the synthetic volumes (default 256)")
    parser.add_argument("--k", type=int, default=20, help="K, the maximum component size (default 20)")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per measurement (default 5)")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
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
                command = [sys.executable, os.path.abspath(__file__), "--measure", name, job, tool,
                           "--size", str(arguments.size), "--k", str(arguments.k), "--repeat", str(arguments.repeat)]
                if arguments.data_dir:
                    command += ["--data-dir", arguments.data_dir]
                result = json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)
                result.update(volume=name, job=job, tool=tool, agree=agreement[job])
                results.append(result)
                print(f"| {name} | {job} | {tool} | {result['seconds']:.3f} | "
                      f"{result['peak_extra_bytes'] / 2**20:.0f} | {'yes' if agreement[job] else 'NO'} |", flush=True)
    if arguments.json:
        with open(arguments.json, "w") as stream:
            json.dump({"k": arguments.k, "size": arguments.size, "repeat": arguments.repeat, "cores": os.cpu_count(),
                       "results": results}, stream, indent=2)
    return 0 if all(result["agree"] for result in results) else 1


if __name__ == "__main__":
    sys.exit(main())
