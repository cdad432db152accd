#!/usr/bin/env bash
# pip install of the Python package (pyproject.toml) into a fresh virtual
# environment with the system site packages (NumPy and Matplotlib from
# Debian), offline, from a copy of the sources as a clone has them; the
# compiled module built in the existing build tree (CHATTER_CMAKE_BUILD_DIR:
# seconds, not the minutes of a fresh library build). Then, from a directory
# outside the sources: `import chatter` finds the installed package, its
# version is pyproject's, and a lobe table and a figure come out.
# With a fourth argument `fresh`, pip builds the library afresh in its own
# CMake tree instead (the path a user without a build tree takes: minutes).
# Usage: pip_install.sh SOURCE_DIR BUILD_DIR PYTHON [fresh]
set -euo pipefail
src=$(cd "$1" && pwd)
build=$(cd "$2" && pwd)
python=$3
reuse=(env CHATTER_CMAKE_BUILD_DIR="$build")
[[ ${4:-} == fresh ]] && reuse=(env -u CHATTER_CMAKE_BUILD_DIR)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

mkdir "$tmp/src"
(cd "$src" && git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$tmp/src")
"$python" -m venv --system-site-packages "$tmp/venv"
"${reuse[@]}" "$tmp/venv/bin/python" -m pip install --no-build-isolation --no-index --no-deps \
  --disable-pip-version-check --quiet "$tmp/src"

cd "$tmp"
env -u PYTHONPATH "$tmp/venv/bin/python" - "$src" <<'PY'
import pathlib
import sys
import tomllib

import chatter

src = pathlib.Path(sys.argv[1])
where = pathlib.Path(chatter.__file__).resolve()
assert "site-packages" in where.parts and str(where).startswith(sys.prefix), f"imported from {where}"
version = tomllib.loads((src / "pyproject.toml").read_text())["project"]["version"]
assert chatter.__version__ == version, (chatter.__version__, version)
lobes = chatter.lobes(chatter.load(src / "configs" / "seed_turning_1dof.toml"), rpm_points=50)
assert lobes["spindle_rpm"].shape == (50,) and lobes.info["method"] == "analytic"
png = lobes._repr_png_()
assert png is None or png.startswith(b"\x89PNG")
print(f"pip install: chatter {chatter.__version__} from {where.parent}; lobes and figure ok")
PY
