"""remove_small_label_components on Dask arrays: each chunk filtered with a halo, exact for any
chunking.

With K the largest K of any label, a chunk's voxels depend on the components that reach into the
chunk and are removed (within K - 1 of it), on their voters (within K), and on whether each
voter's component is removed, which needs its whole size when it has at most K voxels (up to
2K - 1 from the chunk). The box is the chunk and a halo of 2K voxels, and the box alone decides
those components as the image does: a component of at most K voxels near the chunk lies wholly in
the box, away from its faces; one cut by a face of the box inside the image reaches from within K
of the chunk to the face, 2K away, so the box still sees more than K of its voxels and keeps it.
"""

import itertools
import operator

import dask.array as da
import numpy as np
from dask.base import tokenize
from dask.highlevelgraph import HighLevelGraph

from .. import _arguments
from .._labels import remove_small_label_components as _remove_in_memory
from ._graph import _keep_freed_memory_in_task_process, _Statistics, input_of


class _LabelPlan:
    """One chunk's box: the box as the chunk's pieces make it, the chunk's place in the box, and
    the in-memory function's arguments (opaque to Dask's graph traversal)."""

    def __init__(self, dtype, box_shape, crop, options, count_changes):
        self.dtype = dtype
        self.box_shape = box_shape
        self.positions = None
        self.crop = crop
        self.options = options
        self.count_changes = count_changes


def _filter_label_box(plan, box):
    _keep_freed_memory_in_task_process()
    result = _remove_in_memory(box, **plan.options)
    output, mask = result if plan.options["return_mask"] else (result, None)
    # Copies, so that the box's buffers can be let go.
    output, mask = output[plan.crop].copy(), None if mask is None else mask[plan.crop].copy()
    return output, mask, _count_changes(box[plan.crop], output, mask) if plan.count_changes else None


def _count_changes(before, after, mask):
    """What the chunk's voxels add to the statistics: counts that add up over the chunks. A
    repaired voxel always changes its label (its voters are outside its component)."""
    changed = after != before
    modified = int(np.count_nonzero(changed))
    return {"modified_voxels": modified, "unrepairable_voxels": int(np.count_nonzero(mask)) - modified,
            "removed_voxels": _label_counts(before[mask != 0]), "gained_voxels": _label_counts(after[changed])}


def _label_counts(labels):
    values, counts = np.unique(labels, return_counts=True)
    return dict(zip((int(v) for v in values), (int(c) for c in counts)))


def _add_up_changes(chunks, max_size):
    """The statistics of the whole map from its chunks' counts."""
    stats = {"labels": {}, "modified_voxels": 0, "unrepairable_voxels": 0, "effective_max_size": max_size}
    for counts in chunks:
        stats["modified_voxels"] += counts["modified_voxels"]
        stats["unrepairable_voxels"] += counts["unrepairable_voxels"]
        for field in ("removed_voxels", "gained_voxels"):
            for label, voxels in counts[field].items():
                entry = stats["labels"].setdefault(label, {"removed_voxels": 0, "gained_voxels": 0})
                entry[field] += voxels
    stats["labels"] = dict(sorted(stats["labels"].items()))
    return stats


