"""remove_small_components on Dask arrays: the chunked mode as a task graph (docs/algorithm.md,
"Chunks and Dask").

Voxels: each chunk is filtered, as if it were the whole image, in a box holding the chunk and a
halo of BoxHalo(K, side) voxels around it (K for one side, 2K for both; trimmed at the image's
border), which gives exactly the whole image's result in the chunk. For a Dask array, the box is
put together from the pieces of the input chunks it overlaps, each cut out by a task of its own,
so that only those pieces move between workers; an array stored in chunks (a zarr.Array) is read
box by box instead, so that no task keeps input for another.

Statistics: each chunk alone is summarized (its components that reach its faces, serialized), the
summaries are merged pairwise along the chunk grid (along x, the last NumPy axis, then y, then z),
and the root's tally plus the voxels each chunk's filter gave the fallback value are the image's
statistics. No task holds more than two summaries.
"""

import bisect
import itertools
import multiprocessing
import operator
import sys

import dask.array as da
import numpy as np
from dask.array.core import normalize_chunks
from dask.base import tokenize
from dask.delayed import Delayed
from dask.highlevelgraph import HighLevelGraph

from .. import _arguments, _core
from .._numpy import remove_small_components as _remove_in_memory


class _Parameters:
    """What every task of one filtering is asked (opaque to Dask's graph traversal)."""

    def __init__(self, isovalue, max_size, side, fully_connected, threads):
        self.core = (isovalue, max_size, side, fully_connected, threads)


class _BoxPlan:
    """How one chunk's box is put together: the box's shape, where each piece goes in it (for a
    box made of pieces), and the chunk's place in the box."""

    def __init__(self, dtype, box_shape, positions, crop_begin, crop_end, parameters):
        self.dtype = dtype
        self.box_shape = box_shape
        self.positions = positions
        self.crop_begin = crop_begin
        self.crop_end = crop_end
        self.parameters = parameters


class _Statistics(Delayed):
    """The statistics' Delayed, whose graph Dask optimizes as it optimizes arrays': computed together
    with the filtered array or the mask, it is optimized with them and shares their chunks' filter
    tasks (optimized on its own or as a Delayed, a filter task with one dependent there would be
    fused into it under another name and run twice)."""

    __slots__ = ()
    __dask_optimize__ = da.Array.__dict__["__dask_optimize__"]


class _ChunkPlan:
    """A chunk's place in the image, for its summary."""

    def __init__(self, image_shape, begin, parameters):
        self.image_shape = image_shape
        self.begin = begin
        self.parameters = parameters


def _readable(array):
    """``array`` C-contiguous with its samples aligned for its dtype, copied if it is not (a chunk
    that arrived from another worker can lie at any address in the message's buffer)."""
    return np.require(array, requirements=("C", "A"))


_memory_kept = False


def _keep_freed_memory_in_task_process():
    """In a process that only runs tasks (a dask.distributed worker, a process pool's worker),
    each task reuses the memory the task before it freed instead of faulting fresh pages in: the
    process stays at its peak between tasks. The user's own process is left as it is."""
    global _memory_kept
    if not _memory_kept:
        _memory_kept = True
        if multiprocessing.parent_process() is not None or _in_distributed_worker():
            _core.keep_freed_memory()


def _in_distributed_worker():
    distributed = sys.modules.get("distributed")
    if distributed is None:
        return False
    try:
        distributed.get_worker()
    except ValueError:
        return False
    return True


def _filter_box(plan, box):
    _keep_freed_memory_in_task_process()
    return _core.filter_chunk(_readable(box), plan.crop_begin, plan.crop_end, *plan.parameters.core)


def _summarize_chunk(plan, chunk):
    _keep_freed_memory_in_task_process()
    return _core.summarize_chunk(_readable(chunk), plan.image_shape, plan.begin, *plan.parameters.core)


def _assemble_box(plan, pieces):
    if len(pieces) == 1:
        return pieces[0]
    box = np.empty(plan.box_shape, dtype=plan.dtype)
    for position, piece in zip(plan.positions, pieces):
        box[tuple(slice(p, p + n) for p, n in zip(position, piece.shape))] = piece
    return box


def _cut_piece(chunk, slices):
    # A copy, so that the chunk can be let go before every box that needs a piece of it is made.
    return chunk[slices].copy()


def _read(source, slices):
    return source[slices]


def _merge(lower, upper):
    return _core.merge_summaries(lower, upper)


