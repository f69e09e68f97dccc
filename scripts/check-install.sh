#!/usr/bin/env bash
# The installs a new user makes, each checked from this checkout (docs/install.md):
#   1. pip: a clean venv (--system-site-packages, to see Debian's numpy, scipy, h5py, matplotlib),
#      `pip install --no-build-isolation .`, then `import deepcontact`, its __version__ carrying
#      HEAD's commit, and every example in examples/*.py run with the venv's Python, from a
#      directory outside the checkout (the package's own data, not the source tree's).
#   2. CMake: `cmake --install BUILD --prefix P`, P moved elsewhere, then `P/bin/deepcontact
#      --version` and `bench --quick` run from an unrelated directory.
#   3. A C++ consumer: examples/cpp (find_package(DeepContact), a custom solver variant solving a
#      contact LCP) configured against the moved prefix, built and run.
# Usage: scripts/check-install.sh [BUILD]   (BUILD: a configured and built tree, default build;
# the pip build reuses it through DEEPCONTACT_BUILD_DIR, so only the module is relinked)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
BUILD=$(realpath "${1:-build}")
WORK=$(mktemp -d /tmp/dc-install-check.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
HEAD=$(git rev-parse --short=12 HEAD)
step() { printf '\n== %s\n' "$*"; }

step "pip install --no-build-isolation . into a clean venv"
/usr/bin/python3 -m venv --system-site-packages "$WORK/venv"
DEEPCONTACT_BUILD_DIR="$BUILD" JOBS=${JOBS:-2} "$WORK/venv/bin/pip" install --no-build-isolation -q "$ROOT"
mkdir "$WORK/elsewhere"
cd "$WORK/elsewhere"
"$WORK/venv/bin/python" - "$HEAD" <<'PY'
import sys
import deepcontact
head = sys.argv[1]
print("deepcontact", deepcontact.__version__, "from", deepcontact.__file__)
assert "site-packages" in deepcontact.__file__, deepcontact.__file__
assert deepcontact.__version__.split("+g")[1].startswith(head), (deepcontact.__version__, head)
w = deepcontact.World(set={"bodies.count": 10})
w.step(warmstart="cnn")  # the shipped model, found in the installed package's data
assert w.render().shape[2] == 3
PY
for ex in "$ROOT"/examples/*.py; do
  args=()
  case $(basename "$ex") in
    read_trajectory.py)
      "$BUILD/bin/deepcontact" simulate --scene "$ROOT/scenes/mixed.toml" --steps 40 --out run.h5 >/dev/null
      args=(run.h5) ;;
  esac
  echo "-- $(basename "$ex") ${args[*]:-}"
  "$WORK/venv/bin/python" "$ex" "${args[@]}" | tail -n 3
done

step "cmake --install into a prefix, the prefix moved, bench --quick from elsewhere"
cmake --install "$BUILD" --prefix "$WORK/prefix" >/dev/null
mv "$WORK/prefix" "$WORK/moved"
cd "$WORK/elsewhere"
"$WORK/moved/bin/deepcontact" --version | grep -q "commit $HEAD" || { echo "--version lacks the commit $HEAD" >&2; exit 1; }
"$WORK/moved/bin/deepcontact" --version
"$WORK/moved/bin/deepcontact" bench --quick --out quick > quick.log
tail -n 3 quick.log
test -s quick/summary.json && test -s quick/report.md

step "a C++ consumer: find_package(DeepContact), a custom solver variant"
cmake -S "$ROOT/examples/cpp" -B "$WORK/consumer" -DCMAKE_PREFIX_PATH="$WORK/moved" >/dev/null
cmake --build "$WORK/consumer" -j "${JOBS:-2}" >/dev/null
"$WORK/consumer/custom_solver"
"$WORK/consumer/solve_problem_file" "$ROOT/tests/data/fc2d/FrictionContactProblem00031.dat"
echo
echo "check-install: pip, CMake install (moved prefix) and the C++ consumer work"
