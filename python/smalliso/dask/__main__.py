"""python3 -m smalliso.dask: filters a Zarr array into a new one with Dask, chunk by chunk."""

import argparse
import contextlib
import json
import os
import signal
import sys
import time

import dask
import zarr
from dask.array.core import normalize_chunks

import smalliso

from ._zarr import check_paths, filter_into_staging, open_input, stored_chunks

TOOL = "smalliso.dask"
LOCAL_SCHEDULERS = ("threads", "processes", "synchronous")


class _Parser(argparse.ArgumentParser):
    """Command-line errors in one line, exit status 2."""

    def error(self, message):
        self.exit(2, f"{TOOL}: error: {message} (see --help)\n")


def _chunk_sizes(text):
    try:
        sizes = tuple(int(size) for size in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a list of whole numbers such as 256 or 64,256,256")
    if any(size < 1 for size in sizes):
        raise argparse.ArgumentTypeError(f"{text!r}: chunk edges must be >= 1")
    return sizes[0] if len(sizes) == 1 else sizes


def _label_id(text):
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a label id; expected a whole number such as 3 or -1")


def _selection(text):
    word = text.strip().lower()
    if word in ("all", "islands", "holes"):
        return word
    try:
        return [int(item) for item in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a valid choice; expected all, islands, holes or label "
                                         "ids such as 3,5,12")


def _label_sizes(text):
    sizes = {}
    for item in text.split(","):
        label, equals, size = item.partition("=")
        try:
            sizes[int(label)] = int(size)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{item!r} is not L=K; expected a label id, '=' and a size in voxels, "
                                             "such as 7=500")
    return sizes


def _check_kind(parser, arguments):
    """Exactly one kind of image, and only its options."""
    label_options = [flag for flag, value in (("--select", arguments.select), ("--background", arguments.background),
                                              ("--max-size-of", arguments.max_size_of)) if value is not None]
    if arguments.labels:
        for flag, value in (("--isovalue", arguments.isovalue), ("--side", arguments.side)):
            if value is not None:
                parser.error(f"{flag} has no meaning for a label map (--labels)")
        sizes = {}
        for given in arguments.max_size_of or []:
            for label in given.keys() & sizes.keys():
                parser.error(f"--max-size-of gives label {label} more than one K; expected one K per label")
            sizes.update(given)
        return {"select": arguments.select or "all", "background": arguments.background or 0, "max_sizes": sizes}
    if label_options:
        parser.error(f"{label_options[0]} applies to label maps only; expected --labels with it")
    if arguments.isovalue is None:
        parser.error("the following arguments are required: --isovalue (or --labels for a label map)")
    arguments.side = arguments.side or "both"
    return None


