"""smalliso: removes the small specks and bubbles on either side of an isovalue from NumPy and
Dask arrays, changing only the voxels that make them, so that an isosurface extracted afterwards
has no tiny pieces.

* ``smalliso.remove_small_components(array, isovalue, ...)``: a NumPy array, in memory.
* ``smalliso.remove_small_label_components(labels, max_size, ...)``: a label map (segmentation),
  each removed voxel taking the label its surroundings vote for.
* ``smalliso.dask.remove_small_components(dask_array, isovalue, ...)``: a Dask array, chunk by
  chunk, with the same result voxel for voxel (``python3 -m smalliso.dask`` filters Zarr arrays).
"""

from ._core import label_types, pixel_types
from ._labels import remove_small_label_components
from ._numpy import remove_small_components
from ._version import __version__
__all__ = ["label_types", "pixel_types", "remove_small_components", "remove_small_label_components"]
