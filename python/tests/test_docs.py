"""Every `python` block of docs/python.md that starts with `# example:` runs (from the source
folder, as the page says) and exits 0; the examples assert their own results."""
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAGE = os.path.join(ROOT, "docs", "python.md")


def examples():
    text = open(PAGE).read()
    blocks = re.findall(r"```python\n(# example: (\w+)\n.*?)```", text, re.S)
    return [(name, code) for code, name in blocks]


def test_the_page_has_its_examples():
    assert [n for n, _ in examples()] == ["quickstart", "controller", "sweep"]


@pytest.mark.parametrize("name,code", examples(), ids=[n for n, _ in examples()])
def test_example_runs(name, code):
    if "import pandas" in code:
        pytest.importorskip("pandas")
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                       timeout=300)
    print(r.stdout)
    assert r.returncode == 0, r.stderr