def _parser():
    parser = _Parser(
        prog=f"python3 -m {TOOL}",
        description="Removes the small connected components on either side of an isovalue S from a 2-D or 3-D "
                    "Zarr array (specks of voxels >= S, bubbles of voxels < S), chunk by chunk with Dask, and "
                    "writes a new Zarr array with the same shape, chunks, dtype and compressor. The result is "
                    "voxel for voxel that of SmallIsoComponentFilter on the whole array (C order: the last axis "
                    "is x). The outputs appear together, only when all are complete: each is written beside "
                    "its path and all are then renamed into place. With --labels it cleans a label map instead, "
                    "as SmallIsoComponentFilter --labels does.")
    parser.add_argument("input", metavar="IN.zarr", help="the Zarr array to filter (a directory store)")
    parser.add_argument("output", metavar="OUT.zarr",
                        help="where to write the filtered array: a new path, or an earlier output (a Zarr array and "
                             "nothing else), which is replaced; anything else there is refused")
    parser.add_argument("--isovalue", metavar="S", type=float,
                        help="voxels with a value >= S are above it, all others (NaN included) below; required "
                             "unless --labels")
    parser.add_argument("--max-size", metavar="K", type=int, default=20,
                        help="components of at most K voxels are removed; 0 removes nothing (default 20)")
    parser.add_argument("--side", choices=("above", "below", "both"),
                        help="above removes specks, below bubbles, both does above and then below on its result "
                             "(default both)")
    parser.add_argument("--labels", action="store_true",
                        help="the array is a label map: each component of a selected label with at most K voxels "
                             "is removed and each of its voxels takes the label voted by the labels around it")
    parser.add_argument("--select", metavar="all|islands|holes|L,...", type=_selection,
                        help="with --labels, the labels whose small components are removed: all, islands (every "
                             "label but the background), holes (the background only) or label ids (default all)")
    parser.add_argument("--background", metavar="L", type=_label_id,
                        help="with --labels, the background's label id (default 0)")
    parser.add_argument("--max-size-of", metavar="L=K[,L=K...]", type=_label_sizes, action="append",
                        help="with --labels, label L's own K in voxels (repeatable)")
    parser.add_argument("--fully-connected", action="store_true",
                        help="connect voxels that share an edge or a corner too (26 neighbours in 3-D, 8 in 2-D), "
                             "not only a face")
    parser.add_argument("--removed-mask", metavar="MASK.zarr",
                        help="also write the mask of the changed voxels (uint8: 0 kept, 1 removed with an above "
                             "component, 2 with a below component; with --labels 1 for every removed voxel)")
    parser.add_argument("--scheduler", metavar="ADDRESS", default="threads",
                        help="threads, processes or synchronous (Dask's local schedulers), or the address of a "
                             "dask.distributed scheduler such as tcp://host:8786 (default threads)")
    parser.add_argument("--chunks", metavar="N[,N...]", type=_chunk_sizes,
                        help="the tasks' chunks, one edge for every axis or one per axis (NumPy order): whole "
                             "multiples of the input's stored chunks (default the stored chunks); each task reads "
                             "every stored chunk its chunk and halo overlap, so larger tasks read less twice")
    parser.add_argument("--threads", metavar="N", type=int, default=1,
                        help="threads of each task's C++ code (default 1: Dask runs the tasks in parallel)")
    parser.add_argument("--stats", metavar="FILE.json",
                        help="write the input's description, the parameters and every statistic as JSON")
    parser.add_argument("--quiet", action="store_true", help="no progress bar and no summary")
    return parser


def _document(arguments, info, parameters, statistics):
    """The statistics file: the input, the outputs, then ``parameters`` and ``statistics``."""
    return {
        "tool": TOOL,
        "version": smalliso.__version__,
        "input": {"path": arguments.input, "pixel_type": info["dtype"], "dimension": len(info["shape"]),
                  "size": list(reversed(info["shape"])), "chunks": list(reversed(info["chunks"])),
                  "missing_chunks": info["missing_chunks"]},
        "outputs": {"image": arguments.output, "removed_mask": arguments.removed_mask, "stats": arguments.stats},
        "parameters": {**parameters, "connectivity": "full" if arguments.fully_connected else "face",
                       "scheduler": arguments.scheduler, "threads": arguments.threads,
                       "chunks": list(reversed(info["task_chunks"]))},
        "statistics": statistics,
    }


def _statistics_json(arguments, labels, info, stats, seconds, total_seconds):
    """The statistics of SmallIsoComponentFilter in its form; a label map's (``labels``, its options) with label ids
    as strings, as SmallIsoComponentFilter --labels writes them."""
    def side(counts):
        return {"components": counts["components"], "removed_components": counts["removed_components"],
                "removed_voxels": counts["removed_voxels"],
                "size_histogram": [[size, number] for size, number in sorted(counts["size_histogram"].items())]}

    counts = {"modified_voxels": stats["modified_voxels"], "unrepairable_voxels": stats["unrepairable_voxels"],
              "seconds": seconds, "total_seconds": total_seconds}
    if labels is None:
        parameters = {"isovalue": arguments.isovalue, "max_size": arguments.max_size,
                      "effective_max_size": stats["effective_max_size"], "side": arguments.side}
        return _document(arguments, info, parameters,
                         {"above": side(stats["above"]), "below": side(stats["below"]), **counts})
    listed = not isinstance(labels["select"], str)
    parameters = {"labels": True, "max_size": arguments.max_size, "effective_max_size": stats["effective_max_size"],
                  "selection": "listed" if listed else labels["select"]}
    if listed:
        parameters["selected_labels"] = [str(label) for label in labels["select"]]
    parameters["background"] = str(labels["background"])
    parameters["max_size_of"] = {str(label): size for label, size in labels["max_sizes"].items()}
    return _document(arguments, info, parameters,
                     {"labels": {str(label): entry for label, entry in stats["labels"].items()}, **counts})


