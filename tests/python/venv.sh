#!/usr/bin/env bash
# The virtual environments of the Python tests (tests/python/CMakeLists.txt runs this).
#
#   venv.sh tools BUILD         at configure time: BUILD/venv, Debian's python3 with the pinned
#                               packages of requirements.txt from pip (numpy, mujoco, pytest,
#                               scikit-build-core), made once (again when requirements.txt changes)
#   venv.sh wheel BUILD SOURCE  at test time: the wheel of lever that BUILD compiled
#                               (pyproject.toml, python/prebuilt.cmake), then BUILD/venv-test, a
#                               fresh venv into which pip installs that wheel; the test venv
#                               reaches numpy, mujoco and pytest in BUILD/venv through a .pth
#                               file (installing them afresh each run cost 20-30 s)
#   venv.sh ray BUILD           make test-ray: BUILD/venv-ray, a venv with pip's ray
#                               (requirements-ray.txt, made once) and the wheel `venv.sh wheel`
#                               built, reaching numpy and pytest in BUILD/venv as venv-test does
set -euo pipefail
what=$1 build=$(realpath "$2")
here=$(cd "$(dirname "$0")" && pwd)
python=/usr/bin/python3
quiet=(--quiet --disable-pip-version-check --no-input)

case $what in
  tools)
    stamp=$build/venv/requirements.txt
    if [ -x "$build/venv/bin/python" ] && cmp -s "$here/requirements.txt" "$stamp"; then exit 0; fi
    rm -rf "$build/venv"
    "$python" -m venv "$build/venv"
    "$build/venv/bin/pip" install "${quiet[@]}" --only-binary=:all: -r "$here/requirements.txt"
    cp "$here/requirements.txt" "$stamp"
    ;;
  wheel)
    source=$(realpath "$3")
    rm -rf "$build/python-wheel" "$build/venv-test"
    # --no-build-isolation: the backend from the tools venv; the wheel packs BUILD's module and
    # command (LEVER_PYTHON_PREBUILT), so nothing is compiled here
    "$build/venv/bin/pip" wheel "${quiet[@]}" --no-deps --no-build-isolation \
      -w "$build/python-wheel" \
      --config-settings=build-dir="$build/python-wheel/build" \
      --config-settings=cmake.define.LEVER_PYTHON_PREBUILT="$build" "$source"
    "$python" -m venv --without-pip "$build/venv-test"
    tools_site=$("$build/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
    test_site=$("$build/venv-test/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
    echo "$tools_site" > "$test_site/lever-test-dependencies.pth"
    "$build/venv/bin/pip" --python "$build/venv-test/bin/python" install "${quiet[@]}" --no-index \
      "$build"/python-wheel/lever-*.whl
    ;;
  ray)
    stamp=$build/venv-ray/requirements-ray.txt
    if ! { [ -x "$build/venv-ray/bin/python" ] && cmp -s "$here/requirements-ray.txt" "$stamp"; }; then
      rm -rf "$build/venv-ray"
      "$python" -m venv "$build/venv-ray"
      tools_site=$("$build/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
      ray_site=$("$build/venv-ray/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
      echo "$tools_site" > "$ray_site/lever-test-dependencies.pth"
      "$build/venv-ray/bin/pip" install "${quiet[@]}" --only-binary=:all: -r "$here/requirements-ray.txt"
      cp "$here/requirements-ray.txt" "$stamp"
    fi
    "$build/venv-ray/bin/pip" install "${quiet[@]}" --no-index --no-deps --force-reinstall \
      "$build"/python-wheel/lever-*.whl
    ;;
  *) echo "venv.sh: tools BUILD | wheel BUILD SOURCE | ray BUILD" >&2; exit 2 ;;
esac
