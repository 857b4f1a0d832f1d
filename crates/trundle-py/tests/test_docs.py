"""The guide's Python examples run as printed (docs/guide/runtime.md, its Python section),
and the package's doc example says what the package does."""

import doctest
import re

import trundle
from conftest import REPO


def python_examples():
    page = (REPO / "docs" / "guide" / "runtime.md").read_text()
    section = page[page.index("## Python"):]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert blocks, "docs/guide/runtime.md has no Python example in its Python section"
    return blocks


def test_the_guides_examples_run():
    for block in python_examples():
        exec(compile(block, "docs/guide/runtime.md", "exec"), {})


def test_the_package_docstring():
    failures, tried = doctest.testmod(trundle, verbose=False)
    assert tried > 0 and failures == 0
