"""The package under test is the wheel pip installed into this virtual environment (make test's
python.wheel), with its `lever` console script, and numpy and mujoco from pip."""
import pathlib
import subprocess
import sys

import numpy
import pytest

import lever


def test_lever_is_the_installed_wheel_not_the_build_tree():
    package = pathlib.Path(lever.__file__).resolve()
    assert package.is_relative_to(pathlib.Path(sys.prefix).resolve()), package
    assert "site-packages" in package.parts
    assert list(package.parent.glob("_lever*.so"))


def test_numpy_comes_from_pip_not_debian():
    assert "dist-packages" not in pathlib.Path(numpy.__file__).parts


def test_console_script_runs_the_command():
    script = pathlib.Path(sys.prefix) / "bin" / "lever"
    if not script.is_file():
        pytest.skip("not an installed package (no console script in this environment)")
    out = subprocess.run([str(script), "--help"], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and "Usage: lever" in out.stdout
    bad = subprocess.run([str(script), "check", "no-such-file.xml"], capture_output=True, text=True,
                         timeout=60)
    assert bad.returncode != 0 and "no-such-file.xml" in bad.stderr + bad.stdout
