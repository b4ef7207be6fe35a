"""The ```pycon blocks of README.md and docs/*.md, run as doctest runs them: each ``>>>`` line in
order, in one namespace per block, its printed output compared with the lines shown after it."""

from __future__ import annotations

import doctest
import os
import re

import pytest

from conftest import ROOT

DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```pycon\n(.*?)^```$", re.M | re.S)


def blocks():
    """(document, line, text) of every ```pycon block."""
    for doc in DOCUMENTS:
        text = doc.read_text()
        for match in FENCE.finditer(text):
            line = text.count("\n", 0, match.start()) + 1
            yield pytest.param(doc, line, match.group(1), id=f"{doc.relative_to(ROOT)}:{line}")


def test_the_docs_have_python_blocks():
    assert len(list(blocks())) >= 1


@pytest.mark.parametrize("doc, line, text", list(blocks()))
def test_a_python_block_prints_what_it_shows(doc, line, text, tmp_path, monkeypatch):
    # in an empty folder that sees the clone's files by the paths a reader uses
    monkeypatch.chdir(tmp_path)
    for folder in ("urdf", "tests", "assets", "examples"):
        os.symlink(ROOT / folder, tmp_path / folder)
    test = doctest.DocTestParser().get_doctest(text, {}, f"{doc.name}:{line}", str(doc), line)
    assert test.examples, "a ```pycon block without a >>> line"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    failures = []
    runner.run(test, out=failures.append)
    assert runner.failures == 0, "".join(failures)
