"""The `lever` console script of the pip-installed package: runs the C++ `lever` command the wheel
carries in lever/bin, with the same arguments, as that process (its exit status is the command's)."""
import os
import pathlib
import sys


def main() -> None:
    command = pathlib.Path(__file__).resolve().parent / "bin" / "lever"
    if not command.is_file():
        sys.exit(f"lever: the command is not in this installation ({command}); "
                 "install the package with `pip install .` from lever's repository")
    os.execv(command, [str(command), *sys.argv[1:]])