def remove_small_label_components(array, max_size=20, fully_connected=False, *, select="all", background=0,
                                  max_sizes=None, keep_largest=0, max_volume=None, spacing=None, return_mask=False,
                                  return_stats=False, threads=1, chunks=None):
    """Removes the small components of the selected labels of a 2-D, 3-D or 4-D Dask array of
    labels, lazily, chunk by chunk, with exactly the result of
    ``smalliso.remove_small_label_components`` on the whole array, for any chunking.

    The parameters are those of ``smalliso.remove_small_label_components``, and ``array``,
    ``threads`` and ``chunks`` as in ``smalliso.dask.remove_small_components``. ``keep_largest``
    is refused (it needs every component's size in the whole image). Each task holds its chunk with
    a halo of 2K voxels on each side (K the largest of the K's of ``max_size``, ``max_volume`` and
    ``max_sizes``), and the filtered box: choose chunks well larger than 4K.

    The statistics (``return_stats``) are the voxel counts of the in-memory function's, which add
    up over the chunks: ``modified_voxels``, ``unrepairable_voxels``, ``effective_max_size``, and
    ``labels`` (label -> ``removed_voxels``, ``gained_voxels``) for the labels that lost or gained
    voxels. The component counts and size histograms are not given: a chunk does not see every
    component whole.

    Returns the filtered Dask array, or a tuple ``(filtered, mask, stats)`` holding only the parts
    asked for, in that order; ``stats`` is a Dask Delayed (compute it with the arrays, as
    ``dask.compute(filtered, stats)``, so that the chunks are filtered once).
    """
    if _arguments.check_keep_largest(keep_largest) != 0:
        raise ValueError(f"keep_largest is {keep_largest}; it is not supported on Dask arrays, whose chunks do not see "
                         "every component's size (filter the array in memory, or give keep_largest=0)")
    max_size = _arguments.check_max_size(max_size)
    max_volume = _arguments.check_max_volume(max_volume)
    return_mask = _arguments.check_flag(return_mask, "return_mask")
    return_stats = _arguments.check_flag(return_stats, "return_stats")
    source = input_of(array, chunks, "a label for the masked voxels")
    dtype = _arguments.check_label_dtype(source.dtype)
    shape = _arguments.check_shape(source.shape, (2, 3, 4))
    spacing = _arguments.check_spacing(spacing, len(shape))
    # Checks the remaining arguments, and gives K, on a one-voxel map.
    _, stats = _remove_in_memory(np.zeros((1,) * len(shape), dtype), max_size, fully_connected, select=select,
                                 background=background, max_sizes=max_sizes, max_volume=max_volume,
                                 spacing=spacing or None, return_stats=True, threads=threads)
    k = stats["effective_max_size"]
    largest = min(max([k] + list((max_sizes or {}).values())), int(np.prod(shape)))
    # The statistics count the removed voxels from the mask.
    options = dict(max_size=k, fully_connected=bool(fully_connected), select=select, background=background,
                   max_sizes=max_sizes, return_mask=return_mask or return_stats, threads=threads)
    output, mask, statistics = _graph(source, dtype, shape, largest, options, return_stats)
    result = (output,) + ((mask,) if return_mask else ()) + ((statistics,) if return_stats else ())
    return result[0] if len(result) == 1 else result


def _graph(source, dtype, shape, largest, options, count_changes):
    """The filtered array, the mask and (with ``count_changes``) the statistics of ``source``, each
    chunk filtered in its box."""
    token = tokenize(source.name, largest, sorted(options.items(), key=str), count_changes)
    names = {part: f"smalliso-labels-{part}-{token}" for part in ("piece", "filter", "output", "mask", "statistics")}
    layers = {names[part]: {} for part in ("filter", "output", "mask", "statistics")}
    counts = []
    for block in itertools.product(*(range(len(extents)) for extents in source.chunks)):
        begin = [source.starts[a][i] for a, i in enumerate(block)]
        end = [source.starts[a][i + 1] for a, i in enumerate(block)]
        box_begin = [max(0, b - 2 * largest) for b in begin]
        box_end = [min(n, e + 2 * largest) for n, e in zip(shape, end)]
        crop = tuple(slice(b - bb, e - bb) for b, e, bb in zip(begin, end, box_begin))
        plan = _LabelPlan(dtype, tuple(e - b for b, e in zip(box_begin, box_end)), crop, options, count_changes)
        box = source.box(plan, box_begin, box_end, names["piece"], layers[names["filter"]])
        filter_key = (names["filter"],) + block
        layers[names["filter"]][filter_key] = (_filter_label_box, plan, box)
        layers[names["output"]][(names["output"],) + block] = (operator.getitem, filter_key, 0)
        layers[names["mask"]][(names["mask"],) + block] = (operator.getitem, filter_key, 1)
        counts_key = (names["statistics"], "chunk") + block
        layers[names["statistics"]][counts_key] = (operator.getitem, filter_key, 2)
        counts.append(counts_key)
    layers[names["statistics"]][names["statistics"]] = (_add_up_changes, counts, options["max_size"])
    inputs = source.layer_names
    graph = HighLevelGraph({**source.layers, **layers},
                           {**source.dependencies, names["filter"]: inputs, names["output"]: {names["filter"]},
                            names["mask"]: {names["filter"]}, names["statistics"]: {names["filter"]}})
    meta = np.empty((0,) * len(shape), dtype)
    return (da.Array(graph, names["output"], source.chunks, dtype=dtype, meta=meta),
            da.Array(graph, names["mask"], source.chunks, dtype=np.uint8, meta=meta.astype(np.uint8)),
            _Statistics(names["statistics"], graph, layer=names["statistics"]))
