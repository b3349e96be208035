"""The benchmark's volumes: synthetic ones (random noise; blobs with specks and bubbles, a function
of the voxel's position so that any chunk of it can be made on its own), and the real volumes of
DATA_DIR read from their gzip NRRD files."""

import gzip
import os

import numpy as np

# The real volumes and the isovalues used for them in the literature.
REAL_VOLUMES = {"aneurism": 30.5, "bonsai": 50.5, "lobster": 20.5}
SYNTHETIC_ISOVALUE = 127.5


def noise(shape, seed=1):
    """Uniform random uint8 noise: the worst case, a component structure at every scale."""
    return np.random.default_rng(seed).integers(0, 256, size=shape, dtype=np.uint8)


def blobs(shape, begin=(0, 0, 0)):
    """uint8 blobs (a smooth field around the isovalue 127.5) with 1 % of the voxels set to 255 and
    1 % to 0, which gives specks outside the blobs and bubbles inside; ``begin`` is the position of
    the box of ``shape`` in the whole volume, so chunks made one by one fit together."""
    z, y, x = (np.arange(b, b + n, dtype=np.float32).reshape([-1 if a == axis else 1 for a in range(3)])
               for axis, (b, n) in enumerate(zip(begin, shape)))
    field = 100.0 + 40.0 * (np.sin(x * 0.11) + np.sin(y * 0.13) + np.sin(z * 0.07))
    volume = np.clip(field, 0, 254).astype(np.uint8)
    index = ((z.astype(np.uint64) * 1_000_003 + y.astype(np.uint64)) * 1_000_033 + x.astype(np.uint64))
    salt = _splitmix64(index) % np.uint64(100)
    volume[salt == 0] = 255
    volume[salt == 1] = 0
    return volume


def _splitmix64(values):
    """A hash of each value (SplitMix64's finalizer), for noise that depends only on the position."""
    with np.errstate(over="ignore"):
        z = values + np.uint64(0x9E3779B97F4A7C15)
        z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
        z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
        return z ^ (z >> np.uint64(31))


def read_nrrd(path):
    """A NRRD file with an attached raw or gzip body as a C-ordered array (shape (z, y, x))."""
    with open(path, "rb") as stream:
        data = stream.read()
    header, _, body = data.partition(b"\n\n")
    fields = {}
    for line in header.decode("ascii").splitlines()[1:]:
        if line.startswith("#") or ":" not in line:
            continue
        key, _, value = line.partition(":")
        fields[key.strip()] = value.strip()
    types = {"uint8": "u1", "unsigned char": "u1", "uint16": "u2", "unsigned short": "u2", "int16": "i2",
             "short": "i2", "float": "f4", "double": "f8"}
    dtype = np.dtype(types[fields["type"]]).newbyteorder("<" if fields.get("endian", "little") == "little" else ">")
    if fields.get("encoding") in ("gzip", "gz"):
        body = gzip.decompress(body)
    shape = tuple(reversed([int(n) for n in fields["sizes"].split()]))
    return np.frombuffer(body, dtype=dtype).astype(dtype.newbyteorder("="), copy=False).reshape(shape)


def load(name, data_dir=None, size=256):
    """(volume, isovalue) for a volume name: noise, blobs, or a real volume of ``data_dir``."""
    if name == "noise":
        return noise((size,) * 3), SYNTHETIC_ISOVALUE
    if name == "blobs":
        return blobs((size,) * 3), SYNTHETIC_ISOVALUE
    return read_nrrd(os.path.join(data_dir, name + ".nrrd")), REAL_VOLUMES[name]


# The label maps of DATA_DIR/labels: segmentations and an atlas, as the C++ label benchmark times.
REAL_LABEL_MAPS = ("totalseg_trunk_ct_seg", "aal_atlas", "synthseg_head_seg")


def synthetic_labels(size, labels=6, noise=0.02, seed=1):
    """A uint16 map of ``labels`` bands along a wavy surface with a fraction ``noise`` of its voxels
    set to random labels: islands of every label in every other, and holes."""
    z, y, x = np.meshgrid(*(np.arange(size, dtype=np.float64),) * 3, indexing="ij")
    height = (z + 4.0 * np.sin(0.2 * x) * np.cos(0.15 * y)) / size
    bands = np.clip(height * labels, 0, labels - 1).astype(np.uint16)
    random = np.random.default_rng(seed)
    speckled = random.random(bands.shape) < noise
    bands[speckled] = random.integers(0, labels, size=int(speckled.sum()), dtype=np.uint16)
    return bands


def load_labels(name, data_dir=None, size=256):
    """A uint16 label map (shape (z, y, x)): "synthetic", or a NIfTI map of DATA_DIR/labels, read
    with nibabel (SynthSeg's float32 map holds whole numbers)."""
    if name == "synthetic":
        return synthetic_labels(size)
    import nibabel

    data = np.asanyarray(nibabel.load(os.path.join(data_dir, "labels", name + ".nii.gz")).dataobj)
    return np.ascontiguousarray(data.T).astype(np.uint16)
