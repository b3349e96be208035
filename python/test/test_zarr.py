"""Zarr in and out: smalliso.dask.remove_small_components_zarr and python3 -m smalliso.dask (its
results and JSON statistics against the in-memory function and the command-line tool, a failure
that leaves nothing behind, errors)."""

import functools
import itertools
import json
import os
import signal
import subprocess
import sys
import time

import dask
import dask.array
import numcodecs
import numpy as np
import pytest
import zarr

import smalliso
import smalliso.dask
import smalliso.dask.__main__ as command
from label_reference import random_labels
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


@pytest.mark.skipif(not TOOL, reason="SmallIsoComponentFilter was not built (SMALLISO_FILTER_TOOL unset)")
@pytest.mark.parametrize("select", ["islands", "0,5"])
def test_the_command_cleans_label_maps_as_the_command_line_tool(tmp_path, select):
    labels = random_labels(np.random.default_rng(6), "uint16", (10, 11, 12))
    save(tmp_path / "in.zarr", labels, (4, 5, 6))
    options = ["--max-size", 3, "--select", select, "--max-size-of", "12175=9,2=0", "--fully-connected"]
    done = run_command(tmp_path / "in.zarr", tmp_path / "out.zarr", "--labels", *options, "--stats",
                       tmp_path / "dask.json", "--removed-mask", tmp_path / "mask.zarr")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("Label map, K = 3 voxels")
    expected, expected_mask, expected_stats = smalliso.remove_small_label_components(
        labels, 3, True, select=select if select == "islands" else [0, 5], max_sizes={12175: 9, 2: 0},
        return_mask=True, return_stats=True)
    assert expected_stats["modified_voxels"] > 0
    assert same_bits(zarr.open_array(str(tmp_path / "out.zarr"), mode="r")[...], expected)
    assert same_bits(zarr.open_array(str(tmp_path / "mask.zarr"), mode="r")[...], expected_mask)
    write_mha(tmp_path / "in.mha", labels)
    subprocess.run([TOOL, str(tmp_path / "in.mha"), str(tmp_path / "out.mha"), "--labels"] + [str(o) for o in options]
                   + ["--stats", str(tmp_path / "tool.json"), "--quiet"], check=True)
    ours, tool = (json.load(open(tmp_path / name)) for name in ("dask.json", "tool.json"))
    for key in ("modified_voxels", "unrepairable_voxels"):
        assert ours["statistics"][key] == tool["statistics"][key] == expected_stats[key], key
    changed = {label: {key: entry[key] for key in ("removed_voxels", "gained_voxels")}
               for label, entry in tool["statistics"]["labels"].items()
               if entry["removed_voxels"] or entry["gained_voxels"]}
    assert ours["statistics"]["labels"] == changed
    for key in ("labels", "effective_max_size", "selection", "background", "max_size_of", "connectivity"):
        assert ours["parameters"][key] == tool["parameters"][key], key
    assert ours["parameters"].get("selected_labels") == tool["parameters"].get("selected_labels")


