"""The documentation's Mitsuba examples run: every python block that
imports Mitsuba in the README, docs/mitsuba.md and examples/mitsuba's
README, in a scratch folder where the files they name (``scene.xml``,
``examples/mitsuba/fog.xml``) are the example's fog scene at 16 × 16
pixels."""

import os
import re

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
FOG = os.path.join(REPO, "examples", "mitsuba", "fog.xml")
DOCS = ["README.md", "docs/mitsuba.md", "examples/mitsuba/README.md"]


def blocks(doc):
    with open(os.path.join(REPO, doc), encoding="utf-8") as f:
        text = f.read()
    return [b for b in re.findall(r"```python\n(.*?)```", text, flags=re.S) if "import mitsuba" in b]


@pytest.mark.parametrize("doc", DOCS)
def test_mitsuba_examples_in_the_docs_run(mi, doc, tmp_path, monkeypatch):
    import omnee.mitsuba

    found = blocks(doc)
    assert found, f"{doc} has no python block that imports Mitsuba"
    with open(FOG, encoding="utf-8") as f:
        small = re.sub(r'(<default name="res" value=")\d+', r"\g<1>16", f.read())
    assert 'value="16"' in small
    (tmp_path / "examples" / "mitsuba").mkdir(parents=True)
    for name in ("scene.xml", os.path.join("examples", "mitsuba", "fog.xml")):
        (tmp_path / name).write_text(small, encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    current = mi.variant()
    try:
        for block in found:
            exec(compile(block, doc, "exec"), {})
    finally:
        mi.set_variant(current)
        omnee.mitsuba.register()
