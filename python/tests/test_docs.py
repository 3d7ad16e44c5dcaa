"""The docs check of docs/python.md: every ```python block runs, in order, in one namespace
(as the cells of a notebook), in a folder where models/ and tests/ are the repository's."""

import contextlib
import io
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "python.md"


def blocks():
    text = PAGE.read_text()
    return [(text.count("\n", 0, m.start()) + 2, m.group(1))
            for m in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M)]


def test_the_page_has_examples():
    assert len(blocks()) >= 4


def test_every_example_runs(tmp_path, monkeypatch):
    for name in ("models", "tests"):
        (tmp_path / name).symlink_to(ROOT / name)
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs_python"}
    for line, code in blocks():
        out = io.StringIO()
        try:
            with contextlib.redirect_stdout(out):
                exec(compile(code, f"{PAGE}:{line}", "exec"), namespace)
        except Exception as error:  # name the block that failed
            pytest.fail(f"docs/python.md block at line {line} raised {error!r}\n{code}")
