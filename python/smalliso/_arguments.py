"""Checks of the arguments shared by the NumPy and the Dask functions: each bad argument gives a
TypeError or ValueError that says what was wrong and what was expected."""

import math
import operator
import sys

import numpy as np

from . import _core

SIDES = ("above", "below", "both")
# The largest K the C++ core takes (an unsigned 64-bit count of voxels).
_MAX_SIZE_LIMIT = 2**64 - 1


def check_dtype(dtype):
    """The array's dtype, if the core supports it."""
    dtype = np.dtype(dtype)
    if dtype.name not in _core.pixel_types:
        reason = ""
        if dtype.kind in "iu" and dtype.itemsize == 8:
            reason = " (a repaired voxel gets a mean taken in double precision, which cannot hold every 64-bit integer)"
        raise TypeError(
            f"dtype {dtype} is not supported{reason}; expected one of "
            f"{', '.join(_core.pixel_types)} (convert with array.astype(...))")
    if not dtype.isnative:
        raise TypeError(
            f"the array's dtype {dtype.str} is not in the machine's byte order; convert it with "
            "array.astype(array.dtype.newbyteorder('='))")
    return dtype


def check_shape(shape, dimensions=(2, 3)):
    """The shape of an array of one of the ``dimensions`` with at least one voxel."""
    shape = tuple(int(extent) for extent in shape)
    if len(shape) not in dimensions:
        names = [f"{d}-D" for d in dimensions]
        raise ValueError(f"the array is {len(shape)}-D (shape {shape}); expected a "
                         f"{', '.join(names[:-1])} or {names[-1]} array")
    if 0 in shape:
        raise ValueError(f"the array is empty (shape {shape}); it must have at least one voxel")
    return shape


def check_isovalue(isovalue):
    try:
        value = operator.index(isovalue) if isinstance(isovalue, (int, np.integer)) else float(isovalue)
    except (TypeError, ValueError):
        raise TypeError(f"isovalue must be a real number, not {isovalue!r}") from None
    value = float(value)
    if math.isnan(value):
        raise ValueError("isovalue is NaN; it must be a number (every voxel is compared with it)")
    return value


def _whole_number(value, expected):
    """``value`` as an int, or a TypeError saying what was ``expected``."""
    if not isinstance(value, (bool, np.bool_)):
        try:
            return operator.index(value)
        except TypeError:
            pass
    raise TypeError(f"{expected}, not {value!r}")


def check_max_size(max_size):
    size = _whole_number(max_size, "max_size must be a whole number of voxels")
    if size < 0:
        raise ValueError(f"max_size is {size}; it must be >= 0 (components of at most max_size voxels are removed)")
    if size > _MAX_SIZE_LIMIT:
        raise ValueError(f"max_size is {size}; it must be at most 2**64 - 1")
    return size


def check_side(side):
    if not isinstance(side, str):
        raise TypeError(f"side must be one of the strings 'above', 'below' or 'both', not {side!r}")
    if side not in SIDES:
        raise ValueError(f"side is {side!r}; expected 'above', 'below' or 'both'")
    return side


def check_flag(value, name):
    """``value`` as a bool, if it is one (or the integer 1 or 0): a string such as "no" or "false" would
    otherwise be true."""
    if isinstance(value, (bool, np.bool_)) or (isinstance(value, (int, np.integer)) and value in (0, 1)):
        return bool(value)
    raise TypeError(f"{name} must be True or False, not {value!r}")


def check_max_volume(max_volume):
    if max_volume is None:
        return None
    try:
        volume = float(max_volume)
    except (TypeError, ValueError):
        raise TypeError(f"max_volume must be a number (a physical volume) or None, not {max_volume!r}") from None
    if not volume >= 0.0:
        raise ValueError(f"max_volume is {volume}; it must be a volume >= 0 in the spacing's units cubed")
    return volume


