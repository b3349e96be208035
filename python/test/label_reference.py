"""A brute-force reference of the label-map rule (docs/labels.md: flood fill, walks, votes) and random label maps to
hold the label filter to it, in NumPy alone: the package's tests and the ITK wrapping's test share it."""

import itertools
from collections import deque

import numpy as np

LABEL_DTYPES = ("uint8", "int8", "uint16", "int16", "uint32", "int32", "uint64", "int64", "float32", "float64")
# Ids of each dtype: its extremes, negative and sparse ones (a background 0 always among them).
IDS = {"uint8": [0, 3, 200, 255], "int8": [-128, -5, 0, 7, 127], "uint16": [0, 2, 12175, 65535],
       "int16": [-32768, -1, 0, 12175], "uint32": [0, 5, 2**32 - 1], "int32": [-2**31, 0, 41, 2**31 - 1],
       "uint64": [0, 9, 2**63 + 5, 2**64 - 1], "int64": [-2**63, 0, 12175, 2**62 + 3],
       "float32": [0.0, 2.0, -3.0, 1e6], "float64": [0.0, -7.0, 4.0, 2.0**52]}
SHAPES = {2: (9, 11), 3: (5, 6, 7), 4: (3, 4, 5, 4)}


def random_labels(rng, dtype, shape):
    """Blocks of 2 voxels per axis of random ids, with about a fifth of the voxels changed to
    random ids: components of every size, islands and holes."""
    ids = np.array(IDS[dtype], dtype=dtype)
    coarse = ids[rng.integers(len(ids), size=[(n + 1) // 2 for n in shape])]
    labels = coarse
    for axis in range(len(shape)):
        labels = np.repeat(labels, 2, axis=axis)
    labels = np.ascontiguousarray(labels[tuple(slice(0, n) for n in shape)])
    noise = rng.random(shape) < 0.2
    labels[noise] = ids[rng.integers(len(ids), size=int(noise.sum()))]
    return labels


def reference(labels, max_size, fully_connected=False, select="all", background=0, max_sizes=None,
              keep_largest=0):
    """(filtered, mask, stats) by the rule of docs/labels.md, voxel by voxel."""
    shape, values = labels.shape, labels.tolist() if labels.ndim == 0 else labels.ravel().tolist()
    values = [int(v) for v in values]
    coordinates = list(np.ndindex(shape))
    flat = {c: i for i, c in enumerate(coordinates)}
    steps = [d for d in itertools.product((-1, 0, 1), repeat=len(shape)) if any(d)
             and (fully_connected or sum(map(abs, d)) == 1)]
    component = [-1] * len(values)
    sizes, component_labels = [], []
    for start in range(len(values)):
        if component[start] >= 0:
            continue
        component[start] = len(sizes)
        queue, size = deque([start]), 0
        while queue:
            at = queue.popleft()
            size += 1
            for d in steps:
                neighbour = tuple(c + s for c, s in zip(coordinates[at], d))
                n = flat.get(neighbour)
                if n is not None and component[n] < 0 and values[n] == values[start]:
                    component[n] = len(sizes)
                    queue.append(n)
        sizes.append(size)
        component_labels.append(values[start])
    removed = _removed_components(sizes, component_labels, max_size, select, background, max_sizes or {},
                                  keep_largest)
    output, mask = list(values), [0] * len(values)
    stats = {"labels": {}, "modified_voxels": 0, "unrepairable_voxels": 0}
    for label in set(component_labels):
        own = [s for s, l in zip(sizes, component_labels) if l == label]
        gone = [s for s, l, r in zip(sizes, component_labels, removed) if l == label and r]
        stats["labels"][label] = {"components": len(own), "removed_components": len(gone),
                                  "removed_voxels": sum(gone), "gained_voxels": 0,
                                  "size_histogram": {s: own.count(s) for s in set(own)}}
    for v, c in enumerate(component):
        if not removed[c]:
            continue
        mask[v] = 1
        votes = _votes(v, c, coordinates, flat, component, values, removed)
        if not votes:
            stats["unrepairable_voxels"] += 1
            continue
        output[v] = _elect(votes)
        stats["labels"][output[v]]["gained_voxels"] += 1
        stats["modified_voxels"] += 1
    as_array = np.array(output, dtype=object).astype(labels.dtype).reshape(shape)
    return as_array, np.array(mask, np.uint8).reshape(shape), stats


def _removed_components(sizes, component_labels, max_size, select, background, max_sizes, keep_largest):
    def selected(label):
        if select == "all":
            return True
        if select == "islands":
            return label != background
        if select == "holes":
            return label == background
        return label in [int(s) for s in select]

    smallest_kept = {}
    if keep_largest > 0:
        for label in set(component_labels):
            own = sorted((s for s, l in zip(sizes, component_labels) if l == label), reverse=True)
            if len(own) >= keep_largest:
                smallest_kept[label] = own[keep_largest - 1]
    return [selected(label) and (size <= max_sizes.get(label, max_size) or size < smallest_kept.get(label, 0))
            for size, label in zip(sizes, component_labels)]


def _votes(v, c, coordinates, flat, component, values, removed):
    """(label, steps, kept) of the first voxel outside component c on each axis walk from v."""
    votes = []
    for axis, direction in itertools.product(range(len(coordinates[v])), (-1, 1)):
        at, steps = list(coordinates[v]), 0
        while True:
            at[axis] += direction
            steps += 1
            w = flat.get(tuple(at))
            if w is None:
                break
            if component[w] != c:
                votes.append((values[w], steps, not removed[component[w]]))
                break
    return votes


def _elect(votes):
    if any(kept for _, _, kept in votes):
        votes = [vote for vote in votes if vote[2]]
    labels = {label for label, _, _ in votes}
    return min(labels, key=lambda label: (-sum(1 for l, _, _ in votes if l == label),
                                          min(s for l, s, _ in votes if l == label), label))
