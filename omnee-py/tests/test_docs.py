"""The examples in the documentation run: the package docstring's doctest,
the python blocks of omnee-py/README.md (the wheel's description) and of
the repository's README (those that import Mitsuba run in the Mitsuba
suite, omnee-py/tests-mitsuba/test_docs.py)."""

import doctest
import re

import pytest

import omnee
from conftest import REPO


def test_package_docstring_examples():
    result = doctest.testmod(omnee)
    assert result.attempted > 0 and result.failed == 0


@pytest.mark.parametrize("readme", ["omnee-py/README.md", "README.md"])
def test_readme_python_examples(readme):
    text = (REPO / readme).read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S)
              if "import mitsuba" not in b]
    assert blocks, f"{readme} has no python block"
    for block in blocks:
        exec(compile(block, readme, "exec"), {})


def test_the_wheel_readme_links_nothing_outside_the_package():
    """The README is the wheel's description: a relative link out of
    omnee-py/ (such as ../README.md) is broken there."""
    text = (REPO / "omnee-py" / "README.md").read_text(encoding="utf-8")
    assert not re.findall(r"\]\((?!https?://)[^)]*\)", text)
