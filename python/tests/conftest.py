"""Shared fixtures: the repository, its build folder, and one context per test module with the
validation layer on (as every C test has), checked for validation messages after each test."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("CLOTHVK_BUILD_DIR", ROOT / "build")).resolve()

# Before the package loads the library and creates any context: the library of the build whose
# tools the tests compare against, and validation on, as tests/meson.build sets it.
os.environ.setdefault("CLOTHVK_LIBRARY", str(BUILD / "lib" / "libclothvk.so"))
os.environ.setdefault("CLOTHVK_VALIDATION", "1")

import clothvk  # noqa: E402
SCENES = ROOT / "assets" / "scenes"

# hanging.json cut down to 16 x 16 particles so that a test takes well under a second.
SMALL = {"cloths.0.grid": [16, 16], "cloths.0.pins": [[0, 0], [15, 0]]}


@pytest.fixture(scope="module")
def module_context():
    ctx = clothvk.Context()
    assert ctx.info()["validation"], "the validation layer is off: the message checks would be empty"
    yield ctx
    ctx.close()


@pytest.fixture
def ctx(module_context):
    before = module_context.validation_message_count()
    yield module_context
    count = module_context.validation_message_count() - before
    assert count == 0, f"{count} validation messages: {module_context.messages[-count:]}"


@pytest.fixture
def small_scene():
    with clothvk.Scene.load(SCENES / "hanging.json", overrides=SMALL) as scene:
        yield scene
