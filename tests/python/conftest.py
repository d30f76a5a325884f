"""Shared fixtures of the Python tests: where the repository, the models, the lever command and
the lesson are. ctest runs pytest here with PYTHONPATH set to the built package (tests/python's
CMakeLists.txt); LEVER_CLI names the C++ command the package is compared with."""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
MODEL_FILES = sorted([*REPO.glob("models/*.xml"), *REPO.glob("tests/models/*.xml")])


@pytest.fixture(scope="session")
def lever_cli() -> str:
    path = os.environ.get("LEVER_CLI", "")
    if not path or not pathlib.Path(path).is_file():
        pytest.fail("LEVER_CLI must name the built lever command (ctest sets it)")
    return path


def lesson_text() -> str:
    """Lesson 5.1 as the course ships it (shared/seed beside the repository), or ''."""
    seed = REPO.parent / "shared" / "seed"
    for path in sorted(seed.glob("*.txt")) if seed.is_dir() else []:
        text = path.read_text(encoding="utf-8")
        if "def joint_stop(model, data)" in text and "Output:" in text:
            return text
    return ""
