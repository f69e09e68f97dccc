"""The Python reference is complete: every public name has a docstring, the type stubs
(python/deepcontact/__init__.pyi) and the reference table of docs/python.md are those
scripts/generate-python-stubs.py generates from the built module, and `__version__` names the
commit the module was built from."""
import re
import subprocess
import sys

from conftest import SOURCE

SCRIPT = SOURCE / "scripts" / "generate-python-stubs.py"


def test_every_public_name_has_a_docstring_a_stub_and_a_reference_line():
    p = subprocess.run([sys.executable, str(SCRIPT), "--check"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr


def test_the_stub_declares_every_public_name(dc):
    stub = (SOURCE / "python" / "deepcontact" / "__init__.pyi").read_text()
    for name in dc.__all__:
        assert re.search(rf"^(class|def) {re.escape(name)}\b", stub, re.M), f"{name} has no stub"
    doc = (SOURCE / "docs" / "python.md").read_text()
    for name in dc.__all__:
        assert f"`{name}`" in doc, f"docs/python.md does not list {name}"


def test_version_carries_the_commit(dc):
    assert re.fullmatch(r"\d+\.\d+\.\d+\+(g[0-9a-f]{12}(\.dirty)?|unknown)", dc.__version__), dc.__version__
    commit = dc.__commit__
    if commit != "unknown":
        assert dc.__version__.endswith("+g" + commit.replace("-", "."))
    head = subprocess.run(["git", "-C", str(SOURCE), "rev-parse", "--short=12", "HEAD"], capture_output=True, text=True)
    if head.returncode == 0 and commit != "unknown":
        # Built from this checkout (ctest): the module's commit is the work tree's HEAD.
        assert commit.split("-")[0] == head.stdout.strip()