@pytest.mark.parametrize("arguments, message", [
    (["missing.zarr", "out.zarr", "--isovalue", "1"], "'missing.zarr' is not a Zarr array"),
    (["in.zarr", "out.zarr"], "the following arguments are required: --isovalue"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--side", "up"], "invalid choice: 'up'"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--max-size", "-2"], "max_size is -2"),
    (["in.zarr", "out.zarr", "--isovalue", "nan"], "isovalue is NaN"),
    (["in.zarr", "in.zarr", "--isovalue", "1"], "the input and the outputs must be different paths"),
    (["in.zarr", "no/such/dir/out.zarr", "--isovalue", "1"], "does not exist"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--scheduler", "bogus"],
     "--scheduler 'bogus' is not a scheduler (missing port number in address 'bogus'); expected threads"),
    (["in.zarr", "out.zarr", "--labels", "--isovalue", "1"], "--isovalue has no meaning for a label map"),
    (["in.zarr", "out.zarr", "--labels", "--side", "above"], "--side has no meaning for a label map"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--select", "all"], "--select applies to label maps only"),
    (["in.zarr", "out.zarr", "--isovalue", "1", "--max-size-of", "1=2"], "--max-size-of applies to label maps"),
    (["in.zarr", "out.zarr", "--labels", "--select", "some"], "expected all, islands, holes or label ids"),
    (["in.zarr", "out.zarr", "--labels", "--select", "3,300"], "300"),
    (["in.zarr", "out.zarr", "--labels", "--background", "x"], "'x' is not a label id"),
    (["in.zarr", "out.zarr", "--labels", "--max-size-of", "7"], "'7' is not L=K"),
    (["in.zarr", "out.zarr", "--labels", "--max-size-of", "7=1", "--max-size-of", "7=2"], "more than one K"),
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


def test_a_scheduler_it_cannot_reach_leaves_dask_as_it_was(tmp_path, monkeypatch, capsys):
    save(tmp_path / "in.zarr", np.zeros((3, 4), np.uint8), (2, 2))
    monkeypatch.chdir(tmp_path)
    before = dask.config.get("scheduler", None)
    assert command.main(["in.zarr", "out.zarr", "--isovalue", "1", "--scheduler", "bogus"]) == 2
    assert "is not a scheduler" in capsys.readouterr().err
    assert dask.config.get("scheduler", None) == before
    # The threaded scheduler still computes in this process.
    assert dask.array.ones(4, chunks=2).sum().compute() == 4


def snapshot(directory):
    """Every file under ``directory`` with its bytes, and every folder, to see that nothing changed."""
    found = {}
    for folder, folders, files in os.walk(directory):
        for name in folders:
            found[os.path.relpath(os.path.join(folder, name), directory)] = None
        for name in files:
            path = os.path.join(folder, name)
            with open(path, "rb") as stream:
                found[os.path.relpath(path, directory)] = stream.read()
    return found


def make_data_folder(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    save(data / "in.zarr", np.arange(60, dtype=np.uint8).reshape(3, 4, 5), (2, 2, 2))
    (data / "notes.txt").write_text("keep\n")
    mydocs = tmp_path / "mydocs"
    mydocs.mkdir()
    (mydocs / "thesis.txt").write_text("thesis\n")
    (tmp_path / "file.txt").write_text("a file\n")
    save(tmp_path / "earlier.zarr", np.zeros((2, 2), np.uint8), (1, 1))
    (tmp_path / "earlier.zarr" / "notes.txt").write_text("mine\n")
    os.symlink(tmp_path / "mydocs", tmp_path / "link.zarr")
    os.symlink(os.devnull, tmp_path / "null.json")
    return data


@pytest.mark.parametrize("arguments, message", [
    (["data/in.zarr", "data"], "cannot write 'data': it holds the input 'data/in.zarr'"),
    (["data/in.zarr", "out.zarr", "--removed-mask", "data"], "cannot write 'data': it holds the input"),
    (["data/in.zarr", "."], "cannot write '.': it holds the input"),
    (["data/in.zarr", "data/in.zarr/out.zarr"], "lies inside the input 'data/in.zarr'"),
    (["data/in.zarr", "mydocs"], "'mydocs': it is a directory that holds no Zarr array"),
    (["data/in.zarr", "out.zarr", "--removed-mask", "mydocs"], "'mydocs': it is a directory that holds no Zarr"),
    (["data/in.zarr", "file.txt"], "'file.txt': it is a file, not a Zarr array"),
    (["data/in.zarr", "earlier.zarr"], "besides a Zarr array it holds 'notes.txt'"),
    (["data/in.zarr", "link.zarr"], "'link.zarr': it is a symbolic link"),
    (["data/in.zarr", "link.zarr/."], "'link.zarr/.': it is a directory that holds no Zarr array"),
    (["data/in.zarr", "out.zarr", "--removed-mask", "out.zarr/mask.zarr"], "'out.zarr': it holds the output 'out.zarr/mask.zarr'"),
    (["data/in.zarr", "out.zarr", "--stats", "data/in.zarr/.zarray"], "lies inside the input"),
    (["data/in.zarr", "out.zarr", "--stats", "mydocs"], "'mydocs': it is a directory; expected the path of a file"),
    (["data/in.zarr", "out.zarr", "--stats", "null.json"], "'null.json': it is not a regular file"),
])
def test_the_command_replaces_nothing_but_an_earlier_zarr_array(tmp_path, monkeypatch, capsys, arguments, message):
    make_data_folder(tmp_path)
    before = snapshot(tmp_path)
    monkeypatch.chdir(tmp_path)
    status = command.main(arguments + ["--isovalue", "1", "--max-size", "2", "--quiet"])
    stderr = capsys.readouterr().err
    assert status == 2
    assert stderr.count("\n") == 1 and message in stderr and "expected" in stderr, stderr
    assert snapshot(tmp_path) == before


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes in a read-only directory")
@pytest.mark.parametrize("output", ["out", "stats"])
def test_the_command_checks_that_it_can_write_before_the_work(tmp_path, monkeypatch, capsys, output):
    save(tmp_path / "in.zarr", np.zeros((3, 4), np.uint8), (2, 2))
    (tmp_path / "locked").mkdir()
    monkeypatch.chdir(tmp_path)
    os.chmod("locked", 0o555)
    arguments = ["in.zarr", "locked/out.zarr"] if output == "out" else ["in.zarr", "out.zarr", "--stats",
                                                                        "locked/s.json"]
    try:
        status = command.main(arguments + ["--isovalue", "1", "--quiet"])
    finally:
        os.chmod("locked", 0o755)
    stderr = capsys.readouterr().err
    assert status == 2 and stderr.count("\n") == 1, stderr
    assert "cannot create a file in" in stderr and "expected a directory this user can write in" in stderr, stderr
    assert not (tmp_path / "out.zarr").exists() and os.listdir("locked") == [] and leftovers(tmp_path) == []


def test_the_command_replaces_an_earlier_output_of_its_own(tmp_path, monkeypatch):
    volume, isovalue = random_volume(np.random.default_rng(5), "uint8", (6, 7, 8))
    save(tmp_path / "in.zarr", volume, (3, 3, 3))
    monkeypatch.chdir(tmp_path)
    for max_size, output in ((2, "out.zarr"), (5, "out.zarr/."), (3, "./out.zarr/")):
        arguments = ["in.zarr", output, "--removed-mask", "mask.zarr", "--isovalue", str(isovalue),
                     "--max-size", str(max_size), "--quiet"]
        assert command.main(arguments) == 0
        expected, mask = smalliso.remove_small_components(volume, isovalue, max_size, return_mask=True)
        assert same_bits(zarr.open_array("out.zarr", mode="r")[...], expected)
        assert same_bits(zarr.open_array("mask.zarr", mode="r")[...], mask)
    assert leftovers(tmp_path) == []


@pytest.mark.parametrize("setup, message", [
    ("plain file", "'in.zarr' is not a Zarr array (expected the directory of one array)"),
    ("corrupt metadata", "'in.zarr' is not a readable Zarr array: its metadata 'in.zarr/.zarray' is invalid"),
    ("no metadata", "'in.zarr' is not a Zarr array (expected the directory of one array)"),
    ("metadata list", "'in.zarr' is not a readable Zarr array: its metadata 'in.zarr/.zarray' is invalid"),
    ("metadata of another format", "its metadata 'in.zarr/.zarray' is invalid (unsupported zarr format: 3)"),
    ("chunk edge 0", "its metadata 'in.zarr/.zarray' gives shape [3, 4] and chunks [0, 2]; expected whole numbers"),
    ("chunk edge 1.5", "gives shape [3, 4] and chunks [1.5, 2]; expected whole numbers"),
    ("negative extent", "gives shape [3, -4] and chunks [2, 2]; expected whole numbers"),
    ("chunks of another dimension", "gives shape [3, 4] and chunks [2]; expected whole numbers"),
    ("corrupt attributes", "its attributes 'in.zarr/.zattrs' are invalid"),
    ("attributes list", "its attributes 'in.zarr/.zattrs' are invalid ([1]); expected a JSON object"),
    ("0-D", "the array is 0-D (shape ()); expected a 2-D or 3-D array"),
    ("a chunk missing without a fill value", "1 of the 4 chunks of the Zarr array 'in.zarr' are not stored and it has "
     "no fill value to read them as; expected every chunk stored, or a fill value in 'in.zarr/.zarray'"),
])
def test_the_command_names_an_unreadable_input(tmp_path, monkeypatch, capsys, setup, message):
    monkeypatch.chdir(tmp_path)
    if setup == "plain file":
        (tmp_path / "in.zarr").write_bytes(b"\x00" * 64)
    elif setup == "0-D":
        zarr.save_array("in.zarr", np.float32(1))
    else:
        save(tmp_path / "in.zarr", np.zeros((3, 4), np.uint8), (2, 2))
        metadata = tmp_path / "in.zarr" / ".zarray"
        changes = {"metadata of another format": {"zarr_format": 3}, "chunk edge 0": {"chunks": [0, 2]},
                   "chunk edge 1.5": {"chunks": [1.5, 2]}, "negative extent": {"shape": [3, -4]},
                   "chunks of another dimension": {"chunks": [2]}}
        if setup == "corrupt metadata":
            metadata.write_text('{"chunks": [2, 2], "dtype": ')
        elif setup == "no metadata":
            metadata.unlink()
        elif setup == "metadata list":
            metadata.write_text("[]")
        elif setup == "corrupt attributes":
            (tmp_path / "in.zarr" / ".zattrs").write_text("{")
        elif setup == "attributes list":
            (tmp_path / "in.zarr" / ".zattrs").write_text("[1]")
        elif setup == "a chunk missing without a fill value":
            metadata.write_text(json.dumps({**json.loads(metadata.read_text()), "fill_value": None}))
            (tmp_path / "in.zarr" / "1.0").unlink()
        else:
            metadata.write_text(json.dumps({**json.loads(metadata.read_text()), **changes[setup]}))
    status = command.main(["in.zarr", "out.zarr", "--isovalue", "1"])
    stderr = capsys.readouterr().err
    assert status == 2 and stderr.count("\n") == 1 and message in stderr and "%r" not in stderr, stderr
    assert not (tmp_path / "out.zarr").exists() and leftovers(tmp_path) == []


def test_the_command_says_which_chunks_the_input_lacks(tmp_path, monkeypatch, capsys):
    volume, isovalue = random_volume(np.random.default_rng(6), "int16", (6, 6, 6))
    save(tmp_path / "in.zarr", volume, (3, 3, 3))
    (tmp_path / "in.zarr" / "1.0.1").unlink()
    monkeypatch.chdir(tmp_path)
    assert command.main(["in.zarr", "out.zarr", "--isovalue", str(isovalue), "--stats", "s.json", "--quiet"]) == 0
    stderr = capsys.readouterr().err
    assert "1 of the 8 chunks of 'in.zarr' are not stored; Zarr reads them as the fill value 0" in stderr
    with open("s.json") as stream:
        assert json.load(stream)["input"]["missing_chunks"] == 1
    sparse = volume.copy()
    sparse[3:, :3, 3:] = 0
    assert same_bits(zarr.open_array("out.zarr", mode="r")[...], smalliso.remove_small_components(sparse, isovalue))


@pytest.mark.parametrize("compressor, damage, message", [
    (numcodecs.Blosc(), "truncate", "(it holds 20 bytes, its Blosc header gives"),
    (numcodecs.Blosc(), "garbage", "(it holds 7 bytes, fewer than a Blosc header's 16)"),
    (numcodecs.Zlib(), "garbage", "(error: Error -3 while decompressing data"),
    (None, "truncate", "(ValueError: cannot reshape array of size 5 into shape (3,3,3))"),
])
def test_the_command_names_a_chunk_it_cannot_read(tmp_path, monkeypatch, capsys, compressor, damage, message):
    volume, isovalue = random_volume(np.random.default_rng(8), "float32", (6, 6, 6))
    zarr.save_array(str(tmp_path / "in.zarr"), volume, chunks=(3, 3, 3), compressor=compressor,
                    dimension_separator="/")
    chunk = tmp_path / "in.zarr" / "1" / "0" / "1"
    chunk.write_bytes(chunk.read_bytes()[:20] if damage == "truncate" else b"garbage")
    monkeypatch.chdir(tmp_path)
    assert command.main(["in.zarr", "out.zarr", "--isovalue", str(isovalue), "--quiet"]) == 2
    stderr = capsys.readouterr().err
    assert stderr.count("\n") == 1 and "the chunk 'in.zarr/1/0/1' of the Zarr array 'in.zarr' cannot be read " \
        + message in stderr and "; expected " in stderr, stderr
    assert not (tmp_path / "out.zarr").exists() and leftovers(tmp_path) == []


@pytest.mark.parametrize("layout", ["nested", "a directory for a chunk", "a chunk outside the array"])
def test_the_command_counts_the_stored_chunks_as_files(tmp_path, monkeypatch, capsys, layout):
    volume, isovalue = random_volume(np.random.default_rng(7), "int16", (6, 6, 6))
    zarr.save_array(str(tmp_path / "in.zarr"), volume, chunks=(3, 3, 3),
                    dimension_separator="/" if layout == "nested" else ".")
    expected = 0
    if layout == "a directory for a chunk":
        (tmp_path / "in.zarr" / "1.0.1").unlink()
        (tmp_path / "in.zarr" / "1.0.1").mkdir()
        expected = 1
    elif layout == "a chunk outside the array":
        (tmp_path / "in.zarr" / "2.0.0").write_bytes((tmp_path / "in.zarr" / "0.0.0").read_bytes())
    monkeypatch.chdir(tmp_path)
    assert command.main(["in.zarr", "out.zarr", "--isovalue", str(isovalue), "--stats", "s.json", "--quiet"]) == 0
    assert ("not stored" in capsys.readouterr().err) == (expected > 0)
    with open("s.json") as stream:
        assert json.load(stream)["input"]["missing_chunks"] == expected


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP, signal.SIGINT])
def test_a_signal_leaves_nothing_and_one_line(tmp_path, signum):
    # Uniform noise with a large K: each task takes a while, so the signal comes mid-computation.
    volume = np.random.default_rng(7).integers(0, 256, (96, 96, 96), dtype=np.uint8)
    save(tmp_path / "in.zarr", volume, (24, 24, 24))
    save(tmp_path / "out.zarr", np.zeros((2, 2), np.uint8), (1, 1))
    process = subprocess.Popen(
        [sys.executable, "-m", "smalliso.dask", tmp_path / "in.zarr", tmp_path / "out.zarr", "--isovalue", "128",
         "--max-size", "200", "--removed-mask", tmp_path / "mask.zarr", "--quiet"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not any(name.endswith(".partial") for name in os.listdir(tmp_path)) and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.2)
    process.send_signal(signum)
    stdout, stderr = process.communicate(timeout=120)
    assert process.returncode == -signum, (process.returncode, stderr)
    assert stderr == f"smalliso.dask: stopped by {signal.Signals(signum).name}; nothing was written\n"
    assert leftovers(tmp_path) == []
    assert zarr.open_array(str(tmp_path / "out.zarr"), mode="r").shape == (2, 2)
    assert not (tmp_path / "mask.zarr").exists()


# Runs the command with every rename into the path named first preceded by the signal numbered
# second, raised in the command itself (whose handler runs at once, before the rename): the signal
# comes while the outputs are being put in place.
SIGNAL_IN_THE_COMMIT = """
import os, runpy, signal, sys

name, signum = sys.argv[1], int(sys.argv[2])
rename = os.rename

def signalling_rename(source, destination):
    if os.path.basename(destination) == name:
        signal.raise_signal(signum)
    rename(source, destination)

os.rename = os.replace = signalling_rename
sys.argv = ["smalliso.dask"] + sys.argv[3:]
runpy.run_module("smalliso.dask", run_name="__main__", alter_sys=True)
"""


@pytest.mark.parametrize("name, signum", [("out.zarr", signal.SIGTERM), ("mask.zarr", signal.SIGTERM),
                                          ("st.json", signal.SIGTERM), ("mask.zarr", signal.SIGINT),
                                          ("mask.zarr", signal.SIGHUP)])
def test_a_signal_while_the_outputs_are_put_in_place_waits_for_all(tmp_path, monkeypatch, name, signum):
    volume = np.random.default_rng(9).integers(0, 256, (12, 12, 12), dtype=np.uint8)
    save(tmp_path / "in.zarr", volume, (6, 6, 6))
    expected = {size: smalliso.remove_small_components(volume, 150.0, size, return_mask=True) for size in (20, 5)}
    assert not same_bits(expected[20][1], expected[5][1])
    monkeypatch.chdir(tmp_path)
    arguments = ["in.zarr", "out.zarr", "--isovalue", "150", "--removed-mask", "mask.zarr", "--stats", "st.json",
                 "--quiet"]
    assert command.main(arguments + ["--max-size", "20"]) == 0
    process = subprocess.run([sys.executable, "-c", SIGNAL_IN_THE_COMMIT, name, str(int(signum))] + arguments
                             + ["--max-size", "5"], capture_output=True, text=True, timeout=120)
    assert process.returncode == -signum, (process.returncode, process.stderr)
    assert process.stderr == (f"smalliso.dask: stopped by {signal.Signals(signum).name}; 'out.zarr', 'mask.zarr' "
                              "and 'st.json' all written before it\n")
    # Every output of the second run, none of the first.
    assert same_bits(zarr.open_array("out.zarr", mode="r")[...], expected[5][0])
    assert same_bits(zarr.open_array("mask.zarr", mode="r")[...], expected[5][1])
    with open("st.json") as stream:
        assert json.load(stream)["parameters"]["max_size"] == 5
    assert leftovers(tmp_path) == []


def test_a_failure_while_the_outputs_are_put_in_place_keeps_the_earlier_ones(tmp_path, monkeypatch):
    volume = np.random.default_rng(9).integers(0, 256, (12, 12, 12), dtype=np.uint8)
    save(tmp_path / "in.zarr", volume, (6, 6, 6))
    run = functools.partial(smalliso.dask.remove_small_components_zarr, tmp_path / "in.zarr", tmp_path / "out.zarr",
                            150.0, removed_mask=tmp_path / "mask.zarr")
    run(20)
    earlier = {name: zarr.open_array(str(tmp_path / name), mode="r")[...] for name in ("out.zarr", "mask.zarr")}
    rename = os.rename

    def failing_rename(source, destination):
        if os.path.basename(destination) == "mask.zarr" and source.endswith(".partial"):
            raise OSError("the mask's rename failed")
        rename(source, destination)

    monkeypatch.setattr(os, "rename", failing_rename)
    with pytest.raises(OSError, match="mask's rename failed"):
        run(5)
    # The image was put in place first; it is taken back, and the earlier one put back.
    for name, values in earlier.items():
        assert same_bits(zarr.open_array(str(tmp_path / name), mode="r")[...], values), name
    assert leftovers(tmp_path) == []


def test_a_failure_leaves_nothing_once_the_running_writes_end(tmp_path, monkeypatch):
    # The first chunk write fails while another is still under way (both slowed down here); that
    # one must not make the removed staging directory anew.
    volume, isovalue = random_volume(np.random.default_rng(8), "uint8", (8, 6, 6))
    save(tmp_path / "in.zarr", volume, (2, 6, 6))
    write = zarr.Array.__setitem__
    calls = itertools.count()

    def failing_then_slow_write(array, key, value):
        first = next(calls) == 0
        time.sleep(0.2 if first else 0.6)
        if first:
            raise OSError("the first write failed")
        write(array, key, value)

    monkeypatch.setattr(zarr.Array, "__setitem__", failing_then_slow_write)
    with dask.config.set(scheduler="threads", num_workers=2), pytest.raises(OSError, match="first write"):
        smalliso.dask.remove_small_components_zarr(tmp_path / "in.zarr", tmp_path / "out.zarr", isovalue, 1)
    time.sleep(1)
    assert leftovers(tmp_path) == [] and not (tmp_path / "out.zarr").exists()