def _summary(arguments, stats, seconds):
    if arguments.labels:
        removed = sum(counts["removed_voxels"] for counts in stats["labels"].values())
        return (f"Label map, K = {stats['effective_max_size']} voxels, "
                f"{'full' if arguments.fully_connected else 'face'} connectivity: removed {removed} voxels; "
                f"{stats['modified_voxels']} voxels modified, {stats['unrepairable_voxels']} unrepairable. "
                f"Filter {seconds:.3f} s ({arguments.scheduler}).")
    above, below = stats["above"], stats["below"]
    return (f"Isovalue {arguments.isovalue:g}, K = {stats['effective_max_size']} voxels, side {arguments.side}, "
            f"{'full' if arguments.fully_connected else 'face'} connectivity: removed "
            f"{above['removed_components']} of {above['components']} above components ({above['removed_voxels']} "
            f"voxels) and {below['removed_components']} of {below['components']} below components "
            f"({below['removed_voxels']} voxels); {stats['modified_voxels']} voxels modified, "
            f"{stats['unrepairable_voxels']} unrepairable. Filter {seconds:.3f} s ({arguments.scheduler}).")


def _json_text(value, indent=""):
    """JSON laid out for reading: objects one key a line, lists of numbers on one line, lists of
    lists one inner list a line (the command-line tool writes the same members, laid out by its
    JSON library)."""
    inner = indent + "  "
    if isinstance(value, dict):
        items = [f"{inner}{json.dumps(key)}: {_json_text(item, inner)}" for key, item in value.items()]
        return "{\n" + ",\n".join(items) + f"\n{indent}}}" if items else "{}"
    if isinstance(value, list) and any(isinstance(item, (dict, list)) for item in value):
        return "[\n" + ",\n".join(inner + _json_text(item, inner) for item in value) + f"\n{indent}]"
    if isinstance(value, list):
        return "[" + ", ".join(json.dumps(item) for item in value) + "]"
    return json.dumps(value)


@contextlib.contextmanager
def _scheduler(name):
    """None while one of Dask's local schedulers is the scheduler, or a client of a cluster."""
    if name in LOCAL_SCHEDULERS:
        with dask.config.set(scheduler=name):
            yield None
    else:
        from distributed import Client
        try:
            # Not made Dask's default: one that fails to connect would stay the default of the process.
            client = Client(name, timeout="10s", set_as_default=False)
        except OSError as error:
            raise ValueError(f"cannot reach a dask.distributed scheduler at --scheduler {name!r} ({error})") from None
        except (TypeError, ValueError) as error:
            raise ValueError(f"--scheduler {name!r} is not a scheduler ({error}); expected threads, processes, "
                             "synchronous or the address of a dask.distributed scheduler such as tcp://host:8786")
        with client:
            yield client


# Termination signals end the command as SIGINT does: the staged outputs are removed, one line
# says so, and the process ends as the signal asks. While the outputs are being put in place, a
# signal waits until all of them are, so that it leaves every output of one run.
_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
# The signals received while they are held (None while they are not).
_held = None


class _Stopped(KeyboardInterrupt):
    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


def _stop(signum, frame):
    if _held is not None:
        _held.append(signum)
        return
    # One clean-up: a second signal must not interrupt the first one's.
    for other in _SIGNALS:
        signal.signal(other, signal.SIG_IGN)
    raise _Stopped(signum)


