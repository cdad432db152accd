#!/usr/bin/env bash
# Installs the Debian packages chatter needs, only those missing.
# Idempotent and quiet when everything is present. Needs root (or sudo) for apt.
set -euo pipefail

packages=(
  cmake make g++ pkg-config
  libeigen3-dev libsundials-dev libboost-program-options-dev
  libboost-dev  # Boost.Math headers (brent_find_minima), header-only
  libgnuplot-iostream-dev gnuplot-nox libtomlplusplus-dev nlohmann-json3-dev
  # gnuplot-iostream (the CLI's --show windows) needs Boost.Iostreams and
  # Boost.Filesystem; a window needs a gnuplot with a window terminal:
  # gnuplot-qt instead of gnuplot-nox on a desktop (docs/plots.md).
  libboost-iostreams-dev libboost-filesystem-dev
  googletest libgtest-dev libbenchmark-dev
  libsndfile1-dev  # audio recordings (WAV/FLAC/AIFF) for `chatter detect`
  pybind11-dev python3-dev python3-numpy  # the Python module (docs/python.md)
  python3-pytest  # its tests (tests/python, run by ctest)
  # The Python package's figures (result.plot(), notebooks' rich display) and
  # the ctests that run the notebook headless and pip-install the package
  # into a fresh venv (docs/python.md): Matplotlib, nbconvert with its
  # kernel, setuptools (pyproject.toml's build backend) and venv.
  python3-matplotlib jupyter-nbconvert python3-ipykernel python3-setuptools python3-venv
  # `chatter program` reads G-code with LinuxCNC's RS274/NGC interpreter
  # (/usr/bin/rs274; docs/program.md). --no-install-recommends (below) keeps
  # out the real-time kernel image and GUI stacks it would recommend.
  linuxcnc-uspace
  openmpi-bin libopenmpi-dev  # chatter-mpi, the sweeps across processes (docs/scaling.md); ctest runs it under mpirun
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "setup: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "setup: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
