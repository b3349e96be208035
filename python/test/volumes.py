"""Random test volumes for the smalliso tests, and comparisons that see every bit."""

import numpy as np

DTYPES = ("uint8", "int8", "uint16", "int16", "uint32", "int32", "float32", "float64")


def random_volume(rng, dtype, shape):
    """A volume of one of a few kinds, with values near the isovalue it returns: salt noise of two
    values, blobs (a few balls), a few discrete levels that tie with the isovalue, or uniform noise;
    NaN sprinkled into floating-point volumes. Returns (volume, isovalue)."""
    dtype = np.dtype(dtype)
    kind = rng.integers(4)
    low, high = _range_of(rng, dtype)
    if kind == 0:
        volume = np.where(rng.random(shape) < rng.uniform(0.2, 0.8), high, low)
        isovalue = (low + high) / 2
    elif kind == 1:
        grid = np.indices(shape).astype(float)
        volume = np.full(shape, low, dtype=float)
        for _ in range(rng.integers(1, 5)):
            centre = [rng.uniform(0, n) for n in shape]
            radius = rng.uniform(0.5, max(shape) / 2)
            inside = sum((g - c) ** 2 for g, c in zip(grid, centre)) <= radius**2
            volume[inside] = high
        noise = rng.random(shape) < 0.15
        volume[noise] = np.where(volume[noise] == high, low, high)
        isovalue = (low + high) / 2
    elif kind == 2:
        levels = np.linspace(low, high, 4).round() if dtype.kind in "iu" else np.linspace(low, high, 4)
        volume = rng.choice(levels, size=shape)
        isovalue = levels[rng.integers(1, 4)]
    else:
        volume = rng.uniform(low, high, size=shape)
        isovalue = rng.uniform(low, high)
    volume = volume.astype(dtype)
    if dtype.kind == "f" and rng.random() < 0.5:
        volume[rng.random(shape) < 0.1] = np.nan
    return volume, float(isovalue)


def _range_of(rng, dtype):
    """Values to build volumes from: an integer type's extremes now and then, moderate values
    otherwise."""
    if dtype.kind == "f":
        return -50.0, 150.0
    info = np.iinfo(dtype)
    if rng.random() < 0.1:
        return int(info.min), int(info.max)
    return max(int(info.min), -100), min(int(info.max), 200)


def same_bits(a, b):
    """Whether two arrays have the same shape, dtype and bits (NaN payloads included)."""
    a = np.ascontiguousarray(a)
    b = np.ascontiguousarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def without_memory(stats):
    """The statistics without peak_extra_bytes, which only the in-memory filter reports."""
    return {key: value for key, value in stats.items() if key != "peak_extra_bytes"}


def unaligned_copy(array):
    """A copy of ``array`` whose samples lie one byte off the alignment its dtype asks for, as in
    a view of raw bytes or a buffer unpickled from another process."""
    raw = np.zeros(array.nbytes + 1, np.uint8)
    copy = raw[1:].view(array.dtype).reshape(array.shape)
    copy[...] = array
    assert not copy.flags.aligned
    return copy
