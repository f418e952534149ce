"""The machine a bench ran on, in one line every bench script prints next to its timings.

Sessions run on different machines (session 30's AMD EPYC ran the same build 1.5-1.8 times slower
than session 29's machine): absolute times compare only between runs on one CPU, ratios within a
run anywhere. The line names what the core was compiled for (``_core.simd``) and the CPU it ran on.
"""
from __future__ import annotations

import os
import platform

from deployfx import _core


def cpu() -> str:
    """The CPU's model name, with its family and model numbers where /proc/cpuinfo gives them
    (a virtual machine's name may be only the vendor's: "AMD EPYC")."""
    fields: dict[str, str] = {}
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if not line.strip():
                    break  # the first processor's block is enough
                key, _, value = line.partition(":")
                fields.setdefault(key.strip(), value.strip())
    except OSError:
        pass
    name = fields.get("model name") or platform.processor() or platform.machine() or "unknown CPU"
    if "cpu family" in fields and "model" in fields:
        name += f" (family {fields['cpu family']}, model {fields['model']})"
    return name


def describe() -> str:
    """``core built for <instruction sets>; <cpu>, <n> logical cores``."""
    return f"core built for {_core.simd}; {cpu()}, {os.cpu_count()} logical cores"


if __name__ == "__main__":
    print(describe())
