"""Shared fixtures: the bundled fandisk mesh (a real scan-like CAD model with sharp creases)."""
import pathlib

import pytest

import fq

DATA = pathlib.Path(__file__).resolve().parents[2] / "data"


@pytest.fixture(scope="session")
def fandisk():
    """(V, F) of data/fandisk.ply."""
    return fq.read_mesh(DATA / "fandisk.ply")
