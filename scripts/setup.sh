#!/usr/bin/env bash
# Install the Debian packages lever needs, only those that are missing.
# Idempotent: prints nothing and changes nothing when everything is present.
set -euo pipefail

packages=(
  build-essential cmake
  libeigen3-dev        # engine (header-only linear algebra)
  libtinyxml2-dev      # mjcf_lite
  libccd-dev           # tests: libccd's MPR beside lever's (the libccd MuJoCo 2.2.2 runs, in double)
  libqhull-dev         # mjcf_lite: a mesh's convex hull for collision (libqhull_r, as MuJoCo 2.2.2)
  nlohmann-json3-dev   # io: the JSON writer's formatting (header-only; the WebAssembly build too)
  libcli11-dev         # tools/lever: the command line (subcommands, --help, errors; header-only)
  catch2               # tests (Catch2 2.13)
  libmujoco-dev        # the reference: tests, benchmarks and `lever diff` only
  libbenchmark-dev     # bench/
  liborocos-kdl-dev    # bench/ peer
  python3-dev python3-pybind11  # the Python package (python/), for /usr/bin/python3
  python3-numpy                  # tests/packaging: the installed package under Debian's python3
  python3-venv python3-pip       # tests/python: the wheel tested in a fresh venv, numpy, pytest
                                 # and MuJoCo's own package from pip (tests/python/requirements.txt)
  emscripten           # make web, tests/web: lever compiled to WebAssembly for the lab (web/)
  node-acorn           # Emscripten's JS optimizer (NODE_PATH=/usr/share/nodejs)
  chromium             # tests/web: the lab in a real browser, headless
  chromium-driver      # tests/web: chromedriver, which selenium drives chromium through
  python3-selenium     # tests/web: the browser tests (Debian's /usr/bin/python3)
  libjs-three          # the lab's 3D view (three.js r111), served with the page by web/serve.py
  libjs-katex          # the knowledge check's math (KaTeX), served with the page by web/serve.py
)

# `scripts/setup.sh fuzz`: also what `make fuzz` needs (clang and its libFuzzer runtime)
# `scripts/setup.sh lint`: what `make lint` and `make format-check` need
# `scripts/setup.sh bench`: what `make bench` needs besides the above (valgrind's callgrind)
# `scripts/setup.sh web-bench`: npm, which installs make web-bench's pinned peer (mujoco-js)
if [ "${1:-}" = "fuzz" ]; then
  packages+=(clang-14 libclang-rt-14-dev)
fi
if [ "${1:-}" = "lint" ]; then
  packages+=(clang-tidy-14 clang-format-14 cppcheck)
fi
if [ "${1:-}" = "bench" ]; then
  packages+=(valgrind)  # callgrind counts every benchmarked operation's instructions per call
fi
if [ "${1:-}" = "web-bench" ] && ! command -v npm >/dev/null 2>&1; then
  packages+=(npm)  # installs npm mujoco-js (MuJoCo's official wasm build), make web-bench's peer
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

[ ${#missing[@]} -eq 0 ] && exit 0

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null 2>&1 || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
