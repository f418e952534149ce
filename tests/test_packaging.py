"""What a wheel carries (issue 25): the MIT license that pyproject.toml declares, and py.typed (PEP
561: the package's annotations are for type checkers). The wheel is built in process by
scikit-build-core with ``wheel.cmake=false`` (the package files and metadata, no compile)."""
import re
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_license_file_is_the_mit_license_pyproject_declares():
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["license"] == {"text": "MIT"}
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License\n") and "Permission is hereby granted, free of charge" in text
    assert (ROOT / "python" / "deployfx" / "py.typed").exists()


def test_the_wheel_carries_py_typed_and_the_license(tmp_path, monkeypatch):
    build = pytest.importorskip("scikit_build_core.build")
    monkeypatch.chdir(ROOT)
    name = build.build_wheel(str(tmp_path), {"wheel.cmake": "false"})
    with zipfile.ZipFile(tmp_path / name) as whl:
        files = set(whl.namelist())
        metadata = whl.read(next(f for f in files if f.endswith(".dist-info/METADATA"))).decode()
    assert "deployfx/py.typed" in files
    assert any(re.fullmatch(r"deployfx-[^/]+\.dist-info/licenses/LICENSE", f) for f in files)
    assert "License: MIT" in metadata
    sources = {f"deployfx/{p.name}" for p in (ROOT / "python" / "deployfx").glob("*.py")}
    assert sources <= files


def test_build_requirements_file_lists_the_build_system_requires():
    # The README installs these, then builds without isolation so that its second command reuses
    # the first one's build (scikit-build-core clears the build directory for every new isolated
    # environment); CMake as CMakeLists.txt's cmake_minimum_required, and Ninja.
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    requires = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["build-system"]["requires"]
    lines = [line.strip() for line in (ROOT / "requirements-build.txt").read_text(encoding="utf-8").splitlines()]
    listed = [line for line in lines if line and not line.startswith("#")]
    minimum = re.search(r"cmake_minimum_required\(VERSION ([\d.]+)\)", (ROOT / "CMakeLists.txt").read_text()).group(1)
    assert listed == requires + [f"cmake>={minimum}", "ninja"]
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    for marker in ("<!-- ci:main -->", "<!-- ci:test -->"):
        block = readme.split(marker, 1)[1].split("```")[1]
        assert "pip install -r requirements-build.txt && pip install --no-build-isolation" in block