def _finish_statistics(root, fallbacks, max_size):
    stats = _core.summary_statistics(root)
    stats["unrepairable_voxels"] += sum(fallbacks)
    stats["effective_max_size"] = max_size
    return stats


def effective_max_size(max_size, max_volume, spacing, ndim):
    """K: ``max_size``, or what the in-memory filter makes of ``max_volume`` and ``spacing`` (its
    own rule, asked on a one-voxel image)."""
    if max_volume is None:
        return max_size
    # An empty spacing is none given: one unit per axis.
    _, stats = _remove_in_memory(np.zeros((1,) * ndim, np.uint8), 0.0, max_volume=max_volume,
                                 spacing=spacing or None, return_stats=True)
    return stats["effective_max_size"]


def remove_small_components(array, isovalue, max_size=20, side="both", fully_connected=False, *,
                            max_volume=None, spacing=None, return_mask=False, return_stats=False, threads=1,
                            chunks=None):
    """Removes the connected components of at most ``max_size`` voxels on either side of
    ``isovalue`` from a 2-D or 3-D Dask array: lazily, chunk by chunk, with exactly the result of
    ``smalliso.remove_small_components`` on the whole (C-ordered) array, for any chunking.

    The parameters are those of ``smalliso.remove_small_components``. ``array`` is a Dask array
    with known chunk sizes (or anything ``dask.array.asarray`` takes), or an array stored in chunks
    that NumPy-style slicing reads, such as a ``zarr.Array``. ``threads`` is the number of threads
    of each task's C++ code (default 1: Dask runs the tasks in parallel). ``chunks``, in any form
    ``dask.array`` takes, sets the chunks of the tasks and of the result (default the input's). A
    Dask array of masked arrays (``dask.array.ma``) is refused, as a masked array is in memory.

    Each output chunk is computed from the input chunk and a halo of K voxels around it (2K for
    side "both"), so a task holds about (chunk + 2 halo)^3 voxels: choose chunks well larger than
    the halo. The boxes of a Dask array's chunks are put together from pieces of its chunks, which
    stay in memory until every box that needs them is made: how many at once depends on the order
    the scheduler picks, up to the whole input. A stored array is read box by box by the tasks
    themselves, so a worker holds only the few chunks of the tasks it runs; each task decompresses
    every stored chunk its box overlaps, so tasks of several stored chunks each (``chunks``) read
    less of them twice. The statistics are a tree of merges of the chunks' summaries, which hold
    only the components that reach the chunks' faces.

    Returns
    -------
    dask.array.Array, or a tuple
        The filtered array (same chunks and dtype). With ``return_mask`` or ``return_stats``, a
        tuple ``(filtered, mask, stats)`` holding only the parts asked for, in that order: the
        mask a uint8 Dask array, the statistics a ``dask.delayed.Delayed`` dict with the names of
        the in-memory function's (``peak_extra_bytes`` aside). Compute them together
        (``dask.compute(filtered, mask, stats)``) so that the chunks are filtered once. Storing
        with ``dask.array.store`` optimizes the stored arrays apart: store and compute under
        ``dask.config.set({"optimization.fuse.active": False})``, as
        ``remove_small_components_zarr`` does, for the same.
    """
    isovalue = _arguments.check_isovalue(isovalue)
    side = _arguments.check_side(side)
    max_size, max_volume, work_units, fully_connected, return_mask, return_stats = _arguments.check_options(
        max_size, max_volume, threads, fully_connected, return_mask, return_stats)
    source = input_of(array, chunks, "a value on the side the masked voxels belong to")
    dtype = _arguments.check_dtype(source.dtype)
    shape = _arguments.check_shape(source.shape)
    ndim = len(shape)
    spacing = _arguments.check_spacing(spacing, ndim)
    k = effective_max_size(max_size, max_volume, spacing, ndim)
    # No component is larger than the image, so a halo of the image's size is as good as any larger one.
    halo = _core.box_halo(min(k, int(np.prod(shape))), side)
    parameters = _Parameters(isovalue, k, side, fully_connected, work_units)

    token = tokenize(source.name, isovalue, k, side, fully_connected, work_units)
    names = {part: f"smalliso-{part}-{token}" for part in
             ("piece", "filter", "output", "mask", "fallbacks", "summary", "merge", "statistics")}
    blocks = list(itertools.product(*(range(len(extents)) for extents in source.chunks)))
    layers = {name: {} for name in (names["filter"], names["output"], names["mask"], names["statistics"])}
    statistics = layers[names["statistics"]]
    for block in blocks:
        begin = [source.starts[a][i] for a, i in enumerate(block)]
        end = [source.starts[a][i + 1] for a, i in enumerate(block)]
        box_begin = [max(0, b - halo) for b in begin]
        box_end = [min(n, e + halo) for n, e in zip(shape, end)]
        plan = _BoxPlan(dtype, tuple(e - b for b, e in zip(box_begin, box_end)), None,
                        [b - h for b, h in zip(begin, box_begin)], [e - h for e, h in zip(end, box_begin)], parameters)
        filter_key = (names["filter"],) + block
        layers[names["filter"]][filter_key] = (
            _filter_box, plan, source.box(plan, box_begin, box_end, names["piece"], layers[names["filter"]]))
        layers[names["output"]][(names["output"],) + block] = (operator.getitem, filter_key, 0)
        layers[names["mask"]][(names["mask"],) + block] = (operator.getitem, filter_key, 1)
        statistics[(names["fallbacks"],) + block] = (operator.getitem, filter_key, 2)
        statistics[(names["summary"],) + block] = (_summarize_chunk, _ChunkPlan(shape, begin, parameters),
                                                   source.chunk(block, begin, end))
    root = _merge_tree({block: (names["summary"],) + block for block in blocks}, names["merge"], statistics)
    statistics[names["statistics"]] = (_finish_statistics, root, [(names["fallbacks"],) + block for block in blocks], k)

    inputs = source.layer_names
    graph = HighLevelGraph({**source.layers, **layers},
                           {**source.dependencies, names["filter"]: inputs, names["output"]: {names["filter"]},
                            names["mask"]: {names["filter"]}, names["statistics"]: inputs | {names["filter"]}})
    result = (da.Array(graph, names["output"], source.chunks, dtype=dtype, meta=np.empty((0,) * ndim, dtype)),)
    if return_mask:
        result += (da.Array(graph, names["mask"], source.chunks, dtype=np.uint8,
                            meta=np.empty((0,) * ndim, np.uint8)),)
    if return_stats:
        result += (_Statistics(names["statistics"], graph, layer=names["statistics"]),)
    return result[0] if len(result) == 1 else result


