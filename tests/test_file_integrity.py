"""Files that survive (issue 29): Result.save, save_scene and the CLI write atomically, so a save
that fails or is killed leaves the previous file intact; a truncated or altered result or scene
file is an error naming the file, never a different result or scene; files written before the
checks still load (docs/reliability.md)."""
import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import deployfx as dfx
from deployfx import _atomic, scene_file, scenes


def _result(n=50, seed=0):
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 1.0, n)
    return dfx.Result({"t": t, "x": rng.standard_normal(n), "v": rng.standard_normal((n, 3))},
                      units={"x": "m"}, metadata={"model": "linear", "dt": 0.01})


def _same(a, b):
    assert a.series == b.series and a.units == b.units and a.metadata == b.metadata
    for name in a.series:
        np.testing.assert_array_equal(a[name], b[name])


# ------------------------------------------------------------------------------------------------
# Atomic writes

def test_a_save_killed_mid_write_leaves_the_previous_file_intact(tmp_path):
    """A child saves a ~200 MB result over a good file and is SIGKILLed while the temporary file
    grows; the good file loads bit for bit."""
    path = tmp_path / "run.npz"
    good = _result()
    good.save(path)
    code = textwrap.dedent(f"""
        import numpy as np, deployfx as dfx
        n = 2_000_000
        big = dfx.Result({{"t": np.arange(n, dtype=float), "q": np.ones((n, 12))}})
        print("saving", flush=True)
        while True:
            big.save({str(path)!r})
    """)
    p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True)
    try:
        assert p.stdout.readline().strip() == "saving"
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:  # wait until a temporary file has data in it
            tmp = [f for f in tmp_path.iterdir() if f.name.startswith(".run.")]
            if tmp and tmp[0].stat().st_size > 1_000_000:
                break
            time.sleep(0.005)
        else:
            pytest.fail("the child never wrote its temporary file")
        p.send_signal(signal.SIGKILL)
        p.wait(timeout=30)
    finally:
        p.kill()
        p.wait()
        p.stdout.close()
    loaded = dfx.load(path)
    if loaded.series == good.series:  # killed before its first rename (the usual case)
        _same(loaded, good)
    else:  # killed after a complete save: then that one is complete
        assert loaded.q.shape == (2_000_000, 12)
    # The temporary file of the killed save is left behind (SIGKILL runs no clean-up), beside it.
    assert all(f.name.startswith(".run.") and ".tmp" in f.name
               for f in tmp_path.iterdir() if f.name != "run.npz")


