"""remove_small_label_components on NumPy arrays: the module's label-map filter on the array's own
buffer."""

import numpy as np

from . import _arguments, _core
from ._numpy import _place, _prepare, _result


def remove_small_label_components(labels, max_size=20, fully_connected=False, *, select="all", background=0,
                                  max_sizes=None, keep_largest=0, max_volume=None, spacing=None, return_mask=False,
                                  return_stats=False, out=None, in_place=False, threads=None):
    """Removes the connected components of at most ``max_size`` voxels of each selected label from a
    2-D, 3-D or 4-D label map, giving each removed voxel the label voted by its component's
    surroundings (a speck of one organ inside another becomes that organ, not background).

    A component is a connected set of voxels of one label; the background is a label like the
    others, so its small components (holes) are filled. From each voxel of a removed component, a
    walk along each axis direction stops at the first voxel outside the component, which votes for
    its label; the votes of voxels in kept components count (all votes when there are none); the
    most votes win, then the nearest voter, then the smallest label. A voxel whose walks all leave
    the map keeps its label (unrepairable). Every decision is made on the input; every other voxel
    keeps its label. This is ``itk::SmallIsoComponentLabelImageFilter`` (docs/labels.md).

    Parameters
    ----------
    labels : array_like, 2-D, 3-D or 4-D
        dtype uint8, int8, uint16, int16, uint32, int32, uint64, int64, float32 or float64
        (``smalliso.label_types``); a floating-point map must hold whole numbers only (a fraction,
        infinity or NaN is a ValueError naming its index). Memory order, copies and masked arrays
        as in ``remove_small_components``.
    max_size : int
        K: components of at most K voxels are removed; 0 removes none by size.
    fully_connected : bool
        Connect voxels that share an edge or a corner too, not only a face.
    select : "all", "islands", "holes" or a sequence of labels
        The labels whose components may be removed: every label ("all", the default: islands
        removed and holes filled), every label but ``background`` ("islands"), ``background`` only
        ("holes"), or the labels listed.
    background : int
        The background's label, for "islands" and "holes". Default 0.
    max_sizes : dict, optional
        label -> K (voxels) for the labels that have their own K; the others use ``max_size``.
    keep_largest : int
        N > 0: every component of a selected label smaller than its N-th largest is removed too
        (those tied with it are kept). Default 0: off.
    max_volume : float, optional
        The default K as a physical volume (the spacing's units cubed) instead of ``max_size``:
        K = floor(max_volume / voxel volume).
    spacing : sequence of float, optional
        The voxel spacing in the array's axis order (default 1 per axis); only ``max_volume`` uses it.
    return_mask : bool
        Also return the mask of the removed voxels (uint8, same shape and order: 1 removed, 0 kept).
    return_stats : bool
        Also return the statistics: a dict with ``labels`` (label (int) -> ``components``,
        ``removed_components``, ``removed_voxels``, ``gained_voxels``, ``size_histogram`` as a dict
        size -> number of components), ``modified_voxels``, ``unrepairable_voxels`` and
        ``effective_max_size`` (the default K).
    out, in_place, threads
        As in ``remove_small_components``; the result does not depend on ``threads``, and the GIL is
        released while the filter runs.

    Returns
    -------
    ndarray, or a tuple
        The filtered label map, or ``(filtered, mask, stats)`` holding only the parts asked for.
    """
    max_size, max_volume, work_units, fully_connected, return_mask, return_stats = _arguments.check_options(
        max_size, max_volume, threads, fully_connected, return_mask, return_stats)
    keep_largest = _arguments.check_keep_largest(keep_largest)
    in_place = _arguments.check_flag(in_place, "in_place")
    labels, target = _prepare(labels, out, in_place, "a label for the masked voxels")
    dtype = _arguments.check_label_dtype(labels.dtype)
    _arguments.check_shape(labels.shape, (2, 3, 4))
    spacing = _arguments.check_spacing(spacing, labels.ndim)
    selection, selected = _arguments.check_select(select, dtype)
    background = _arguments.check_label(background, dtype, "background")
    size_labels, sizes = _arguments.check_max_sizes(max_sizes, dtype)
    labels, target = _place(labels, target, out)
    output, mask, stats = _core.filter_labels(
        target if target is not None else labels, max_size, max_volume, spacing, np.array(size_labels, dtype), sizes,
        selection, np.array(selected, dtype), np.array([background], dtype), keep_largest, fully_connected,
        target is not None, return_mask, work_units)
    return _result(target if target is not None else output, mask if return_mask else None,
                   stats if return_stats else None)
