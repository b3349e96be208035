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
from ._graph import _keep_freed_memory_in_task_process, input_of


class _LabelPlan:
    """One chunk's box: the box as the chunk's pieces make it, the chunk's place in the box, and
    the in-memory function's arguments (opaque to Dask's graph traversal)."""

    def __init__(self, dtype, box_shape, crop, options):
        self.dtype = dtype
        self.box_shape = box_shape
        self.positions = None
        self.crop = crop
        self.options = options


def _filter_label_box(plan, box):
    _keep_freed_memory_in_task_process()
    result = _remove_in_memory(box, **plan.options)
    output, mask = result if plan.options["return_mask"] else (result, None)
    # Copies, so that the box's buffers can be let go.
    return output[plan.crop].copy(), None if mask is None else mask[plan.crop].copy()


def remove_small_label_components(array, max_size=20, fully_connected=False, *, select="all", background=0,
                                  max_sizes=None, keep_largest=0, max_volume=None, spacing=None, return_mask=False,
                                  threads=1, chunks=None):
    """Removes the small components of the selected labels of a 2-D, 3-D or 4-D Dask array of
    labels, lazily, chunk by chunk, with exactly the result of
    ``smalliso.remove_small_label_components`` on the whole array, for any chunking.

    The parameters are those of ``smalliso.remove_small_label_components``, and ``array``,
    ``threads`` and ``chunks`` as in ``smalliso.dask.remove_small_components``. ``keep_largest``
    is refused (it needs every component's size in the whole image), and there are no statistics.
    Each task holds its chunk with a halo of 2K voxels on each side (K the largest of the K's of
    ``max_size``, ``max_volume`` and ``max_sizes``), and the filtered box: choose chunks well larger
    than 4K. Returns the filtered Dask array, or ``(filtered, mask)`` with ``return_mask``.
    """
    if _arguments.check_keep_largest(keep_largest) != 0:
        raise ValueError(f"keep_largest is {keep_largest}; it is not supported on Dask arrays, whose chunks do not see "
                         "every component's size (filter the array in memory, or give keep_largest=0)")
    max_size = _arguments.check_max_size(max_size)
    max_volume = _arguments.check_max_volume(max_volume)
    return_mask = _arguments.check_flag(return_mask, "return_mask")
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
    options = dict(max_size=k, fully_connected=bool(fully_connected), select=select, background=background,
                   max_sizes=max_sizes, return_mask=return_mask, threads=threads)
    return _graph(source, dtype, shape, largest, options, return_mask)


def _graph(source, dtype, shape, largest, options, return_mask):
    """The filtered array (and the mask) of ``source``, each chunk filtered in its box."""
    token = tokenize(source.name, largest, sorted(options.items(), key=str))
    names = {part: f"smalliso-labels-{part}-{token}" for part in ("piece", "filter", "output", "mask")}
    layers = {names[part]: {} for part in ("filter", "output", "mask")}
    for block in itertools.product(*(range(len(extents)) for extents in source.chunks)):
        begin = [source.starts[a][i] for a, i in enumerate(block)]
        end = [source.starts[a][i + 1] for a, i in enumerate(block)]
        box_begin = [max(0, b - 2 * largest) for b in begin]
        box_end = [min(n, e + 2 * largest) for n, e in zip(shape, end)]
        crop = tuple(slice(b - bb, e - bb) for b, e, bb in zip(begin, end, box_begin))
        plan = _LabelPlan(dtype, tuple(e - b for b, e in zip(box_begin, box_end)), crop, options)
        box = source.box(plan, box_begin, box_end, names["piece"], layers[names["filter"]])
        filter_key = (names["filter"],) + block
        layers[names["filter"]][filter_key] = (_filter_label_box, plan, box)
        layers[names["output"]][(names["output"],) + block] = (operator.getitem, filter_key, 0)
        layers[names["mask"]][(names["mask"],) + block] = (operator.getitem, filter_key, 1)
    inputs = source.layer_names
    graph = HighLevelGraph({**source.layers, **layers},
                           {**source.dependencies, names["filter"]: inputs, names["output"]: {names["filter"]},
                            names["mask"]: {names["filter"]}})
    meta = np.empty((0,) * len(shape), dtype)
    output = da.Array(graph, names["output"], source.chunks, dtype=dtype, meta=meta)
    if not return_mask:
        return output
    return output, da.Array(graph, names["mask"], source.chunks, dtype=np.uint8, meta=meta.astype(np.uint8))
