"""Zarr in, Zarr out: a Zarr array filtered chunk by chunk into a new one, which appears only when
it is complete."""

import os
import shutil
import sys
import tempfile

import dask
import dask.array as da
import zarr

from ._graph import remove_small_components


def remove_small_components_zarr(source, target, isovalue, max_size=20, side="both", fully_connected=False, *,
                                 max_volume=None, spacing=None, removed_mask=None, client=None, progress=False,
                                 threads=1, chunks=None):
    """Filters the Zarr array at ``source`` (a directory store) into a new Zarr array at ``target``
    with the same shape, chunks, dtype, compressor and attributes, and returns the statistics (the
    dict of ``smalliso.dask.remove_small_components``).

    The parameters are those of ``smalliso.dask.remove_small_components``; ``chunks`` (the tasks')
    must be whole multiples of the stored chunks, so that no two tasks write one stored chunk.
    ``removed_mask``, if given, is the path of a second Zarr array to write the mask of the changed
    voxels to.
    ``client``, a ``distributed.Client``, runs the work on its cluster; otherwise Dask's current
    scheduler does (the threaded one unless configured otherwise). ``progress`` shows a progress
    bar (``dask.diagnostics.ProgressBar`` on stderr, or ``distributed.progress`` with a client).

    Each task reads its chunk and halo from ``source`` itself, so a worker holds only the few
    chunks of the tasks it runs. Every output is written chunk by chunk by the tasks into a
    temporary directory beside it and renamed into place only when all of them are complete
    (replacing an existing one), so a failure leaves no half-written array behind.
    """
    source = os.fspath(source)
    outputs = [os.fspath(target)] + ([os.fspath(removed_mask)] if removed_mask is not None else [])
    paths = [os.path.realpath(path) for path in [source] + outputs]
    if len(set(paths)) != len(paths):
        raise ValueError(f"the input and the outputs must be different paths, not {[source] + outputs}")
    try:
        stored = zarr.open_array(source, mode="r")
    except (zarr.errors.ArrayNotFoundError, zarr.errors.ContainsGroupError, FileNotFoundError):
        raise ValueError(f"{source!r} is not a Zarr array (expected the directory of one array)") from None
    for path in outputs:
        parent = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(parent):
            raise ValueError(f"cannot write {path!r}: its directory {parent!r} does not exist")

    parts = remove_small_components(stored, isovalue, max_size, side, fully_connected,
                                    max_volume=max_volume, spacing=spacing, return_mask=removed_mask is not None,
                                    return_stats=True, threads=threads, chunks=chunks)
    for extents, stored_extent in zip(parts[0].chunks, stored.chunks):
        if any(extent % stored_extent for extent in extents[:-1]):
            raise ValueError(f"the tasks' chunks {parts[0].chunksize} must be whole multiples of the stored chunks "
                             f"{stored.chunks}, so that no two tasks write one stored chunk")
    arrays, stats = parts[:-1], parts[-1]
    staged = []
    try:
        targets = []
        for index, (path, array) in enumerate(zip(outputs, arrays)):
            staged.append(tempfile.mkdtemp(prefix=f".{os.path.basename(path)}.", suffix=".partial",
                                           dir=os.path.dirname(os.path.abspath(path))))
            # The filtered image is stored as the input is; the mask with Zarr's defaults.
            options = {"compressor": stored.compressor, "filters": stored.filters} if index == 0 else {}
            written = zarr.open_array(staged[-1], mode="w", shape=array.shape, chunks=stored.chunks,
                                      dtype=array.dtype, **options)
            if index == 0:
                written.attrs.update(stored.attrs.asdict())
            targets.append(written)
        # Unfused, the stores' graph and the statistics' share the chunks' filter tasks.
        with dask.config.set({"optimization.fuse.active": False}):
            stores = da.store(list(arrays), targets, lock=False, compute=False)
            statistics = _compute(stores, stats, client, progress)
        for staging, path in zip(staged, outputs):
            _replace(staging, path)
    except BaseException:
        for staging in staged:
            shutil.rmtree(staging, ignore_errors=True)
        raise
    return statistics


def _compute(stores, stats, client, progress):
    """Writes the chunks and returns the statistics, in one computation (the chunks are filtered
    once)."""
    if client is not None:
        futures = client.compute([stores, stats])
        if progress:
            from distributed import progress as show_progress
            show_progress(futures)
        return client.gather(futures)[1]
    if progress:
        from dask.diagnostics import ProgressBar
        with ProgressBar(out=sys.stderr):
            return dask.compute(stores, stats)[1]
    return dask.compute(stores, stats)[1]


def _replace(staging, path):
    """Renames the complete ``staging`` directory to ``path``, moving an old ``path`` aside first."""
    if not os.path.lexists(path):
        os.rename(staging, path)
        return
    old = tempfile.mkdtemp(prefix=f".{os.path.basename(path)}.", suffix=".old", dir=os.path.dirname(staging))
    os.rmdir(old)
    os.rename(path, old)
    os.rename(staging, path)
    if os.path.isdir(old) and not os.path.islink(old):
        shutil.rmtree(old)
    else:
        os.remove(old)
