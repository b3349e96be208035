"""Zarr in, Zarr out: a Zarr array filtered chunk by chunk into a new one, which appears only when
it is complete."""

import contextlib
import itertools
import os
import re
import shutil
import sys
import tempfile
import threading

import dask
import dask.array as da
import numcodecs
import zarr
from dask.base import tokenize

from .. import _arguments
from ._graph import remove_small_components
from ._labels import remove_small_label_components

# The names a Zarr array's directory holds: its metadata, and chunk keys ("0.1.2", or "0/1/2"
# with nested directories).
_ZARR_METADATA = (".zarray", ".zattrs")
_CHUNK_KEY = re.compile(r"\d+(\.\d+)*")


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
    temporary directory beside it, and all are renamed into place together only when all of them
    are complete, so a failure or an interruption leaves either every output or none (the earlier
    ones) behind, never a half-written array. An output path must be new or
    hold a Zarr array (an earlier output, which is replaced); it must neither hold nor lie inside
    the input or the other output. Anything else there is refused with a ValueError before any
    work, so nothing but an earlier Zarr array is ever replaced.
    """
    return _commit(filter_into_staging(
        source, target, isovalue, max_size, side, fully_connected, max_volume=max_volume, spacing=spacing,
        removed_mask=removed_mask, client=client, progress=progress, threads=threads, chunks=chunks))


def remove_small_label_components_zarr(source, target, max_size=20, fully_connected=False, *, select="all",
                                       background=0, max_sizes=None, max_volume=None, spacing=None,
                                       removed_mask=None, client=None, progress=False, threads=1, chunks=None):
    """``remove_small_components_zarr`` for a label map: the Zarr array at ``source`` filtered by
    ``smalliso.dask.remove_small_label_components`` (whose parameters these are) into ``target``,
    and the statistics returned; the mask, if asked for, marks the removed voxels with 1."""
    labels = {"select": select, "background": background, "max_sizes": max_sizes}
    return _commit(filter_into_staging(
        source, target, None, max_size, None, fully_connected, max_volume=max_volume, spacing=spacing,
        removed_mask=removed_mask, client=client, progress=progress, threads=threads, chunks=chunks, labels=labels))


def _commit(filtered):
    statistics, staged = filtered
    try:
        staged.commit()
    finally:
        staged.discard()
    return statistics


def filter_into_staging(source, target, isovalue, max_size=20, side="both", fully_connected=False, *,
                        max_volume=None, spacing=None, removed_mask=None, client=None, progress=False, threads=1,
                        chunks=None, labels=None):
    """``remove_small_components_zarr`` up to the commit: the statistics and the outputs staged
    beside their paths (a ``StagedOutputs``), which the caller commits or discards. Nothing is
    left staged if it fails. With ``labels`` (the label options ``select``, ``background`` and
    ``max_sizes``), the array is a label map and ``isovalue`` and ``side`` are not used."""
    source = os.fspath(source)
    # Normalized, so that the path renamed into place is the one checked ("out.zarr/." is out.zarr,
    # and a link's "link/." the link).
    outputs = [os.path.normpath(os.fspath(path)) for path in (target, removed_mask) if path is not None]
    check_paths(source, outputs)
    stored = open_input(source)

    options = dict(max_volume=max_volume, spacing=spacing, return_mask=removed_mask is not None, return_stats=True,
                   threads=threads, chunks=chunks)
    checked = _CheckedInput(stored, source)
    parts = (remove_small_components(checked, isovalue, max_size, side, fully_connected, **options) if labels is None
             else remove_small_label_components(checked, max_size, fully_connected, **labels, **options))
    for extents, stored_extent in zip(parts[0].chunks, stored.chunks):
        if any(extent % stored_extent for extent in extents[:-1]):
            raise ValueError(f"the tasks' chunks {parts[0].chunksize} must be whole multiples of the stored chunks "
                             f"{stored.chunks}, so that no two tasks write one stored chunk")
    arrays, stats = parts[:-1], parts[-1]
    staged = StagedOutputs(source)
    targets = []
    try:
        for index, (path, array) in enumerate(zip(outputs, arrays)):
            staging = staged.stage_directory(path)
            # The filtered image is stored as the input is; the mask with Zarr's defaults.
            options = {"compressor": stored.compressor, "filters": stored.filters} if index == 0 else {}
            written = zarr.open_array(staging, mode="w", shape=array.shape, chunks=stored.chunks,
                                      dtype=array.dtype, **options)
            if index == 0:
                written.attrs.update(stored.attrs.asdict())
            targets.append(_StagedArray(written))
        # Unfused, the stores' graph and the statistics' share the chunks' filter tasks.
        with dask.config.set({"optimization.fuse.active": False}):
            stores = da.store(list(arrays), targets, lock=False, compute=False)
            statistics = _compute(stores, stats, client, progress)
    except BaseException:
        for written in targets:
            written.close()
        staged.discard()
        raise
    return statistics, staged


def open_input(source):
    """The Zarr array at ``source``, read-only, or a ValueError saying why it cannot be read or
    filtered."""
    not_an_array = ValueError(f"{source!r} is not a Zarr array (expected the directory of one array)")
    if not os.path.isdir(source):
        raise not_an_array
    metadata = os.path.join(source, ".zarray")
    try:
        stored = zarr.open_array(source, mode="r")
    except (zarr.errors.ArrayNotFoundError, zarr.errors.ContainsGroupError, FileNotFoundError, NotADirectoryError):
        raise not_an_array from None
    except Exception as error:
        # Zarr decodes the metadata without checking its types: a wrong one fails anywhere.
        raise ValueError(f"{source!r} is not a readable Zarr array: its metadata {metadata!r} is invalid "
                         f"({error})") from None
    shape, chunks = stored.shape, stored.chunks
    if not (len(chunks) == len(shape) and all(type(n) is int and n >= 0 for n in shape)
            and all(type(n) is int and n >= 1 for n in chunks)):
        raise ValueError(f"{source!r} is not a readable Zarr array: its metadata {metadata!r} gives shape "
                         f"{list(shape)} and chunks {list(chunks)}; expected whole numbers, one shape extent >= 0 "
                         "and one chunk edge >= 1 per axis")
    try:
        attributes = stored.attrs.asdict()
    except Exception as error:
        attributes = error
    if not isinstance(attributes, dict):
        raise ValueError(f"{source!r} is not a readable Zarr array: its attributes "
                         f"{os.path.join(source, '.zattrs')!r} are invalid ({attributes!r}); expected a JSON object")
    _arguments.check_dtype(stored.dtype)
    _arguments.check_shape(shape)
    # Without a fill value, Zarr leaves the voxels of a chunk that is not stored as the memory held.
    if stored.fill_value is None:
        missing = stored.nchunks - stored_chunks(source, stored)
        if missing:
            raise ValueError(f"{missing} of the {stored.nchunks} chunks of the Zarr array {source!r} are not stored "
                             "and it has no fill value to read them as; expected every chunk stored, or a fill value "
                             f"in {metadata!r}")
    return stored


def stored_chunks(source, stored):
    """How many of the chunks of the Zarr array ``stored`` at ``source`` are stored, as files
    (Zarr's own count sees only the top level of nested chunk directories, and counts any name)."""
    grid = [-(-extent // edge) for extent, edge in zip(stored.shape, stored.chunks)]
    count = 0
    for directory, _, files in os.walk(source):
        for name in files:
            key = os.path.relpath(os.path.join(directory, name), source).replace(os.sep, ".")
            indices = key.split(".")
            if len(indices) == len(grid) and all(i.isdigit() and int(i) < n for i, n in zip(indices, grid)):
                count += 1
    return count


def check_paths(source, outputs, files=()):
    """Raises a ValueError unless every output directory (and every file of ``files``) can be
    written without losing anything: each path distinct, none holding or inside another or the
    input, its directory existing, and an existing output directory a Zarr array."""
    named = [("the input", source)] + [("the output", path) for path in outputs] + [("the file", f) for f in files]
    resolved = [os.path.realpath(path) for _, path in named]
    if len(set(resolved)) != len(resolved):
        raise ValueError(f"the input and the outputs must be different paths, not {[path for _, path in named]}")
    for (what, path), real in zip(named[1:], resolved[1:]):
        for (other_what, other), other_real in zip(named, resolved):
            if other_real.startswith(real + os.sep):
                raise ValueError(f"cannot write {path!r}: it holds {other_what} {other!r}; expected a path of its "
                                 "own (a new one, or an earlier output of this command)")
            if real.startswith(other_real + os.sep):
                raise ValueError(f"cannot write {path!r}: it lies inside {other_what} {other!r}; expected a path "
                                 "of its own")
        parent = os.path.dirname(os.path.abspath(path))
        if not os.path.isdir(parent):
            raise ValueError(f"cannot write {path!r}: its directory {parent!r} does not exist")
        # Each output is staged beside it: found out now, not after the work (or after another output is written).
        try:
            tempfile.TemporaryFile(dir=parent).close()
        except OSError as error:
            raise ValueError(f"cannot write {path!r}: cannot create a file in {parent!r} ({error.strerror}); "
                             "expected a directory this user can write in") from None
    for path in outputs:
        check_replaceable(path)
    for path in files:
        if os.path.isdir(path):
            raise ValueError(f"cannot write {path!r}: it is a directory; expected the path of a file")
        # The file is renamed into place: over /dev/stdout, say, it would replace the device's link.
        if os.path.exists(path) and not os.path.isfile(path):
            raise ValueError(f"cannot write {path!r}: it is not a regular file (a device, FIFO or socket); expected "
                             "the path of a file")


def check_replaceable(path):
    """Raises a ValueError unless ``path`` is free or holds a Zarr array and nothing else."""
    if not os.path.lexists(path):
        return
    expected = "expected a new path or an earlier output of this command (a Zarr array), which is replaced"
    if os.path.islink(path):
        raise ValueError(f"cannot write {path!r}: it is a symbolic link; {expected}")
    if not os.path.isdir(path):
        raise ValueError(f"cannot write {path!r}: it is a file, not a Zarr array; {expected}")
    if not os.path.isfile(os.path.join(path, ".zarray")):
        raise ValueError(f"cannot write {path!r}: it is a directory that holds no Zarr array; {expected}")
    stranger = _first_stranger(path)
    if stranger is not None:
        raise ValueError(f"cannot write {path!r}: besides a Zarr array it holds {stranger!r}; {expected}")


def _first_stranger(path):
    """The first entry of the Zarr array's directory ``path`` that is neither its metadata nor a
    chunk, or None."""
    for directory, folders, files in os.walk(path):
        top = directory == path
        for name in sorted(folders):
            if not name.isdigit():
                return os.path.relpath(os.path.join(directory, name), path)
        for name in sorted(files):
            if not (_CHUNK_KEY.fullmatch(name) or (top and name in _ZARR_METADATA)):
                return os.path.relpath(os.path.join(directory, name), path)
    return None


class _CheckedInput:
    """The input array as the tasks read it: a chunk that cannot be decoded is named in a
    ValueError, and a Blosc chunk whose length is not the one its header gives is refused (Blosc
    decodes a truncated chunk into wrong voxels without an error)."""

    def __init__(self, array, path):
        self.array, self.path = array, path
        self.shape, self.dtype, self.chunks = array.shape, array.dtype, array.chunks

    def __dask_tokenize__(self):
        return tokenize(self.path, self.shape, self.dtype, self.chunks, self.array.compressor, self.array.filters)

    def __getitem__(self, slices):
        blocks = list(itertools.product(*(range(s.start // edge, -(-s.stop // edge))
                                          for s, edge in zip(slices, self.chunks))))
        if isinstance(self.array.compressor, numcodecs.Blosc):
            for block in blocks:
                self._check_blosc_length(block)
        try:
            return self.array[slices]
        except Exception:
            for block in blocks:
                try:
                    self.array[tuple(slice(i * edge, (i + 1) * edge) for i, edge in zip(block, self.chunks))]
                except Exception as error:
                    raise self._unreadable(block, f"{type(error).__name__}: {error}") from None
            raise

    def _chunk_file(self, block):
        """The file of the chunk ``block`` (flat or nested), or None if it is not stored."""
        for separator in (".", os.sep):
            path = os.path.join(self.path, separator.join(map(str, block)))
            if os.path.isfile(path):
                return path
        return None

    def _check_blosc_length(self, block):
        path = self._chunk_file(block)
        if path is None:
            return
        with open(path, "rb") as stream:
            header = stream.read(16)
            length = os.fstat(stream.fileno()).st_size
        if len(header) < 16:
            raise self._unreadable(block, f"it holds {length} bytes, fewer than a Blosc header's 16")
        expected = numcodecs.blosc.cbuffer_sizes(header)[1]
        if expected != length:
            raise self._unreadable(block, f"it holds {length} bytes, its Blosc header gives {expected}")

    def _unreadable(self, block, reason):
        name = self._chunk_file(block) or os.path.join(self.path, ".".join(map(str, block)))
        return ValueError(f"the chunk {name!r} of the Zarr array {self.path!r} cannot be read ({reason}); expected "
                          f"{self.array.compressor or 'uncompressed'} data of a chunk of {self.chunks} {self.dtype} "
                          "voxels")


class _StagedArray:
    """A staged Zarr array that the tasks write chunks into, until it is closed: a write begun
    before ``close`` ends before ``close`` returns, and none begins after, so a removed staging
    directory is not made anew by a task still running (Zarr makes the directories it writes into).
    Pickled for another process, it is the plain array there."""

    def __init__(self, array):
        self.array = array
        self.shape, self.dtype, self.ndim = array.shape, array.dtype, array.ndim
        self._writing = 0
        self._closed = False
        self._condition = threading.Condition()

    def __setitem__(self, key, value):
        with self._condition:
            if self._closed:
                raise RuntimeError("the output was abandoned")
            self._writing += 1
        try:
            self.array[key] = value
        finally:
            with self._condition:
                self._writing -= 1
                self._condition.notify_all()

    def close(self):
        with self._condition:
            self._closed = True
            self._condition.wait_for(lambda: self._writing == 0)

    def __reduce__(self):
        return (_identity, (self.array,))


def _identity(value):
    return value


def _compute(stores, stats, client, progress):
    """Writes the chunks and returns the statistics, in one computation (the chunks are filtered
    once)."""
    if client is not None:
        futures = client.compute([stores, stats])
        try:
            if progress:
                from distributed import progress as show_progress
                show_progress(futures)
            return client.gather(futures)[1]
        except BaseException:
            client.cancel(futures)
            raise
    if progress:
        from dask.diagnostics import ProgressBar
        with ProgressBar(out=sys.stderr):
            return dask.compute(stores, stats)[1]
    return dask.compute(stores, stats)[1]


class StagedOutputs:
    """Outputs written beside their paths (same file system, so that each is put in place by a
    rename), which ``commit`` puts in place together: every path is checked first, and an earlier
    output is moved aside and removed only once every new one is in place, so that a failure (or
    an interruption) in between puts the earlier ones back. ``discard`` removes what is still
    staged."""

    def __init__(self, source):
        self.source = source
        self._staged = []

    def stage_directory(self, path):
        """A new directory beside ``path`` to write its output into."""
        staging = tempfile.mkdtemp(prefix=f".{os.path.basename(path)}.", suffix=".partial",
                                   dir=os.path.dirname(os.path.abspath(path)))
        self._staged.append((staging, path))
        return staging

    def stage_file(self, path, text):
        """Writes ``text`` into a new file beside ``path`` (with the permissions a new file gets)."""
        handle, staging = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.", suffix=".partial",
                                           dir=os.path.dirname(os.path.abspath(path)))
        self._staged.append((staging, path))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(staging, 0o666 & ~umask)
        with os.fdopen(handle, "w") as stream:
            stream.write(text)

    def commit(self):
        """Renames every staged output to its path, replacing the earlier outputs there (checked
        again: each must still be a Zarr array and nothing else, or a regular file)."""
        for staging, path in self._staged:
            if os.path.isdir(staging):
                check_paths(self.source, [path])
            else:
                check_paths(self.source, [], [path])
        moved = []
        try:
            for staging, path in self._staged:
                old = None
                if os.path.lexists(path):
                    old = _free_name(path, ".old")
                    os.rename(path, old)
                moved.append([staging, path, old, False])
                os.rename(staging, path)
                moved[-1][3] = True
        except BaseException:
            for staging, path, old, placed in reversed(moved):
                with contextlib.suppress(OSError):
                    if placed:
                        os.rename(path, staging)
                    if old is not None:
                        os.rename(old, path)
            raise
        self._staged = []
        for _, _, old, _ in moved:
            if old is not None:
                _remove(old)

    def discard(self):
        for staging, _ in self._staged:
            _remove(staging)
        self._staged = []


def _free_name(path, suffix):
    """A new hidden name beside ``path``, free to rename something to."""
    name = tempfile.mkdtemp(prefix=f".{os.path.basename(path)}.", suffix=suffix,
                            dir=os.path.dirname(os.path.abspath(path)))
    os.rmdir(name)
    return name


def _remove(path):
    if os.path.isdir(path) and not os.path.islink(path):
        shutil.rmtree(path, ignore_errors=True)
    else:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(path)