def check_spacing(spacing, ndim):
    """The spacing as a list of floats in NumPy's axis order (empty when not given)."""
    if spacing is None:
        return []
    try:
        values = [float(value) for value in spacing]
    except (TypeError, ValueError):
        raise ValueError(f"spacing must be a sequence of {ndim} positive numbers, not {spacing!r}") from None
    if len(values) != ndim or not all(math.isfinite(value) and value > 0.0 for value in values):
        raise ValueError(
            f"spacing is {spacing!r}; expected {ndim} positive finite numbers, one per axis in the array's axis order")
    # The image's index-to-physical matrix (the spacing's diagonal) must be invertible in double precision.
    if not sys.float_info.min <= math.prod(values) < math.inf:
        raise ValueError(f"spacing is {spacing!r}, whose voxel volume {math.prod(values)!r} is not a normal "
                         "double-precision number; expected spacings whose product lies between 2.2e-308 and 1.8e308")
    return values


def check_threads(threads):
    """The number of work units for the core (0 for ITK's default)."""
    if threads is None:
        return 0
    count = _whole_number(threads, "threads must be a whole number >= 1 or None")
    if not 1 <= count <= _core.max_threads:
        raise ValueError(
            f"threads is {count}; it must be between 1 and {_core.max_threads} (or None for ITK's default)")
    return count


def check_options(max_size, max_volume, threads, fully_connected, return_mask, return_stats):
    """(max_size, max_volume, work units, fully_connected, return_mask, return_stats): the options
    that the NumPy and Dask functions share, checked in that order."""
    return (check_max_size(max_size), check_max_volume(max_volume), check_threads(threads),
            check_flag(fully_connected, "fully_connected"), check_flag(return_mask, "return_mask"),
            check_flag(return_stats, "return_stats"))


SELECTIONS = ("all", "islands", "holes")


def check_label_dtype(dtype):
    """The label map's dtype, if the label filter supports it."""
    dtype = np.dtype(dtype)
    if dtype.name not in _core.label_types:
        raise TypeError(f"dtype {dtype} is not supported for label maps; expected one of "
                        f"{', '.join(_core.label_types)} (convert with labels.astype(...))")
    if not dtype.isnative:
        raise TypeError(f"the label map's dtype {dtype.str} is not in the machine's byte order; convert it with "
                        "labels.astype(labels.dtype.newbyteorder('='))")
    return dtype


def check_label(value, dtype, name):
    """``value`` as a label of a map of ``dtype``: a whole number that the dtype holds exactly."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a label (a whole number), not {value!r}")
    if isinstance(value, (float, np.floating)):
        if not (math.isfinite(value) and value == int(value)):
            raise ValueError(f"{name} is {value!r}; a label is a whole number")
    value = int(value)
    if dtype.kind == "f":
        try:
            with np.errstate(over="ignore"):
                holds = int(dtype.type(value)) == value
        except OverflowError:
            holds = False
    else:
        holds = np.iinfo(dtype).min <= value <= np.iinfo(dtype).max
    if not holds:
        raise ValueError(f"{name} is {value}, which a label map of dtype {dtype} cannot hold")
    return value


def check_select(select, dtype):
    """(selection, labels): "all", "islands" or "holes" with no labels, or "listed" with the
    labels of a non-empty sequence."""
    if isinstance(select, str):
        if select not in SELECTIONS:
            raise ValueError(f"select is {select!r}; expected 'all', 'islands', 'holes' or a list of labels")
        return select, []
    try:
        labels = list(select)
    except TypeError:
        raise TypeError(f"select must be 'all', 'islands', 'holes' or a list of labels, not {select!r}") from None
    if not labels:
        raise ValueError("select is an empty list of labels; give at least one label, or 'all'")
    return "listed", [check_label(label, dtype, "a label of select") for label in labels]


def check_max_sizes(max_sizes, dtype):
    """(labels, sizes) of a dict label -> K (None: no label has its own K)."""
    if max_sizes is None:
        return [], []
    if not hasattr(max_sizes, "items"):
        raise TypeError(f"max_sizes must be a dict label -> K (voxels), not {max_sizes!r}")
    labels, sizes = [], []
    for label, size in max_sizes.items():
        labels.append(check_label(label, dtype, "a label of max_sizes"))
        try:
            sizes.append(check_max_size(size))
        except (TypeError, ValueError) as error:
            raise type(error)(f"max_sizes[{label!r}]: {error}") from None
    return labels, sizes


def check_keep_largest(keep_largest):
    count = _whole_number(keep_largest, "keep_largest must be a whole number of components")
    if not 0 <= count <= _MAX_SIZE_LIMIT:
        raise ValueError(f"keep_largest is {count}; it must be >= 0 (0 keeps every component that is large enough)")
    return count
