"""Zarr in and out: smalliso.dask.remove_small_components_zarr and python3 -m smalliso.dask (its
results and JSON statistics against the in-memory function and the command-line tool, a failure
that leaves nothing behind, errors)."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import zarr

import smalliso
import smalliso.dask
import smalliso.dask.__main__ as command
from metaimage import write as write_mha
from volumes import random_volume, same_bits, without_memory

TOOL = os.environ.get("SMALLISO_FILTER_TOOL")


def save(path, volume, chunks):
    zarr.save_array(str(path), volume, chunks=chunks)
    zarr.open_array(str(path), mode="r+").attrs["spacing"] = [1.0] * volume.ndim


def leftovers(directory):
    """Temporary directories and files left beside the outputs."""
    return [name for name in os.listdir(directory) if name.startswith(".")]


def test_round_trip_keeps_chunks_compressor_and_attributes(tmp_path):
    volume, isovalue = random_volume(np.random.default_rng(1), "float32", (9, 10, 11))
    save(tmp_path / "in.zarr", volume, (4, 4, 5))
    stats = smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 4,
                                                       "both", True, removed_mask=tmp_path / "mask.zarr")
    expected, expected_mask, expected_stats = smalliso.remove_small_components(
        volume, isovalue, 4, "both", True, return_mask=True, return_stats=True)
    source, output = (zarr.open_array(str(tmp_path / name), mode="r") for name in ("in.zarr", "out.zarr"))
    assert same_bits(output[...], expected)
    assert same_bits(zarr.open_array(str(tmp_path / "mask.zarr"), mode="r")[...], expected_mask)
    assert stats == without_memory(expected_stats)
    assert output.chunks == source.chunks and output.compressor == source.compressor
    assert output.attrs.asdict() == {"spacing": [1.0, 1.0, 1.0]}
    assert leftovers(tmp_path) == []


def test_tasks_of_several_stored_chunks(tmp_path):
    volume, isovalue = random_volume(np.random.default_rng(4), "int16", (13, 14, 15))
    save(tmp_path / "in.zarr", volume, (2, 3, 4))
    smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 5,
                                               chunks=(4, 6, 8))
    output = zarr.open_array(str(tmp_path / "out.zarr"), mode="r")
    assert output.chunks == (2, 3, 4)
    assert same_bits(output[...], smalliso.remove_small_components(volume, isovalue, 5))
    with pytest.raises(ValueError, match=r"must be whole multiples of the stored chunks \(2, 3, 4\)"):
        smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "other.zarr", isovalue, 5,
                                                   chunks=(4, 5, 8))
    assert not (tmp_path / "other.zarr").exists() and leftovers(tmp_path) == []


def test_an_existing_output_is_replaced_only_when_the_new_one_is_complete(tmp_path):
    volume, isovalue = random_volume(np.random.default_rng(2), "uint8", (8, 9, 10))
    save(tmp_path / "in.zarr", volume, (3, 3, 3))
    save(tmp_path / "out.zarr", np.zeros((2, 2), np.uint8), (1, 1))
    # A chunk of the input that cannot be decompressed makes the computation fail half-way.
    with open(tmp_path / "in.zarr" / "1.1.1", "wb") as stream:
        stream.write(b"not a compressed chunk")
    with pytest.raises(Exception):
        smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 3,
                                                   removed_mask=tmp_path / "mask.zarr")
    assert zarr.open_array(str(tmp_path / "out.zarr"), mode="r").shape == (2, 2)
    assert not (tmp_path / "mask.zarr").exists()
    assert leftovers(tmp_path) == []
    save(tmp_path / "in.zarr", volume, (3, 3, 3))
    smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 3)
    assert same_bits(zarr.open_array(str(tmp_path / "out.zarr"), mode="r")[...],
                     smalliso.remove_small_components(volume, isovalue, 3))
    assert leftovers(tmp_path) == []


def run_command(*arguments):
    return subprocess.run([sys.executable, "-m", "smalliso.dask"] + [str(a) for a in arguments],
                          capture_output=True, text=True)


@pytest.mark.skipif(not TOOL, reason="SmallIsoComponentFilter was not built (SMALLISO_FILTER_TOOL unset)")
def test_the_command_writes_the_statistics_of_the_command_line_tool(tmp_path):
    volume, isovalue = random_volume(np.random.default_rng(3), "int16", (10, 11, 12))
    save(tmp_path / "in.zarr", volume, (4, 5, 6))
    done = run_command(tmp_path / "in.zarr", tmp_path / "out.zarr", "--isovalue", isovalue, "--max-size", 6,
                       "--side", "above", "--fully-connected", "--stats", tmp_path / "dask.json",
                       "--removed-mask", tmp_path / "mask.zarr")
    assert done.returncode == 0, done.stderr
    assert "removed" in done.stdout
    write_mha(tmp_path / "in.mha", volume)
    subprocess.run([TOOL, str(tmp_path / "in.mha"), str(tmp_path / "out.mha"), "--isovalue", repr(isovalue),
                    "--max-size", "6", "--side", "above", "--fully-connected", "--stats", str(tmp_path / "tool.json"),
                    "--quiet"], check=True)
    ours, tool = (json.load(open(tmp_path / name)) for name in ("dask.json", "tool.json"))
    for key in ("above", "below", "modified_voxels", "unrepairable_voxels"):
        assert ours["statistics"][key] == tool["statistics"][key], key
    for key in ("effective_max_size", "side", "connectivity"):
        assert ours["parameters"][key] == tool["parameters"][key], key
    assert ours["input"]["size"] == tool["input"]["size"] == [12, 11, 10]
    assert ours["input"]["pixel_type"] == tool["input"]["pixel_type"] == "int16"
    assert same_bits(zarr.open_array(str(tmp_path / "out.zarr"), mode="r")[...],
                     smalliso.remove_small_components(volume, isovalue, 6, "above", True))


@pytest.mark.parametrize("arguments, message", [
    (["missing.zarr", "out.zarr", "--isovalue", "1"], "'missing.zarr' is not a Zarr array"),
    (["in.zarr", "out.zarr"], "the following arguments are required: --isovalue"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--side", "up"], "invalid choice: 'up'"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--max-size", "-2"], "max_size is -2"),
    (["in.zarr", "out.zarr", "--isovalue", "nan"], "isovalue is NaN"),
    (["in.zarr", "in.zarr", "--isovalue", "1"], "the input and the outputs must be different paths"),
    (["in.zarr", "no/such/dir/out.zarr", "--isovalue", "1"], "does not exist"),
])
def test_the_command_gives_one_line_errors(tmp_path, monkeypatch, capsys, arguments, message):
    save(tmp_path / "in.zarr", np.zeros((3, 4), np.uint8), (2, 2))
    monkeypatch.chdir(tmp_path)
    try:
        status = command.main(arguments)
    except SystemExit as exit:
        status = exit.code
    stderr = capsys.readouterr().err
    assert status == 2
    assert stderr.count("\n") == 1 and message in stderr, stderr
    assert not (tmp_path / "out.zarr").exists()