@contextlib.contextmanager
def _signals_held():
    """Holds the termination signals until the block ends, then stops by the first one received."""
    global _held
    _held = []
    try:
        yield
    finally:
        received, _held = _held, None
        if received:
            _stop(received[0], None)


def main(argv=None):
    start = time.perf_counter()
    # The command's process only runs the filter: its tasks may keep what they free for the next.
    smalliso._core.keep_freed_memory()
    parser = _parser()
    arguments = parser.parse_args(argv)
    labels = _check_kind(parser, arguments)
    outputs = [arguments.output] + ([arguments.removed_mask] if arguments.removed_mask is not None else [])
    files = [arguments.stats] if arguments.stats is not None else []
    handlers = {signum: signal.signal(signum, _stop) for signum in _SIGNALS}
    before = [_identity(path) for path in outputs + files]
    staged = None
    try:
        try:
            check_paths(arguments.input, outputs, files)
            stored = open_input(arguments.input)
            missing = stored.nchunks - stored_chunks(arguments.input, stored)
            if missing:
                print(f"{TOOL}: note: {missing} of the {stored.nchunks} chunks of {arguments.input!r} are not "
                      f"stored; Zarr reads them as the fill value {stored.fill_value}", file=sys.stderr)
            with _scheduler(arguments.scheduler) as client:
                begin = time.perf_counter()
                stats, staged = filter_into_staging(
                    arguments.input, arguments.output, arguments.isovalue, arguments.max_size, arguments.side,
                    arguments.fully_connected, removed_mask=arguments.removed_mask, client=client,
                    progress=not arguments.quiet, threads=arguments.threads, chunks=arguments.chunks, labels=labels)
                seconds = time.perf_counter() - begin
            info = {"dtype": str(stored.dtype), "shape": list(stored.shape), "chunks": list(stored.chunks),
                    "missing_chunks": missing,
                    "task_chunks": [extents[0] for extents in normalize_chunks(
                        stored.chunks if arguments.chunks is None else arguments.chunks, stored.shape)]}
            if arguments.stats is not None:
                total = time.perf_counter() - start
                document = _statistics_json(arguments, labels, info, stats, seconds, total)
                staged.stage_file(arguments.stats, _json_text(document) + "\n")
            with _signals_held():
                staged.commit()
        finally:
            if staged is not None:
                staged.discard()
        if not arguments.quiet:
            print(_summary(arguments, stats, seconds))
    except KeyboardInterrupt as stop:
        written = [path for path, identity in zip(outputs + files, before) if _identity(path) != identity]
        _end_by_signal(getattr(stop, "signum", signal.SIGINT), written)
    except (TypeError, ValueError) as error:
        print(f"{TOOL}: error: {error}", file=sys.stderr)
        return 2
    except Exception as error:
        print(f"{TOOL}: failed: {type(error).__name__}: {error}", file=sys.stderr)
        return 1
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)
    return 0


def _identity(path):
    """What is at ``path`` (device and inode), None if nothing: an output renamed into place has
    a new one."""
    try:
        status = os.lstat(path)
    except FileNotFoundError:
        return None
    return status.st_dev, status.st_ino


def _end_by_signal(signum, written):
    """Says what the signal left (every output, or none of them), then ends the process as the
    signal asks (as the command-line tool does), so that a shell sees which signal ended it."""
    names = list(map(repr, written))
    if len(names) > 1:
        left = f"{', '.join(names[:-1])} and {names[-1]} all written before it"
    else:
        left = f"{names[0]} written before it" if names else "nothing was written"
    print(f"{TOOL}: stopped by {signal.Signals(signum).name}; {left}", file=sys.stderr, flush=True)
    sys.stdout.flush()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)
    # Reached only where the signal does not end the process (it is blocked): end as it would.
    sys.exit(128 + signum)


if __name__ == "__main__":
    sys.exit(main())
