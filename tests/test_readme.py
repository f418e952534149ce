"""Every Python block of the README runs as written (issue 25): a newcomer copies them. Each block
runs on its own, in a fresh namespace, in a temporary directory (the files it writes go there).
The reference is the README itself: a block that raises fails the test, naming its first line.
"""
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parent.parent / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)


def test_the_readme_has_python_blocks():
    assert len(BLOCKS) >= 4


@pytest.mark.parametrize("code", BLOCKS, ids=[f"block{k}" for k in range(len(BLOCKS))])
def test_readme_block_runs(code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(code, f"README block: {code.splitlines()[0]}", "exec"), {"__name__": "readme"})
