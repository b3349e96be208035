"""How the comparisons measure: each measurement in a fresh process, its wall time, and its peak
memory as Linux counts it (resident set, C++ allocations included), which tracemalloc's count of
Python's own allocations would miss."""

import json
import os
import statistics
import subprocess
import sys
import time


def resident_bytes():
    """(current, peak) resident set size of this process, from /proc/self/status."""
    fields = {}
    with open("/proc/self/status") as status:
        for line in status:
            key, _, value = line.partition(":")
            if key in ("VmRSS", "VmHWM"):
                fields[key] = int(value.split()[0]) * 1024
    return fields["VmRSS"], fields["VmHWM"]


def reset_peak():
    """Starts a new peak: the kernel sets VmHWM back to the current resident size."""
    with open("/proc/self/clear_refs", "w") as clear:
        clear.write("5")


def time_and_peak(call, repeat):
    """Runs ``call`` once to warm up, then ``repeat`` timed times: the median and every wall time in
    seconds, and the peak resident memory of the warm-up beyond this process's size before it."""
    baseline, _ = resident_bytes()
    reset_peak()
    call()
    _, peak = resident_bytes()
    seconds = []
    for _ in range(repeat):
        begin = time.perf_counter()
        call()
        seconds.append(time.perf_counter() - begin)
    return {"seconds": statistics.median(seconds), "runs": seconds, "peak_extra_bytes": peak - baseline}


def add_options(parser, size_help):
    """The options every comparison takes."""
    parser.add_argument("--data-dir", metavar="DATA_DIR", help="folder of the real volumes (label maps in its labels/)")
    parser.add_argument("--size", type=int, default=256, help=size_help + " (default 256)")
    parser.add_argument("--k", type=int, default=20, help="K, the maximum component size (default 20)")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per measurement (default 5)")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")


def in_fresh_process(script, arguments, *measure):
    """The JSON that ``script --measure MEASURE...`` prints, run with the comparison's options in a
    new interpreter."""
    command = [sys.executable, script, "--measure", *measure,
               "--size", str(arguments.size), "--k", str(arguments.k), "--repeat", str(arguments.repeat)]
    if arguments.data_dir:
        command += ["--data-dir", arguments.data_dir]
    return json.loads(subprocess.run(command, check=True, capture_output=True, text=True).stdout)


def write_json(arguments, results):
    """The results and the options they were measured with, in the --json file when one is named."""
    if arguments.json:
        with open(arguments.json, "w") as stream:
            json.dump({"k": arguments.k, "size": arguments.size, "repeat": arguments.repeat, "cores": os.cpu_count(),
                       "results": results}, stream, indent=2)
