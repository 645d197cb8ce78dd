"""Failures raise clothvk.Error with the library's sentence and the result's name."""

import json

import pytest

import clothvk
from conftest import SCENES


def test_bad_mass_raises_with_the_library_sentence(tmp_path):
    scene = json.loads((SCENES / "hanging.json").read_text())
    scene["cloths"][0]["mass"] = -1
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(scene))
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.load(path)
    err = caught.value
    assert isinstance(err, RuntimeError)
    assert err.message == f"{path}: cloths.0.mass: must be greater than 0, got -1"
    assert str(err) == err.message
    assert err.result == "CVK_ERROR_INVALID_ARGUMENT"


def test_bad_override_and_missing_file(tmp_path):
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.load(SCENES / "hanging.json", overrides={"solver.omega": 2.5})
    assert caught.value.message == \
        f"{SCENES / 'hanging.json'}: solver.omega (from --set): must be greater than 0 and less " \
        "than 2, got 2.5"
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.load(tmp_path / "absent.json")
    assert caught.value.result == "CVK_ERROR_IO", caught.value.result


def test_wrong_state_shape(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as sim:
        with pytest.raises(ValueError, match=r"expected shape \(256, 3\)"):
            sim.write_state([[0, 0, 0]])
        with pytest.raises(clothvk.Error) as caught:
            bad = sim.positions()
            bad[3, 1] = float("nan")
            sim.write_state(bad)
        assert caught.value.result == "CVK_ERROR_INVALID_ARGUMENT"


def test_scene_text_errors_name_the_source():
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.parse('{"cloths": [{"mass": -1}]}', "inline")
    assert caught.value.message == "inline: cloths.0.mass: must be greater than 0, got -1"
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.parse('{"cloths": [{"mass": }]}', "inline")
    assert (caught.value.message, caught.value.result) == \
        ("inline:1:22: malformed JSON: unexpected token near '}'", "CVK_ERROR_PARSE")
    with clothvk.Scene.parse('{"cloths": [{"grid": [4, 4]}]}', "inline",
                             overrides=["frames=12"]) as scene:
        assert (scene.frames, scene.cloth_count) == (12, 1)
