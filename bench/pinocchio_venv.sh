#!/usr/bin/env bash
# The Pinocchio peer's virtual environment (bench/CMakeLists.txt runs this at configure time).
#
#   pinocchio_venv.sh BUILD   BUILD/venv-pinocchio: Debian's python3 with pip's pin (pinned by
#                             bench/requirements.txt), made once (again when the file changes);
#                             prints the prefix that holds Pinocchio's C++ headers, libraries and
#                             CMake config (site-packages/cmeel.prefix)
set -euo pipefail
build=$(realpath "$1")
here=$(cd "$(dirname "$0")" && pwd)
venv=$build/venv-pinocchio
stamp=$venv/requirements.txt
if ! { [ -x "$venv/bin/python" ] && cmp -s "$here/requirements.txt" "$stamp"; }; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv "$venv" >&2
  "$venv/bin/pip" install --quiet --disable-pip-version-check --no-input --only-binary=:all: \
    -r "$here/requirements.txt" >&2
  cp "$here/requirements.txt" "$stamp"
fi
site=$("$venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
echo "$site/cmeel.prefix"
