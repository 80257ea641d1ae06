# Errors as exceptions: bad input names the file and the field, as the command does; blow-ups
# and device failures have classes of their own.
import json
import pickle

import pytest

import rubble
from test_physics import falling_sphere


def test_missing_file_names_the_file(tmp_path):
    path = str(tmp_path / "nowhere.json")
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(path)
    assert e.value.file == path and e.value.field is None
    assert str(e.value) == f"{path}: scene file not found"
    assert isinstance(e.value, ValueError)


def test_bad_field_in_a_file_names_the_file_and_the_field(tmp_path, rubble_binary):
    scene = falling_sphere()
    scene["bodies"][0]["mass"] = -1.0
    path = tmp_path / "bad_mass.json"
    path.write_text(json.dumps(scene))
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(path)
    assert e.value.file == str(path)
    assert e.value.field.startswith("bodies[0].mass")
    # The command says the same words, with exit status 2.
    from conftest import run_command
    done = run_command(rubble_binary, "validate", path, check=False)
    assert done.returncode == 2
    assert done.stderr.strip() == f"rubble: {e.value}"


def test_bad_field_in_a_dict_names_its_label():
    scene = falling_sphere()
    scene["shapes"]["ball"]["radius"] = 0.0
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(scene)
    assert e.value.file == "<scene dict>"
    assert e.value.field.startswith("shapes.ball.radius")
    scene["shapes"]["ball"]["radius"] = 0.1
    scene["bodies"][0]["colour"] = "red"
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(scene, label="my scene")
    assert e.value.file == "my scene" and "colour" in e.value.field


def test_bad_options_name_the_option():
    scene = falling_sphere()
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(scene, iterations=0)
    assert e.value.where == "World.load: iterations"
    with pytest.raises(rubble.SceneError, match='unknown value "gauss-seidel"'):
        rubble.World.load(scene, solver="gauss-seidel")
    with pytest.raises(rubble.SceneError, match="dt"):
        rubble.World.load(scene, dt=-0.01)
    with pytest.raises(TypeError, match="unknown option 'iteration'"):
        rubble.World.load(scene, iteration=5)


def test_a_state_that_blows_up_is_a_numerical_error():
    w = rubble.World.load(falling_sphere())
    w.apply_impulse("ball", [3e38, 0, 0])
    w.apply_impulse("ball", [3e38, 0, 0])  # the momentum overflows to infinity
    with pytest.raises(rubble.NumericalError) as e:
        w.step(10)
    assert "body ball" in str(e.value) and "after step 1" in str(e.value)
    assert isinstance(e.value, ArithmeticError)


def test_energy_growth_is_a_numerical_error():
    # A box spun at 10^6 rad/s: its energy grows step by step with finite numbers; the blow-up
    # watch stops it, as the command does with exit status 3.
    spinner = {
        "format": "rubble-scene", "version": 1,
        "simulation": {"gravity": [0, 0, 0]},
        "shapes": {"c": {"type": "box", "half_extents": [1, 0.2, 0.5]}},
        "bodies": [{"name": "spinner", "shape": "c", "mass": 1,
                    "angular_velocity": [1e6, 3e5, 0]}],
    }
    w = rubble.World.load(spinner)
    with pytest.raises(rubble.NumericalError, match="blew up in step 3") as e:
        w.step(10)
    assert e.value.where == "body spinner" and e.value.kind == "Numerical"


def test_a_pile_at_one_point_is_a_limit_error():
    # 600 boxes at one point make 179,700 pairs, past the budget of 65,536 + 64 per body.
    scene = {
        "format": "rubble-scene", "version": 1,
        "shapes": {"box": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}},
        "bodies": [{"name": f"b{i}", "shape": "box", "mass": 1, "position": [0, 1, 0]}
                   for i in range(600)],
    }
    w = rubble.World.load(scene)
    with pytest.raises(rubble.LimitError, match="step 1 has more than 103936 broad-phase pairs") \
            as e:
        w.step()
    assert e.value.where == "broadPhase" and isinstance(e.value, RuntimeError)
    assert w.step_count == 0
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is rubble.LimitError and back.where == "broadPhase"


def test_an_interrupted_step_is_a_keyboard_interrupt():
    # What the library reports when a stop request ends a step between its stages.
    e = rubble._errors.make_error("Interrupted", "step 4", "stopped on request")
    assert type(e) is rubble.StepInterrupted
    assert isinstance(e, KeyboardInterrupt) and e.where == "step 4"
    assert str(e) == "step 4: stopped on request"


def test_keywords_are_checked_as_the_command_line_checks_them(tmp_path, rubble_binary):
    # The option table reads keywords as it reads flags: the same ranges, the same words.
    from conftest import run_command
    path = tmp_path / "fall.json"
    path.write_text(json.dumps(falling_sphere()))
    for key, value, flag, text in [
            ("dt", 1e-40, "--dt", "1e-40"),
            ("particle_spacing", 1e-9, "--particle-spacing", "1e-09"),
            ("iterations", 0, "--iterations", "0")]:
        with pytest.raises(rubble.SceneError) as e:
            rubble.World.load(path, **{key: value})
        assert e.value.where == f"World.load: {key}"
        done = run_command(rubble_binary, "run", path, flag, text, check=False)
        assert done.returncode == 2
        message = str(e.value)[len(e.value.where) + 2:]
        assert done.stderr.strip() == f"rubble: {flag}: {message}"


def test_a_kernel_that_does_not_build_is_a_device_error(tmp_path, repo):
    # A copy of the kernels with one of them broken: the device's compiler refuses it.
    kernels = tmp_path / "kernels"
    kernels.mkdir()
    for f in (repo / "kernels").glob("*.cl"):
        (kernels / f.name).write_text(f.read_text())
    first = sorted(kernels.glob("*.cl"))[0]
    first.write_text(first.read_text() + "\n__kernel void broken(void) { this is not C }\n")
    with pytest.raises(rubble.DeviceError) as e:
        rubble.World.load(rubble.example_scene("stack_10"), backend="opencl", solver="jacobi",
                          kernel_dir=kernels)
    assert isinstance(e.value, RuntimeError)


def test_bad_arguments_raise_python_errors():
    w = rubble.World.load(falling_sphere())
    with pytest.raises(IndexError):
        w.set_velocity(5, [0, 0, 0])
    with pytest.raises(KeyError):
        w.apply_impulse("nobody", [0, 1, 0])
    with pytest.raises(ValueError, match="three numbers"):
        w.set_velocity(0, [1, 2])
    with pytest.raises(ValueError):
        w.step(-1)
    with pytest.raises(KeyError, match="no shape named 'rock'"):
        w.add_debris("rock", [[0, 1, 0]])
    with pytest.raises(rubble.SceneError, match="mass"):
        w.add_debris("ball", [[0, 1, 0]], mass=0.0)
    with pytest.raises(KeyError, match="no example scene named 'nothing'"):
        rubble.example_scene("nothing")


def test_errors_keep_their_fields_across_processes():
    scene = falling_sphere()
    scene["bodies"][0]["mass"] = -1.0
    with pytest.raises(rubble.SceneError) as e:
        rubble.World.load(scene)
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is rubble.SceneError
    assert (str(back), back.file, back.field, back.where) == \
        (str(e.value), e.value.file, e.value.field, e.value.where)
