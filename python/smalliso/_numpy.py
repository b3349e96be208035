"""remove_small_components on NumPy arrays: the module's in-memory filter on the array's own
buffer."""

import numpy as np

from . import _arguments, _core


def remove_small_components(array, isovalue, max_size=20, side="both", fully_connected=False, *,
                            max_volume=None, spacing=None, return_mask=False, return_stats=False,
                            out=None, in_place=False, threads=None):
    """Removes the connected components of at most ``max_size`` voxels on either side of
    ``isovalue`` from a 2-D or 3-D array, changing only their voxels.

    Every voxel is *above* (``value >= isovalue``) or *below* (all others, NaN included), as
    Marching Cubes decides. Components of at most ``max_size`` voxels (K) are removed: each of
    their voxels gets a value on the other side, the mean of the first other-side values met
    walking from it along each axis (rounded half up for integers). Every other voxel keeps its
    value bit for bit, so the isosurface of the result at ``isovalue`` is the input's without its
    small pieces. This is ``itk::SmallIsoComponentImageFilter`` (see the project's README).

    Parameters
    ----------
    array : array_like, 2-D or 3-D
        dtype uint8, int8, uint16, int16, uint32, int32, float32 or float64 (``smalliso.pixel_types``).
        A C-ordered array's last axis is ITK's x (shape (z, y, x) is an ITK image of size (x, y, z));
        a Fortran-ordered array is used as it is, its first axis being x. Neither is copied. An array
        that is neither C- nor Fortran-contiguous (a strided view), or whose samples are not
        aligned for its dtype (a view of raw bytes at an odd offset), is copied into a C-ordered
        array first, or refused with ``in_place=True``. A masked array is refused.
    isovalue : float
        Voxels ``>= isovalue`` are above it; NaN is an error.
    max_size : int
        K: components of at most K voxels are removed; 0 removes nothing.
    side : {"above", "below", "both"}
        "above" removes specks (small above components), "below" bubbles, "both" does "above" and
        then "below" on its result.
    fully_connected : bool
        Connect voxels that share an edge or a corner too (8 / 26 neighbours), not only a face.
    max_volume : float, optional
        The threshold as a physical volume (the spacing's units cubed), used instead of
        ``max_size``: K = floor(max_volume / voxel volume).
    spacing : sequence of float, optional
        The voxel spacing in the array's axis order (default 1 per axis); only ``max_volume`` uses it.
    return_mask : bool
        Also return the mask of the changed voxels (uint8, same shape and order: 0 kept, 1 removed
        with an above component, 2 with a below component). Without it no mask is made, which
        saves one byte per voxel.
    return_stats : bool
        Also return the statistics: a dict with the names of ``SmallIsoComponentFilter --stats``:
        ``above`` and ``below`` (each ``components``, ``removed_components``, ``removed_voxels``,
        ``size_histogram`` as a dict size -> number of components), ``modified_voxels``,
        ``unrepairable_voxels``, ``effective_max_size`` (K) and ``peak_extra_bytes``.
    out : ndarray, optional
        Where to put the result: same shape and dtype, C- or Fortran-contiguous, aligned. The input is copied
        into it and filtered there.
    in_place : bool
        Filter ``array`` itself (a writable, aligned, C- or Fortran-contiguous ndarray): no output buffer.
    threads : int, optional
        Threads (ITK work units) for the filter; default ITK's default (the number of cores).
        The result does not depend on it. The GIL is released while the filter runs.

    Returns
    -------
    ndarray, or a tuple
        The filtered array (``out`` or ``array`` itself when given or in place, else a new array
        with the input's memory order). With ``return_mask`` or ``return_stats``, a tuple
        ``(filtered, mask, stats)`` holding only the parts asked for, in that order (as
        ``numpy.unique`` does with its ``return_*`` flags).
    """
    isovalue = _arguments.check_isovalue(isovalue)
    side = _arguments.check_side(side)
    max_size, max_volume, work_units, fully_connected, return_mask, return_stats = _arguments.check_options(
        max_size, max_volume, threads, fully_connected, return_mask, return_stats)
    in_place = _arguments.check_flag(in_place, "in_place")
    array, target = _prepare(array, out, in_place, "a value on the side the masked voxels belong to")
    _arguments.check_dtype(array.dtype)
    _arguments.check_shape(array.shape)
    spacing = _arguments.check_spacing(spacing, array.ndim)
    array, target = _place(array, target, out)
    output, mask, stats = _core.filter(target if target is not None else array, isovalue, max_size, max_volume,
                                       side, fully_connected, spacing, target is not None, return_mask,
                                       work_units)
    return _result(target if target is not None else output, mask if return_mask else None,
                   stats if return_stats else None)


def _prepare(array, out, in_place, fill_hint):
    """(array, target): the input as an ndarray, and itself as the target when it is filtered in
    place (else None); ``fill_hint`` says what a masked array's masked voxels could be filled with."""
    if isinstance(array, np.ma.MaskedArray):
        # numpy.asarray drops the mask: the masked voxels' hidden values would be filtered as data.
        raise TypeError("array is a masked array, whose mask the filter cannot honour; expected a plain array, such "
                        f"as array.filled(value) with {fill_hint}")
    if in_place and out is not None:
        raise ValueError("give out or in_place=True, not both (out=array filters array in place)")
    if in_place or out is array:
        return array, _writable_target(array, "array", "leave in_place off")
    return np.asarray(array), None


def _place(array, target, out):
    """(array, target) once the checked input is copied into ``out``, or copied into an aligned,
    contiguous array when the filter could not read it where it is."""
    if out is not None and target is None:
        target = _writable_target(out, "out", "give no out")
        if out.shape != array.shape or out.dtype != array.dtype:
            raise ValueError(f"out has shape {out.shape} and dtype {out.dtype}; expected the input's shape "
                             f"{array.shape} and dtype {array.dtype}")
        if np.may_share_memory(out, array):
            raise ValueError("out overlaps the input array; give out=array (or in_place=True) to filter the "
                             "array in place, or an out of its own")
        np.copyto(out, array)
    if target is None and not (array.flags.aligned and (array.flags.c_contiguous or array.flags.f_contiguous)):
        # The filter reads whole samples: a strided view, or samples at addresses not aligned for
        # the dtype (a view of raw bytes, a buffer unpickled from another process), get a copy.
        array = np.require(array, requirements=("C", "A"))
    return array, target


def _result(filtered, mask, stats):
    """The filtered array alone, or a tuple with the mask and the statistics asked for (not None)."""
    result = (filtered,) + tuple(part for part in (mask, stats) if part is not None)
    return result[0] if len(result) == 1 else result


def _writable_target(array, name, remedy):
    """``array`` if the filter can write its result into it."""
    if not isinstance(array, np.ndarray):
        raise TypeError(f"{name} must be a NumPy array to be written into, not {type(array).__name__}")
    if not array.flags.writeable:
        raise ValueError(f"{name} is read-only; the result is written into it (give a writable array, or {remedy})")
    if not (array.flags.c_contiguous or array.flags.f_contiguous):
        raise ValueError(f"{name} is neither C- nor Fortran-contiguous (a strided view) and the result is written "
                         f"into it; filter a contiguous copy (numpy.ascontiguousarray) instead, or {remedy}")
    if not array.flags.aligned:
        raise ValueError(f"{name}'s samples are not aligned for its dtype {array.dtype} and the result is written "
                         f"into it; filter an aligned copy (numpy.require(a, requirements='A')) instead, or {remedy}")
    return array