def input_of(array, chunks, fill_hint):
    """The input, a _StoredInput or a _DaskInput, of tasks of ``chunks``; ``fill_hint`` says what a
    masked array's masked voxels could be filled with."""
    if _is_stored(array):
        return _StoredInput(array, _task_chunks(chunks, array))
    array = da.asarray(array)
    if isinstance(array._meta, np.ma.MaskedArray):
        # Each chunk would reach the filter through numpy.asarray, which drops its mask: the masked
        # voxels' hidden values would be filtered as data.
        raise TypeError("array is a Dask array of masked arrays, whose mask the filter cannot honour; expected "
                        f"a plain array, such as dask.array.ma.filled(array, value) with {fill_hint}")
    if any(np.isnan(extent) for extents in array.chunks for extent in extents):
        raise ValueError("the Dask array has unknown chunk sizes; call array.compute_chunk_sizes() first")
    return _DaskInput(array if chunks is None else array.rechunk(_task_chunks(chunks, array)))


def _task_chunks(chunks, array):
    """``chunks`` (any form ``dask.array`` takes, None for the array's own) normalized for the
    array, or a ValueError if they do not describe chunks of at least one voxel."""
    if chunks is None:
        chunks = array.chunks
    try:
        normalized = normalize_chunks(chunks, array.shape, dtype=array.dtype)
    except (ValueError, TypeError, ZeroDivisionError) as error:
        # Dask's message can run to several lines; its first says what is wrong.
        raise ValueError(f"chunks is {chunks!r}, which does not describe chunks of the array of shape "
                         f"{tuple(array.shape)} ({str(error).splitlines()[0]}); expected positive chunk edges") from None
    if 0 not in array.shape and any(not extent >= 1 for extents in normalized for extent in extents):
        raise ValueError(f"chunks is {chunks!r}; expected chunk edges of at least one voxel, one per axis of the "
                         f"array of shape {tuple(array.shape)}")
    return normalized


def _starts(chunks):
    """Where each chunk starts along each axis, and the axis' end."""
    return [np.cumsum((0,) + extents).tolist() for extents in chunks]


