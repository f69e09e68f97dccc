"""Build of the `deepcontact` Python package for `pip install --no-build-isolation .`
(docs/python.md "Install"). The extension deepcontact._core is built by CMake, like
`make build` does, in build-python/cmake (or in the CMake build tree $DEEPCONTACT_BUILD_DIR,
e.g. `build`, to reuse its objects); the package gets the pure-Python modules, the stubs, the
renderer (bench/plots/render_trajectory.py) and the shipped data under deepcontact/data/
(models/, scenes/, plot scripts), where the extension finds them (dc::data_path).

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


class CMakeBuild(build_ext):
    """Configures and builds the CMake target dc_python, then copies the module into place."""

    def build_extension(self, ext):
        build_dir = pathlib.Path(os.environ.get("DEEPCONTACT_BUILD_DIR") or pathlib.Path(self.build_temp) / "cmake")
        build_dir = build_dir if build_dir.is_absolute() else ROOT / build_dir
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
