"""A small MetaImage (.mha) writer and reader, so that the tests can hand arrays to the
command-line tool and read its results back without ITK's Python package."""

import zlib

import numpy as np

_ELEMENT_TYPES = {"uint8": "MET_UCHAR", "int8": "MET_CHAR", "uint16": "MET_USHORT", "int16": "MET_SHORT",
                  "uint32": "MET_UINT", "int32": "MET_INT", "float32": "MET_FLOAT", "float64": "MET_DOUBLE"}
_DTYPES = {name: dtype for dtype, name in _ELEMENT_TYPES.items()}


def write(path, array, spacing=None):
    """Writes a C-ordered view of ``array`` (shape (z, y, x) or (y, x)) as an image of size
    (x, y, z); ``spacing`` in the array's axis order."""
    array = np.ascontiguousarray(array)
    spacing = spacing if spacing is not None else [1.0] * array.ndim
    header = [
        "ObjectType = Image",
        f"NDims = {array.ndim}",
        "BinaryData = True",
        "BinaryDataByteOrderMSB = False",
        "CompressedData = False",
        "DimSize = " + " ".join(str(n) for n in reversed(array.shape)),
        "ElementSpacing = " + " ".join(repr(float(s)) for s in reversed(spacing)),
        f"ElementType = {_ELEMENT_TYPES[array.dtype.name]}",
        "ElementDataFile = LOCAL",
    ]
    with open(path, "wb") as stream:
        stream.write(("\n".join(header) + "\n").encode("ascii"))
        stream.write(array.astype(array.dtype.newbyteorder("<"), copy=False).tobytes())


def read(path):
    """The image at ``path`` as a C-ordered array of shape (z, y, x) or (y, x)."""
    with open(path, "rb") as stream:
        data = stream.read()
    fields = {}
    position = 0
    while True:
        end = data.index(b"\n", position)
        key, _, value = data[position:end].decode("ascii").partition("=")
        fields[key.strip()] = value.strip()
        position = end + 1
        if key.strip() == "ElementDataFile":
            break
    body = data[position:]
    if fields.get("CompressedData") == "True":
        body = zlib.decompress(body)
    dtype = np.dtype(_DTYPES[fields["ElementType"]]).newbyteorder("<")
    shape = tuple(reversed([int(n) for n in fields["DimSize"].split()]))
    return np.frombuffer(body, dtype=dtype).astype(dtype.newbyteorder("="), copy=False).reshape(shape)