def test_a_save_that_fails_mid_write_leaves_the_previous_file_and_no_temporary(tmp_path,
                                                                              monkeypatch):
    path = tmp_path / "run.npz"
    good = _result()
    good.save(path)

    def failing_savez(fh, **entries):
        fh.write(b"PK\x03\x04 partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(np, "savez", failing_savez)
    with pytest.raises(OSError, match="No space left"):
        _result(seed=1).save(path)
    monkeypatch.undo()
    _same(dfx.load(path), good)
    assert sorted(f.name for f in tmp_path.iterdir()) == ["run.npz"]


def test_atomic_writes_keep_the_mode_of_the_file_they_replace(tmp_path):
    path = tmp_path / "a.txt"
    path.write_text("old")
    os.chmod(path, 0o640)
    _atomic.write_text(path, "new")
    assert path.read_text() == "new" and (path.stat().st_mode & 0o777) == 0o640


def test_an_interrupted_scene_save_leaves_the_previous_file(tmp_path, monkeypatch):
    paper = scenes.paper2016(2, "linear", nx=3, ny=2)
    path = tmp_path / "s.toml"
    dfx.save_scene(paper, path)
    before = path.read_bytes()

    def interrupted(path, text, encoding="utf-8"):
        with _atomic.atomic_open(path, "w", encoding=encoding) as fh:
            fh.write(text[: len(text) // 2])
            raise KeyboardInterrupt

    monkeypatch.setattr(_atomic, "write_text", interrupted)
    with pytest.raises(KeyboardInterrupt):
        dfx.save_scene(paper, path)
    assert path.read_bytes() == before
    assert sorted(f.name for f in tmp_path.iterdir()) == ["s.toml"]


def test_the_cli_leaves_no_partial_or_temporary_files(tmp_path):
    from deployfx import cli

    assert cli.main(["appendage", "--nx", "3", "--ny", "2", "--modes", "4",
                     "--out", str(tmp_path)]) == 0
    assert sorted(f.name for f in tmp_path.iterdir()) == ["appendage_frequencies.csv",
                                                           "appendage_modes.png"]
    rows = (tmp_path / "appendage_frequencies.csv").read_text().splitlines()
    assert rows[0] == "mode,frequency_Hz" and len(rows) == 5


# ------------------------------------------------------------------------------------------------
# Result files: integrity check

def test_a_truncated_result_file_is_an_error_naming_it(tmp_path):
    path = tmp_path / "r.npz"
    _result(n=2000).save(path)
    data = path.read_bytes()
    for cut in (10, len(data) // 3, len(data) // 2, len(data) - 30, len(data) - 1):
        bad = tmp_path / f"cut{cut}.npz"
        bad.write_bytes(data[:cut])
        with pytest.raises(ValueError, match=str(bad).replace("\\", "\\\\")):
            dfx.load(bad)


def test_an_altered_series_is_detected_by_the_checksum(tmp_path):
    """A series rewritten inside a valid archive (CRC-32 updated by zipfile) with the header and
    checksum entries copied unchanged: only the SHA-256 can tell."""
    import zipfile

    path = tmp_path / "r.npz"
    r = _result()
    r.save(path)
    altered = tmp_path / "altered.npz"
    with zipfile.ZipFile(path) as src, zipfile.ZipFile(altered, "w") as dst:
        for item in src.infolist():
            data = src.read(item)
            if item.filename == "series/x.npy":
                x = np.array(r.x)
                x[7] += 1e-12
                import io

                buf = io.BytesIO()
                np.save(buf, x)
                data = buf.getvalue()
            dst.writestr(item, data)
    with pytest.raises(ValueError, match="does not match its SHA-256"):
        dfx.load(altered)


def test_a_result_file_without_the_checksum_still_loads(tmp_path):
    """Back-compatibility: the format before the checksum (version 1, no "checksum" in the
    header, no deployfx_sha256 entry), written here as that code wrote it."""
    r = _result()
    header = json.dumps({"format": "deployfx.Result", "version": 1, "series": list(r.series),
                         "units": r.units, "metadata": r.metadata})
    path = tmp_path / "old.npz"
    with open(path, "wb") as fh:
        np.savez(fh, deployfx_header=np.array(header),
                 **{"series/" + name: r[name] for name in r.series})
    _same(dfx.load(path), r)


def test_a_result_file_announcing_a_checksum_but_missing_it_is_refused(tmp_path):
    r = _result()
    header = json.dumps({"format": "deployfx.Result", "version": 1, "series": list(r.series),
                         "units": r.units, "metadata": r.metadata, "checksum": "sha256"})
    path = tmp_path / "stripped.npz"
    with open(path, "wb") as fh:
        np.savez(fh, deployfx_header=np.array(header),
                 **{"series/" + name: r[name] for name in r.series})
    with pytest.raises(ValueError, match="deployfx_sha256 entry is missing"):
        dfx.load(path)


def test_non_result_files_are_clear_errors(tmp_path):
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a zip at all")
    with pytest.raises(ValueError, match="junk.npz"):
        dfx.load(junk)
    bare = tmp_path / "bare.npy"
    np.save(bare, np.arange(3.0))
    with pytest.raises(ValueError, match="bare .npy array"):
        dfx.load(bare)


# ------------------------------------------------------------------------------------------------
# Scene files: integrity check

@pytest.fixture(scope="module")
def paper():
    return scenes.paper2016(2, "linear", nx=3, ny=2)


def test_a_toml_scene_cut_at_a_table_boundary_is_an_error_not_a_scene_without_its_lock(
        tmp_path, paper):
    """The issue's case: the file cut just before the lock's table ([hinges.lock], here the paper
    scene's [hinges.groove]) parsed as valid TOML and loaded as the scene without its lock."""
    path = tmp_path / "s.toml"
    dfx.save_scene(paper, path)
    text = path.read_text()
    cut = tmp_path / "cut.toml"
    cut.write_text(text[: text.index("[hinges.groove]")])
    with pytest.raises(ValueError, match=r"cut\.toml is truncated or was changed"):
        dfx.load_scene(cut)
    # The same content without the check line is the old, unchecked format: it loads, and is
    # indeed a different scene (no lock) - what the check prevents.
    unchecked = tmp_path / "unchecked.toml"
    unchecked.write_text("\n".join(l for l in text[: text.index("[hinges.groove]")].splitlines()
                                   if not l.startswith("content_sha256")))
    assert "groove" not in scene_file.scene_to_dict(dfx.load_scene(unchecked))["hinges"][0]


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_a_scene_cut_mid_line_is_an_error_naming_the_file(tmp_path, paper, suffix):
    path = tmp_path / f"s{suffix}"
    dfx.save_scene(paper, path)
    text = path.read_text()
    for frac in (0.2, 0.5, 0.9):
        cut = tmp_path / f"cut{suffix}"
        cut.write_text(text[: int(len(text) * frac)] + "1")  # a line ended mid-value
        with pytest.raises(ValueError, match=f"cut\\{suffix}"):
            dfx.load_scene(cut)


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_a_scene_edited_after_saving_is_refused_until_its_check_is_removed(tmp_path, paper,
                                                                          suffix):
    path = tmp_path / f"s{suffix}"
    dfx.save_scene(paper, path)
    text = path.read_text()
    edited = text.replace("0.25", "0.3", 1)  # the lock's friction coefficient
    assert edited != text
    path.write_text(edited)
    with pytest.raises(ValueError, match="truncated or was changed"):
        dfx.load_scene(path)
    path.write_text("\n".join(l for l in edited.splitlines() if "content_sha256" not in l))
    assert scene_file.scene_to_dict(dfx.load_scene(path))["hinges"][0]["groove"]["friction"][
        "mu"] == 0.3


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_a_saved_scene_round_trips_with_its_check(tmp_path, paper, suffix):
    path = dfx.save_scene(paper, tmp_path / f"s{suffix}")
    assert "content_sha256" in path.read_text()
    assert scene_file.scene_to_dict(dfx.load_scene(path)) == scene_file.scene_to_dict(paper)
