#!/usr/bin/env python3
"""smalliso.dask on one machine's dask.distributed clusters: a synthetic uint8 volume of
--gigabytes (blobs with specks and bubbles, stored as a Zarr array of --stored-chunk^3 chunks)
filtered into a new Zarr array with its statistics, in tasks of --chunk^3 voxels, by a LocalCluster
of each --workers count (worker processes of one thread each). Measured per run: wall time; the
statistics' merges (their summed task time, and the tail from the end of the last chunk's task to
the statistics, which nothing overlaps); each worker's peak resident memory (VmHWM, reset before
the run) and its resident memory at the start; the bytes the workers fetched from each other; the
time and output bytes of every kind of task (filters, summaries, merges, stores); each worker's
user and system time and minor page faults. Then, in this process, what a filter task is held
against: per task box, the in-memory filter on the box (one thread) and the Zarr codec's time to
read the box and write the chunk.

  PYTHONPATH=build/python python3 benchmark/python/dask_cluster.py --gigabytes 2 --directory DIR

It needs about twice --gigabytes of disk in --directory (the input and the output, both removed
afterwards) and is meant for a quiet machine: on a busy one the times say little."""

import argparse
import itertools
import json
import os
import resource
import shutil
import sys
import time

import dask
import dask.array as da
import numpy as np
import zarr
from dask.utils import key_split
from distributed import Client, LocalCluster, get_task_stream

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import memory  # noqa: E402
import volumes  # noqa: E402

import smalliso.dask  # noqa: E402


def make_input(path, edge, chunk, stored_chunk):
    """Writes the blobs volume of edge^3 voxels as a Zarr array of stored_chunk^3 chunks, a task
    chunk at a time."""
    def block(_, block_info=None):
        location = block_info[None]["array-location"]
        return volumes.blobs(tuple(e - b for b, e in location), tuple(b for b, _ in location))

    target = zarr.open_array(path, mode="w", shape=(edge,) * 3, chunks=(stored_chunk,) * 3, dtype=np.uint8)
    template = da.empty((edge,) * 3, dtype=np.uint8, chunks=chunk)
    da.map_blocks(block, template, dtype=np.uint8).store(target, lock=False)


def _worker_memory(dask_worker=None):
    current, peak = memory.resident_bytes()
    return {"rss": current, "peak": peak}


def _worker_reset(dask_worker=None):
    memory.reset_peak()


def _worker_usage(dask_worker=None):
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return {"user": usage.ru_utime, "system": usage.ru_stime, "minor_faults": usage.ru_minflt}


def _worker_fetched_bytes(dask_worker):
    return sum(entry["total"] for entry in dask_worker.transfer_incoming_log)


def run(source, target, workers, arguments):
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      memory_limit=0) as cluster, Client(cluster) as client:
        client.run(_worker_reset)
        before = client.run(_worker_memory)
        usage_before = client.run(_worker_usage)
        with get_task_stream(client) as stream:
            begin = time.perf_counter()
            stats = smalliso.dask.remove_small_components_zarr(source, target, volumes.SYNTHETIC_ISOVALUE, arguments.k,
                                                               arguments.side, client=client, chunks=arguments.chunk)
            wall = time.perf_counter() - begin
        after = client.run(_worker_memory)
        usage_after = client.run(_worker_usage)
        fetched = sum(client.run(_worker_fetched_bytes).values())
    groups = {}
    for record in stream.data:
        group = groups.setdefault(key_split(record["key"]), {"tasks": 0, "seconds": 0.0, "bytes": 0, "max_bytes": 0,
                                                              "end": 0.0})
        compute = [s for s in record["startstops"] if s["action"] == "compute"]
        group["tasks"] += 1
        group["seconds"] += sum(s["stop"] - s["start"] for s in compute)
        group["bytes"] += record.get("nbytes", 0)
        group["max_bytes"] = max(group["max_bytes"], record.get("nbytes", 0))
        group["end"] = max([group["end"]] + [s["stop"] for s in compute])
    # The merges overlap the chunks' work; what is left after the last chunk task is the serial tail.
    last_chunk_task = max(groups[name]["end"] for name in ("smalliso-filter", "smalliso-summary"))
    merge_tail = groups["smalliso-statistics"]["end"] - last_chunk_task
    return {
        "workers": workers, "wall_seconds": wall,
        "merge_task_seconds": groups.get("smalliso-merge", {}).get("seconds", 0.0), "merge_tail_seconds": merge_tail,
        "worker_peak_bytes": [after[w]["peak"] for w in sorted(after)],
        "worker_baseline_bytes": [before[w]["rss"] for w in sorted(after)],
        "fetched_between_workers_bytes": fetched,
        "worker_usage": [{key: usage_after[w][key] - usage_before[w][key] for key in usage_after[w]}
                         for w in sorted(after)],
        "tasks": {name: {k: v for k, v in group.items() if k != "end"} for name, group in sorted(groups.items())},
        "removed": {"above": stats["above"]["removed_components"], "below": stats["below"]["removed_components"]},
    }


