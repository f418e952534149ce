"""Atomic file writes: the target is either its previous content or the complete new one, never a
partial file, whatever stops the writer (an exception, SIGKILL, a full disk, a power cut).

The new content goes to a temporary file in the target's directory (same file system, so the
rename is atomic), is flushed and fsync'ed, then renamed over the target with ``os.replace``; the
directory is fsync'ed so that the rename itself survives a crash (POSIX rename(2); the pattern of
SQLite's and git's lock files). On any failure the temporary file is removed and the target is
left as it was.
"""
from __future__ import annotations

import contextlib
import os
import secrets
import stat
from pathlib import Path
from typing import IO, Iterator, Union

PathLike = Union[str, os.PathLike]


def _fsync_dir(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # a platform or file system without directory handles
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _temporary(target: Path) -> tuple[int, Path]:
    """A new file beside ``target``, created exclusively with the mode a plain open() would give
    (0o666 less the umask), as (descriptor, path); the suffix is kept so that writers that go by
    it (matplotlib, ffmpeg) still choose the right format."""
    for _ in range(100):
        tmp = target.with_name(f".{target.stem}.{secrets.token_hex(6)}.tmp{target.suffix}")
        try:
            return os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666), tmp
        except FileExistsError:
            continue
    raise FileExistsError(f"could not create a temporary file beside {target}")


def _finish(tmp: Path, target: Path) -> None:
    """fsync ``tmp``, give it the mode of the file it replaces, rename it over ``target``."""
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    with contextlib.suppress(FileNotFoundError):
        os.chmod(tmp, stat.S_IMODE(os.stat(target).st_mode))
    os.replace(tmp, target)
    _fsync_dir(target.parent)


def replace(tmp: PathLike, path: PathLike) -> None:
    """Move the finished file ``tmp`` (on the file system of ``path``) over ``path``: fsync,
    rename, fsync of the directory."""
    _finish(Path(tmp), _target(path))


def _target(path: PathLike) -> Path:
    # A symbolic link is followed: its target file is replaced, the link is kept.
    return Path(os.path.realpath(path)) if os.path.islink(path) else Path(path)


@contextlib.contextmanager
def atomic_path(path: PathLike) -> Iterator[Path]:
    """A temporary path to write the new content of ``path`` to (by any writer that takes a path);
    on a normal exit it replaces ``path`` atomically, on an exception it is removed."""
    target = _target(path)
    fd, tmp = _temporary(target)
    os.close(fd)
    try:
        yield tmp
        _finish(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


@contextlib.contextmanager
def atomic_open(path: PathLike, mode: str = "w", **kwargs) -> Iterator[IO]:
    """``open(path, mode, **kwargs)`` for writing (``"w"``, ``"wb"``, ``"wt"``), atomically."""
    if mode not in ("w", "wt", "wb"):
        raise ValueError(f"atomic_open: mode = {mode!r} must be 'w', 'wt' or 'wb'")
    target = _target(path)
    fd, tmp = _temporary(target)
    try:
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
        _finish(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def write_text(path: PathLike, text: str, encoding: str = "utf-8") -> None:
    """``Path(path).write_text(text, encoding)``, atomically."""
    with atomic_open(path, "w", encoding=encoding, newline="") as fh:
        fh.write(text)


def write_bytes(path: PathLike, data: bytes) -> None:
    """``Path(path).write_bytes(data)``, atomically."""
    with atomic_open(path, "wb") as fh:
        fh.write(data)
