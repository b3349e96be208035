"""smalliso on Dask arrays: the in-memory result, voxel for voxel, computed chunk by chunk on any
Dask scheduler (``dask.distributed`` included), and Zarr arrays filtered into Zarr arrays
(``python3 -m smalliso.dask IN.zarr OUT.zarr --isovalue S``); label maps with
``remove_small_label_components`` and ``remove_small_label_components_zarr`` (``--labels``)."""

from ._graph import remove_small_components
from ._labels import remove_small_label_components
from ._zarr import remove_small_components_zarr, remove_small_label_components_zarr

__all__ = ["remove_small_components", "remove_small_components_zarr", "remove_small_label_components",
           "remove_small_label_components_zarr"]
