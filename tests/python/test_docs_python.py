"""The Python code blocks of docs/python.md run as written (in order, in one namespace, in a
fresh directory that holds the `run.h5` they read: `deepcontact simulate --out run.h5`)."""
import os
import re

from conftest import SOURCE, run_cli


def python_blocks():
    text = (SOURCE / "docs" / "python.md").read_text()
    return re.findall(r"^```python\n(.*?)^```", text, re.M | re.S)


def test_the_python_blocks_of_docs_python_md_run(tmp_path, monkeypatch):
    blocks = python_blocks()
    assert len(blocks) >= 2
    run_cli("simulate", "--set", "time.steps=20", "--set", "bodies.count=10", "--out", tmp_path / "run.h5")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "docs_python"}
    for i, block in enumerate(blocks):
        exec(compile(block, f"docs/python.md python block {i + 1}", "exec"), namespace)
    assert os.path.exists("p.hdf5") and os.path.exists("out.dat")
