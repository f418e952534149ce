"""docs/api.md is the API reference generated from the public docstrings by tools/api_doc.py
(issue 25): regenerated here and compared, so it cannot drift from the code. It is what users
read, so it must not send them to the C++ sources a wheel does not ship."""
import difflib
import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def api_doc():
    spec = importlib.util.spec_from_file_location("api_doc", ROOT / "tools" / "api_doc.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_docs_api_md_is_what_the_docstrings_give():
    text = api_doc().render()
    stored = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    if text != stored:
        diff = "".join(list(difflib.unified_diff(stored.splitlines(True), text.splitlines(True),
                                                 "docs/api.md", "tools/api_doc.py"))[:40])
        raise AssertionError(f"docs/api.md is out of date: run python tools/api_doc.py\n{diff}")


def test_the_reference_covers_the_api_and_names_no_header():
    text = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    for name in ("class `deployfx.scene.Scene()`", "`deployfx.scene.Scene.compile(description=None)`",
                 "`deployfx.model.Model.simulate(", "class `deployfx.results.Result(", "`deployfx.animation.animate(",
                 "`deployfx.integrators.simulate_linear(M, C, K, q0, v0, t_end, dt"):
        assert name in text
    assert not re.findall(r"\w+\.(?:hpp|cpp)\b", text), "a user-facing docstring names a C++ source"


def test_markdown_of_numpy_sections_and_roles():
    md = api_doc().markdown
    doc = """Summary :class:`~deployfx.results.Result` and :func:`deployfx.load`.

    Parameters
    ----------
    series
        Mapping of ``name`` to array.
    k : hinge index

    Prose again."""
    assert md(doc).splitlines() == ["Summary `Result` and `deployfx.load`.", "", "**Parameters**", "",
                                    "- `series`:", "  Mapping of `name` to array.", "- `k`: hinge index", "",
                                    "Prose again."]
