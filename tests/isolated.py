"""Running code in a child interpreter, so that a crash (SIGSEGV, abort) or a hang fails one test
instead of killing or blocking the whole pytest run (issue 29)."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

TESTS = Path(__file__).parent


@dataclass
class Outcome:
    returncode: int  # negative: killed by that signal
    stdout: str
    stderr: str
    timed_out: bool

    @property
    def signal_name(self) -> str:
        return signal.Signals(-self.returncode).name if self.returncode < 0 else ""

    def json(self):
        """The last stdout line, parsed as JSON."""
        return json.loads(self.stdout.strip().splitlines()[-1])

    def describe(self) -> str:
        how = ("timed out" if self.timed_out else f"killed by {self.signal_name}"
               if self.returncode < 0 else f"exit {self.returncode}")
        return (f"child {how}\n--- stdout:\n{self.stdout[-3000:]}\n"
                f"--- stderr:\n{self.stderr[-3000:]}")


def run_python(code: str, timeout: float = 120.0, stdin: str | None = None) -> Outcome:
    """Run ``code`` (dedented) with this interpreter and environment; the tests directory is on
    sys.path. A child still running after ``timeout`` s is killed (timed_out)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(TESTS), env.get("PYTHONPATH")]))
    env.setdefault("PYTHONFAULTHANDLER", "1")  # a crash prints the Python stack
    try:
        p = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], input=stdin,
                           capture_output=True, text=True, timeout=timeout, env=env)
        return Outcome(p.returncode, p.stdout, p.stderr, False)
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        err = e.stderr.decode() if isinstance(e.stderr, bytes) else (e.stderr or "")
        return Outcome(-signal.SIGKILL, out, err, True)


def assert_ok(outcome: Outcome) -> Outcome:
    """The child exited normally (status 0)."""
    assert outcome.returncode == 0 and not outcome.timed_out, outcome.describe()
    return outcome
