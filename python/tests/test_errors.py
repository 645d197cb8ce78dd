"""Failures raise clothvk.Error with the library's sentence and the result's name."""

import errno
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
        f"{SCENES / 'hanging.json'}: solver.omega (from overrides): must be greater than 0 and " \
        "less than 2, got 2.5"
    with pytest.raises(clothvk.Error) as caught:
        clothvk.Scene.load(tmp_path / "absent.json")
    assert caught.value.result == "CVK_ERROR_IO", caught.value.result


def test_a_missing_scene_file_is_a_file_not_found_error(tmp_path):
    absent = tmp_path / "absent.json"
    with pytest.raises(FileNotFoundError) as caught:
        clothvk.Scene.load(absent)
    err = caught.value
    assert isinstance(err, clothvk.SceneNotFoundError) and isinstance(err, clothvk.Error)
    assert str(err) == f"{absent}: cannot open: No such file or directory"
    assert (err.errno, err.filename, err.result) == (errno.ENOENT, str(absent), "CVK_ERROR_IO")


def test_an_unknown_key_is_a_key_error_with_its_path():
    hanging = SCENES / "hanging.json"
    with pytest.raises(KeyError) as caught:
        clothvk.Scene.load(hanging, overrides={"cloths.0.stiffness.bogus": 1})
    err = caught.value
    assert isinstance(err, clothvk.ScenePathError)
    assert str(err) == f"{hanging}: cloths.0.stiffness.bogus (from overrides): unknown key " \
        "(expected one of: structural, shear, bend)"
    assert err.key_path == ("cloths", 0, "stiffness", "bogus")
    with pytest.raises(KeyError) as caught:
        clothvk.Scene.load(hanging, overrides={"cloths.3.mass": 1})
    assert str(caught.value) == f"{hanging}: overrides['cloths.3.mass']: index 3 is out of " \
        "range (cloths has 1 element)"
    assert caught.value.key_path == ("cloths", 3, "mass")
    with pytest.raises(KeyError) as caught:
        clothvk.Scene.load(hanging, overrides=["cloths.3.mass=1"])
    assert str(caught.value) == f"{hanging}: overrides entry 'cloths.3.mass=1': index 3 is out " \
        "of range (cloths has 1 element)"
    with pytest.raises(KeyError) as caught:
        clothvk.Scene.parse('{"cloths": [{}], "gravitee": 1}', "inline")
    assert str(caught.value) == ("inline: gravitee: unknown key (expected one of: name, dt, "
                                 "substeps, frames, integrate, gravity, damping, solver, cloths, "
                                 "render, collision, colliders, attachments, wind, air_density, "
                                 "instances)")
    assert caught.value.key_path == ("gravitee",)


def test_a_bad_value_is_a_value_error_with_its_path():
    with pytest.raises(ValueError) as caught:
        clothvk.Scene.parse('{"cloths": [{"mass": -1}]}', "inline")
    err = caught.value
    assert isinstance(err, clothvk.SceneValueError)
    assert (str(err), err.key_path) == ("inline: cloths.0.mass: must be greater than 0, got -1",
                                        ("cloths", 0, "mass"))
    with pytest.raises(ValueError) as caught:
        clothvk.Scene.parse('{"cloths": [{}]}', "inline", overrides={"solver.linear": "lu"})
    assert str(caught.value) == 'inline: solver.linear (from overrides): unknown linear solver ' \
        '"lu" (expected rbgs, jacobi, chebyshev, gs-cpu or cg)'
    with pytest.raises(ValueError) as caught:
        clothvk.Scene.parse('{"cloths": [{}]}', "inline", overrides=["frames"])
    assert (str(caught.value), caught.value.key_path) == \
        ("inline: overrides entry 'frames': expected key.path=value", None)
    with pytest.raises(ValueError) as caught:
        clothvk.Scene.parse('{"cloths": [', "inline")
    assert (str(caught.value), caught.value.key_path) == \
        ("inline:1:12: malformed JSON: ']' expected near end of file", None)


def test_no_message_for_python_overrides_says_set():
    for overrides in ({"dt": 0}, ["dt=0"]):
        with pytest.raises(ValueError) as caught:
            clothvk.Scene.parse('{"cloths": [{}]}', "inline", overrides=overrides)
        assert str(caught.value) == "inline: dt (from overrides): must be greater than 0, got 0"


def test_bad_arguments_raise_in_python_words(ctx, small_scene):
    with pytest.raises(TypeError) as caught:
        clothvk.Scene.load(SCENES / "hanging.json", overrides={3: 1})
    assert str(caught.value) == 'overrides: a key must be a dotted key path string such as ' \
        '"solver.omega", got int 3'
    with pytest.raises(ValueError) as caught:
        clothvk.Scene.load(SCENES / "hanging.json", overrides={"": 1})
    assert str(caught.value) == "overrides: a key must not be empty"
    with clothvk.Simulation(ctx, small_scene) as sim:
        with pytest.raises(ValueError) as caught:
            sim.step(-1)
        assert str(caught.value) == "frames must be at least 0, got -1"
        with pytest.raises(TypeError) as caught:
            sim.step(1.5)
        assert str(caught.value) == "frames must be a whole number, got float 1.5"
        with pytest.raises(ValueError) as caught:
            sim.grab(0, -3, [0, 0, 0])
        assert str(caught.value) == "index must be at least 0, got -3"
        assert sim.stats()["frames"] == 0
    with pytest.raises(ValueError) as caught:
        clothvk.Simulation(ctx, small_scene, workgroup_size=2**32)
    assert str(caught.value) == "workgroup_size must be at most 4294967295, got 4294967296"


def test_wrong_state_shape(ctx, small_scene):
    with clothvk.Simulation(ctx, small_scene) as sim:
        with pytest.raises(ValueError) as shape:
            sim.write_state([[0, 0, 0]])
        assert str(shape.value) == "positions: expected shape (256, 3), got (1, 3)"
        bad = sim.positions()
        bad[3, 1] = float("nan")
        with pytest.raises(clothvk.Error) as caught:
            sim.write_state(bad)
        assert caught.value.result == "CVK_ERROR_INVALID_ARGUMENT" and str(caught.value) == \
            "cvk_sim_write_state: position coordinate 1 of particle 3 is not a finite number"


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