def _is_stored(array):
    """Whether ``array`` is an array stored in chunks that NumPy-style slicing reads (a zarr.Array, a
    chunked h5py.Dataset), rather than something for dask.array.asarray."""
    chunks = getattr(array, "chunks", None)
    return (not isinstance(array, (da.Array, np.ndarray)) and isinstance(chunks, tuple)
            and all(isinstance(extent, int) for extent in chunks) and hasattr(array, "__getitem__"))


class _DaskInput:
    """A Dask array as the input: each box is put together from pieces of the chunks it overlaps."""

    def __init__(self, array):
        self.name = array.name
        self.dtype = array.dtype
        self.shape = array.shape
        self.chunks = array.chunks
        self.starts = _starts(self.chunks)
        self.layers = dict(array.dask.layers)
        self.dependencies = dict(array.dask.dependencies)
        self.layer_names = set(array.__dask_layers__())

    def chunk(self, block, begin, end):
        return (self.name,) + block

    def box(self, plan, box_begin, box_end, piece_name, layer):
        """A task giving the box [box_begin, box_end): the input chunks' pieces, each cut out by a
        task added to ``layer`` (once, whichever boxes need it) unless it is a whole chunk, put
        together; ``plan.positions`` receives their positions in the box."""
        per_axis = []
        for axis_starts, b, e in zip(self.starts, box_begin, box_end):
            first = bisect.bisect_right(axis_starts, b) - 1
            last = bisect.bisect_left(axis_starts, e)
            per_axis.append([(i, max(b, axis_starts[i]) - axis_starts[i],
                              min(e, axis_starts[i + 1]) - axis_starts[i], max(b, axis_starts[i]) - b)
                             for i in range(first, last)])
        keys = []
        plan.positions = []
        for combination in itertools.product(*per_axis):
            block = tuple(i for i, _, _, _ in combination)
            chunk_key = (self.name,) + block
            whole = all(lo == 0 and hi == axis_starts[i + 1] - axis_starts[i]
                        for (i, lo, hi, _), axis_starts in zip(combination, self.starts))
            if whole:
                keys.append(chunk_key)
            else:
                bounds = tuple(value for _, lo, hi, _ in combination for value in (lo, hi))
                key = (piece_name,) + block + bounds
                if key not in layer:
                    layer[key] = (_cut_piece, chunk_key, tuple(slice(lo, hi) for _, lo, hi, _ in combination))
                keys.append(key)
            plan.positions.append(tuple(position for _, _, _, position in combination))
        return (_assemble_box, plan, keys)


class _StoredInput:
    """An array stored in chunks as the input, one graph key holding it: each task reads its box
    (or, for a summary, its chunk) itself, so no input stays in memory beyond the task that reads
    it, whatever order the scheduler runs the tasks in."""

    def __init__(self, array, chunks):
        self.name = "smalliso-source-" + tokenize(array)
        self.dtype = array.dtype
        self.shape = array.shape
        self.chunks = chunks
        self.starts = _starts(self.chunks)
        self.layers = {self.name: {self.name: array}}
        self.dependencies = {self.name: set()}
        self.layer_names = {self.name}

    def chunk(self, block, begin, end):
        return (_read, self.name, tuple(slice(b, e) for b, e in zip(begin, end)))

    def box(self, plan, box_begin, box_end, piece_name, layer):
        return (_read, self.name, tuple(slice(b, e) for b, e in zip(box_begin, box_end)))


def _merge_tree(summaries, merge_name, layer):
    """Adds the pairwise merges of the summaries (a dict block index -> key) along the last axis,
    then the one before it, and so on, to ``layer``; returns the root's key. Along one axis, each
    round merges neighbours two by two, so a line of n chunks takes ceil(log2 n) rounds."""
    ndim = len(next(iter(summaries)))
    counter = itertools.count()
    for axis in reversed(range(ndim)):
        lines = {}
        for block in sorted(summaries):
            lines.setdefault(block[:axis] + block[axis + 1:], []).append(summaries[block])
        summaries = {}
        for rest, keys in lines.items():
            while len(keys) > 1:
                merged = []
                for lower, upper in zip(keys[0::2], keys[1::2]):
                    key = (merge_name, next(counter))
                    layer[key] = (_merge, lower, upper)
                    merged.append(key)
                keys = merged + keys[len(merged) * 2:]
            summaries[rest[:axis] + (0,) + rest[axis:]] = keys[0]
    return summaries[(0,) * ndim]
