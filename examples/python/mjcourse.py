"""The course's helper package, as the lesson programs import it: `from mjcourse import
model_path`. model_path("arm2") is the course model's file: lever's models/ folder next to this
examples/ folder, else the copy `make install` puts in <prefix>/share/lever/models, else the folder
named by LEVER_MODELS."""
import os
import pathlib


def _models_dir() -> pathlib.Path:
    candidates = []
    if os.environ.get("LEVER_MODELS"):
        candidates.append(pathlib.Path(os.environ["LEVER_MODELS"]))
    here = pathlib.Path(__file__).resolve().parent
    candidates.append(here.parent.parent / "models")              # a checkout: examples/python/
    candidates.append(here.parent.parent / "share" / "lever" / "models")  # an installed copy
    for prefix in ("/usr/local", "/usr"):
        candidates.append(pathlib.Path(prefix) / "share" / "lever" / "models")
    for c in candidates:
        if (c / "arm2.xml").is_file():
            return c
    raise FileNotFoundError("lever's models not found; set LEVER_MODELS to the models folder")


def model_path(name: str) -> pathlib.Path:
    """The path of one of the course's models, e.g. model_path("arm2")."""
    path = _models_dir() / f"{name}.xml"
    if not path.is_file():
        raise FileNotFoundError(f"no course model called '{name}' ({path})")
    return path
