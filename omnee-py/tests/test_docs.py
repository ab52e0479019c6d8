"""The examples in the documentation run: the package docstring's doctest and
the README's "Use from Python" block."""

import doctest
import re

import omnee
from conftest import REPO


def test_package_docstring_examples():
    result = doctest.testmod(omnee)
    assert result.attempted > 0 and result.failed == 0


def test_readme_python_example():
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", readme, flags=re.S)
    assert blocks, "README.md has no python block"
    for block in blocks:
        exec(compile(block, "README.md", "exec"), {})