def task_reference(source, arguments):
    """Per task box, in this process: the Zarr codec reading the box, the in-memory filter of the
    box at one thread, and the codec writing the chunk (into a scratch array like the output)."""
    stored = zarr.open_array(source, mode="r")
    halo = smalliso._core.box_halo(arguments.k, arguments.side)
    scratch = zarr.open_array(os.path.join(arguments.directory, "smalliso-benchmark-scratch.zarr"), mode="w",
                              shape=stored.shape, chunks=stored.chunks, dtype=stored.dtype)
    # This process's allocations are reused between boxes, as a worker's are between tasks.
    smalliso._core.keep_freed_memory()
    totals = {"tasks": 0, "read_box_seconds": 0.0, "in_memory_seconds": 0.0, "write_chunk_seconds": 0.0}
    starts = [range(0, extent, arguments.chunk) for extent in stored.shape]
    for begin in itertools.product(*starts):
        end = [min(b + arguments.chunk, extent) for b, extent in zip(begin, stored.shape)]
        box = tuple(slice(max(b - halo, 0), min(e + halo, extent)) for b, e, extent in zip(begin, end, stored.shape))
        crop = tuple(slice(b - s.start, e - s.start) for b, e, s in zip(begin, end, box))
        t0 = time.perf_counter()
        values = stored[box]
        t1 = time.perf_counter()
        output = smalliso.remove_small_components(values, volumes.SYNTHETIC_ISOVALUE, max_size=arguments.k,
                                                  side=arguments.side, threads=1)
        t2 = time.perf_counter()
        scratch[tuple(slice(b, e) for b, e in zip(begin, end))] = output[crop]
        t3 = time.perf_counter()
        totals["tasks"] += 1
        totals["read_box_seconds"] += t1 - t0
        totals["in_memory_seconds"] += t2 - t1
        totals["write_chunk_seconds"] += t3 - t2
    shutil.rmtree(scratch.store.path, ignore_errors=True)
    return totals


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gigabytes", type=float, default=2.0, help="size of the volume (default 2)")
    parser.add_argument("--chunk", type=int, default=256, help="edge of the tasks' chunks (default 256: 16 MiB)")
    parser.add_argument("--stored-chunk", type=int, default=64,
                        help="edge of the Zarr array's chunks, which divides --chunk (default 64)")
    parser.add_argument("--k", type=int, default=20, help="K (default 20)")
    parser.add_argument("--side", default="both", help="the side (default both)")
    parser.add_argument("--workers", default="1,2", help="worker counts, one cluster each (default 1,2)")
    parser.add_argument("--directory", required=True, help="where to put the Zarr arrays (removed afterwards)")
    parser.add_argument("--json", metavar="FILE", help="also write the results as JSON")
    arguments = parser.parse_args()

    edge = int(round((arguments.gigabytes * 1e9) ** (1 / 3)))
    source = os.path.join(arguments.directory, "smalliso-benchmark-input.zarr")
    target = os.path.join(arguments.directory, "smalliso-benchmark-output.zarr")
    begin = time.perf_counter()
    with dask.config.set(scheduler="threads"):
        make_input(source, edge, arguments.chunk, arguments.stored_chunk)
    print(f"input: {edge}^3 uint8 voxels ({edge**3 / 1e9:.2f} GB), tasks of {arguments.chunk}^3 voxels, stored in "
          f"chunks of {arguments.stored_chunk}^3; made in {time.perf_counter() - begin:.1f} s", flush=True)
    results = []
    try:
        for workers in (int(w) for w in arguments.workers.split(",")):
            result = run(source, target, workers, arguments)
            results.append(result)
            shutil.rmtree(target)
            print(json.dumps({k: v for k, v in result.items() if k != "tasks"}), flush=True)
        reference = task_reference(source, arguments)
        print(json.dumps({"reference": reference}), flush=True)
    finally:
        shutil.rmtree(source, ignore_errors=True)
        shutil.rmtree(target, ignore_errors=True)
    chunk_bytes = arguments.chunk**3
    print("| workers | wall s | merge tasks s | merge tail s | tail / wall | peak per worker MiB | above its start, "
          "in chunks | fetched between workers MiB | summaries and merges MiB |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in results:
        peak = max(r["worker_peak_bytes"])
        extra = max(p - b for p, b in zip(r["worker_peak_bytes"], r["worker_baseline_bytes"]))
        summaries = r["tasks"]["smalliso-summary"]["bytes"] + r["tasks"].get("smalliso-merge", {}).get("bytes", 0)
        print(f"| {r['workers']} | {r['wall_seconds']:.1f} | {r['merge_task_seconds']:.2f} | "
              f"{r['merge_tail_seconds']:.2f} | {100 * r['merge_tail_seconds'] / r['wall_seconds']:.1f} % | "
              f"{peak / 2**20:.0f} | {extra / chunk_bytes:.1f} | {r['fetched_between_workers_bytes'] / 2**20:.0f} | "
              f"{summaries / 2**20:.1f} |")
    print("| workers | worker user s | worker system s | minor faults (M) | filter + store task s, mean | in-memory "
          "filter on the box s | codec: read box + write chunk s | (task - codec) / in-memory |")
    print("|---|---|---|---|---|---|---|---|")
    n = reference["tasks"]
    codec = (reference["read_box_seconds"] + reference["write_chunk_seconds"]) / n
    in_memory = reference["in_memory_seconds"] / n
    for r in results:
        usage = r["worker_usage"]
        stores = sum(group["seconds"] for name, group in r["tasks"].items() if name.startswith("store"))
        task = (r["tasks"]["smalliso-filter"]["seconds"] + stores) / n
        print(f"| {r['workers']} | {sum(u['user'] for u in usage):.1f} | {sum(u['system'] for u in usage):.1f} | "
              f"{sum(u['minor_faults'] for u in usage) / 1e6:.2f} | {task:.3f} | {in_memory:.3f} | {codec:.3f} | "
              f"{(task - codec) / in_memory:.1f} |")
    if arguments.json:
        with open(arguments.json, "w") as stream:
            json.dump({"edge": edge, "chunk": arguments.chunk, "stored_chunk": arguments.stored_chunk, "k": arguments.k,
                       "side": arguments.side, "results": results,
                       "reference": reference}, stream, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
