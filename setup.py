"""Build of the `deepcontact` Python package for `pip install --no-build-isolation .`
(docs/install.md). The extension deepcontact._core is built by CMake, like `make build` does:
in the CMake build tree `build/` when it exists (only the module is built or relinked there,
sharing the objects of `make build`/`make test`), else in build-python/cmake; the environment
variable DEEPCONTACT_BUILD_DIR names another tree. The package gets the pure-Python modules, the
stubs, the renderer (bench/plots/render_trajectory.py) and the shipped data under
deepcontact/data/ (models/, scenes/, plot scripts), where the extension finds them
(dc::data_path).

The module is built for Debian's /usr/bin/python3 (python3-pybind11, python3-numpy): the Python
that runs pip must be that one or a venv made from it with --system-site-packages, and have
wheel and numpy; otherwise the build stops at once with one message saying so.

The version is the project's with the git commit as local label (0.1.0+g1a2b3c4d5e6f), the
same string as deepcontact.__version__.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent
# The data root keeps the source tree's relative paths (core/include/dc/core/install_paths.hpp).
# research/plots is not among them: the module does not link dc_research (docs/python.md).
DATA = ["models", "scenes", "bench/plots", "python/deepcontact/trajectory.py"]


def project_version():
    text = (ROOT / "CMakeLists.txt").read_text()
    version = re.search(r"project\(DeepContact VERSION ([0-9.]+)", text).group(1)
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short=12", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
        return f"{version}+g{commit}" + (".dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return f"{version}+unknown"


DEBIAN_PYTHON = "/usr/bin/python3"


def check_python():
    """Stop with one message when this Python cannot build or use the module."""
    problems = []
    for module, package in (("wheel", "python3-wheel"), ("numpy", "python3-numpy")):
        try:
            __import__(module)
        except ImportError:
            problems.append(f"no module {module} (Debian: {package})")
    try:
        debian = subprocess.run([DEBIAN_PYTHON, "-c", "import sys; print(sys.version_info[:2])"], capture_output=True,
                                text=True, check=True).stdout.strip()
        if debian != str(sys.version_info[:2]):
            problems.append(f"Python {sys.version_info[0]}.{sys.version_info[1]}, but the module is built for "
                            f"{DEBIAN_PYTHON}, Python {debian.strip('()').replace(', ', '.')}")
    except (OSError, subprocess.CalledProcessError):
        problems.append(f"{DEBIAN_PYTHON} not found (Debian's python3, which the module is built for)")
    if problems:
        sys.exit(f"deepcontact: cannot build with {sys.executable}: " + "; ".join(problems) + ". Use "
                 f"{DEBIAN_PYTHON} or a venv made from it that sees Debian's packages: {DEBIAN_PYTHON} -m venv "
                 "--system-site-packages venv && venv/bin/pip install --no-build-isolation . "
                 "(scripts/install-deps.sh installs python3-wheel and python3-numpy; docs/install.md)")


def cmake_cache(build_dir):
    """The CMakeCache.txt entries NAME:TYPE=VALUE of build_dir as {NAME: VALUE} ({} without one)."""
    path = build_dir / "CMakeCache.txt"
    if not path.exists():
        return {}
    out = {}
    for line in path.read_text(errors="replace").splitlines():
        m = re.match(r"^([A-Za-z_0-9]+):\w+=(.*)$", line)
        if m:
            out[m.group(1)] = m.group(2)
    return out


def reusable(build_dir):
    """True when build_dir is a CMake tree of this source that builds the module."""
    cache = cmake_cache(build_dir)
    return (bool(cache) and pathlib.Path(cache.get("CMAKE_HOME_DIRECTORY", "")).resolve() == ROOT
            and cache.get("DC_PYTHON", "ON").upper() not in ("OFF", "0", "FALSE", "NO")
            and cache.get("DC_SANITIZE", "OFF").upper() in ("OFF", "0", "FALSE", "NO")
            and cache.get("DC_FUZZ", "OFF").upper() in ("OFF", "0", "FALSE", "NO"))


class CMakeBuild(build_ext):
    """Configures and builds the CMake target dc_python, then copies the module into place."""

    def build_extension(self, ext):
        if os.environ.get("DEEPCONTACT_BUILD_DIR"):
            build_dir = pathlib.Path(os.environ["DEEPCONTACT_BUILD_DIR"])
            build_dir = build_dir if build_dir.is_absolute() else ROOT / build_dir
        elif reusable(ROOT / "build"):  # the tree of `make build` / `make test`
            build_dir = ROOT / "build"
        else:
            build_dir = pathlib.Path(self.build_temp) / "cmake"
            build_dir = build_dir if build_dir.is_absolute() else ROOT / build_dir
        print(f"deepcontact: building the module in {build_dir}", flush=True)
        if not (build_dir / "CMakeCache.txt").exists():
            subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                            "-DDC_TESTS=OFF", "-DDC_BENCHMARKS=OFF"], check=True)
        jobs = os.environ.get("JOBS") or str(os.cpu_count() or 2)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "dc_python", "-j", jobs], check=True)
        built = sorted((build_dir / "python" / "deepcontact").glob("_core*.so"))
        if not built:
            raise RuntimeError(f"the CMake build in {build_dir} made no deepcontact/_core*.so")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[-1], target)


class BuildPy(build_py):
    """The package plus the renderer and the data root deepcontact/data/."""

    def run(self):
        super().run()
        package = pathlib.Path(self.build_lib) / "deepcontact"
        shutil.copyfile(ROOT / "bench" / "plots" / "render_trajectory.py", package / "render_trajectory.py")
        data = package / "data"
        for rel in DATA:
            src, dst = ROOT / rel, data / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            if src.is_dir():
                shutil.copytree(src, dst, dirs_exist_ok=True, ignore=shutil.ignore_patterns("__pycache__"))
            else:
                shutil.copyfile(src, dst)


# Not for `setup.py --version` and other queries that build nothing.
if any(arg.startswith(("bdist", "build", "install", "develop", "editable_wheel", "dist_info", "egg_info"))
       for arg in sys.argv[1:]):
    check_python()

setup(
    version=project_version(),
    packages=["deepcontact"],
    package_dir={"deepcontact": "python/deepcontact"},
    package_data={"deepcontact": ["*.pyi", "py.typed"]},
    ext_modules=[Extension("deepcontact._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild, "build_py": BuildPy},
    # setuptools' own build/ would mix with the CMake build tree of `make build`.
    options={"build": {"build_base": "build-python"}},
    zip_safe=False,
)
