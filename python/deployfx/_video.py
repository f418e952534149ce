"""The ffmpeg that MP4 animations run: the system's (matplotlib's ``animation.ffmpeg_path``,
``ffmpeg`` on PATH by default) or else the static binary of the imageio-ffmpeg wheel
(``pip install "deployfx[video]"``; in the test extras, so MP4 output is exercised)."""
from __future__ import annotations

import shutil


def ffmpeg_path() -> str:
    """The ffmpeg executable to write an MP4 with; RuntimeError saying how to get one if none."""
    import matplotlib

    found = shutil.which(str(matplotlib.rcParams["animation.ffmpeg_path"]))
    if found:
        return found
    try:
        import imageio_ffmpeg

        return imageio_ffmpeg.get_ffmpeg_exe()  # raises RuntimeError if its binary is missing
    except (ImportError, RuntimeError):
        raise RuntimeError("writing .mp4 needs ffmpeg, which was not found: pip install "
                           "\"deployfx[video]\" (the imageio-ffmpeg wheel), or install it (Debian: "
                           "apt-get install ffmpeg), or write a .gif") from None
