"""smalliso on Dask arrays: the in-memory result, voxel for voxel, computed chunk by chunk on any
Dask scheduler, dask.distributed included."""

from ._graph import remove_small_components

__all__ = ["remove_small_components"]
