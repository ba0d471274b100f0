"""The World, models and materials from Python: arrays, errors, and the same positions as the
C++ World stepping the same scene."""
import subprocess
import sys

import numpy as np
import pytest

import msm_sim
from scene import build_world


@pytest.mark.parametrize("integrator", ["explicit", "implicit"])
def test_positions_bit_identical_to_cpp_world(integrator, world_reference, tmp_path):
    steps, spacing = 150, 0.01
    out = tmp_path / "positions.bin"
    subprocess.run([world_reference, integrator, repr(spacing), str(steps), str(out)],
                   check=True, capture_output=True)
    expected = np.fromfile(out, dtype=np.float64).reshape(-1, 3)
    world = build_world(integrator, spacing)
    for _ in range(steps):
        assert world.step(1e-3)["accepted"]
    positions = world.positions(0)
    assert positions.shape == expected.shape
    assert np.array_equal(positions, expected)
    # The sphere has reached the cube: the comparison covers contacts, not a free fall alone.
    assert world.wrenches(0)[1]["microcollisions"] > 0


def test_arrays_shapes_and_dtypes():
    world = build_world("explicit", 0.01)
    world.step(1e-3)
    n = 64
    for array in (world.positions(0), world.velocities(0)):
        assert array.shape == (n, 3) and array.dtype == np.float64
    model = msm_sim.build_model(msm_sim.Material(youngs=1e5, poisson=0.25, density=1000.0),
                                "box", size=[0.04, 0.04, 0.04], spacing=0.01)
    assert model.rest_positions.shape == (n, 3) and model.rest_positions.dtype == np.float64
    assert model.masses.shape == (n,) and model.masses.dtype == np.float64
    assert model.springs.shape == (model.num_springs, 2) and model.springs.dtype == np.int32
    assert model.spring_stiffness.shape == (model.num_springs,)
    wrenches = world.wrenches(0)
    assert len(wrenches) == 2 and wrenches[0]["force"].shape == (3,)
    energies = world.energies(0)
    assert energies["total"] == pytest.approx(
        energies["kinetic"] + energies["elastic"] + energies["gravitational"])


def test_positions_are_copies_and_reset_restores_rest():
    world = build_world("explicit", 0.01)
    before = world.positions(0)
    before[:] = 0.0
    assert not np.array_equal(world.positions(0), before)
    rest = world.positions(0)
    for _ in range(20):
        world.step(1e-3)
    assert not np.array_equal(world.positions(0), rest)
    world.reset()
    assert world.time == 0.0 and np.array_equal(world.positions(0), rest)


def test_contact_points_recorded():
    material = msm_sim.Material(youngs=5e4, poisson=0.3, density=1000.0)
    cube = msm_sim.build_model(material, "box", size=[0.04, 0.04, 0.04], spacing=0.01)
    world = msm_sim.World(record_contact_points=True)
    world.add_body("cube", cube.transformed([0.0, 0.0, 0.0195]))
    world.add_collider("ground", "plane")
    for _ in range(30):
        world.step(1e-3)
    points = world.contact_points(0)
    k = points["node"].shape[0]
    assert k > 0 and points["point"].shape == (k, 3) and points["node"].dtype == np.int32


def test_clamp_holds_its_nodes_and_carries_the_weight():
    material = msm_sim.Material(youngs=5e4, poisson=0.3, density=1000.0)
    cube = msm_sim.build_model(material, "box", size=[0.04, 0.04, 0.04], spacing=0.01)
    world = msm_sim.World(gravity=[0.0, 0.0, -9.81])
    body = world.add_body("cube", cube, damping=0.01)
    top = np.flatnonzero(cube.rest_positions[:, 2] > 0.01)
    assert world.add_clamp(body, "hook", top) == 0
    for _ in range(300):
        world.step(1e-3)
    assert np.array_equal(world.positions(body)[top], cube.rest_positions[top])
    hook = world.wrenches(body)[0]
    assert hook["force"][2] < 0.0  # the hanging cube pulls the hook down
    with pytest.raises(ValueError):
        world.add_clamp(body, "bad", [cube.num_nodes])


def test_tensile_law_makes_power_springs_that_stiffen_in_tension():
    material = msm_sim.Material(youngs=5e4, poisson=0.3, density=1000.0)
    linear = msm_sim.build_model(material, "box", size=[0.04, 0.04, 0.04], spacing=0.01)
    power = msm_sim.build_model(material, "box", size=[0.04, 0.04, 0.04], spacing=0.01,
                                tensile_law={"alpha": 1.0, "beta": 5.0})
    # The laws share the small-strain stiffness; beta stiffens the springs when stretched.
    assert np.array_equal(power.spring_stiffness, linear.spring_stiffness)
    stretched = []
    for model in (linear, power):
        world = msm_sim.World(gravity=[0.0, 0.0, 0.0])
        body = world.add_body("cube", model)
        world.set_state(body, model.rest_positions * [1.2, 1.0, 1.0], np.zeros((64, 3)))
        stretched.append(world.energies(body)["elastic"])
    assert stretched[1] > stretched[0] > 0.0
    with pytest.raises(ValueError, match="tensile_law"):
        msm_sim.build_model(material, "box", size=[0.04] * 3, spacing=0.01, spring="power")


def test_model_file_round_trip(tmp_path):
    material = msm_sim.Material.from_shore(30, poisson=0.45, density=1070.0, scale="00")
    assert 0.0 < material.youngs < 1e6
    model = msm_sim.build_model(material, "sphere", radius=0.02, spacing=0.005)
    path = str(tmp_path / "ball.msm")
    model.save(path)
    loaded = msm_sim.load_model(path)
    assert np.array_equal(loaded.rest_positions, model.rest_positions)
    assert np.array_equal(loaded.spring_stiffness, model.spring_stiffness)


def test_mass_scaling_by_its_yaml_name():
    material = msm_sim.Material(youngs=2e5, poisson=0.45, density=1100.0)
    scaled = msm_sim.build_model(material, "sphere", radius=0.02, spacing=0.005)
    plain = msm_sim.build_model(material, "sphere", radius=0.02, spacing=0.005, mass_scaling=0.0)
    assert plain.added_mass == 0.0
    assert 0.0 < scaled.added_mass <= 0.01 * plain.masses.sum()
    assert scaled.masses.sum() == pytest.approx(plain.masses.sum() + scaled.added_mass)
    with pytest.raises(ValueError, match="mass_scaling must lie in"):
        msm_sim.build_model(material, "sphere", radius=0.02, spacing=0.005, mass_scaling=0.5)


@pytest.mark.parametrize("call, message", [
    (lambda: msm_sim.Material(youngs=-1.0, poisson=0.3, density=1000.0), "oung"),
    (lambda: msm_sim.build_model(msm_sim.Material(youngs=1e5, poisson=0.3, density=1e3),
                                 "cone", spacing=0.01), "shape must be"),
    (lambda: msm_sim.World(integrator="rk4"), "integrator must be"),
    (lambda: build_world("explicit", 0.01).positions(3), "no body 3"),
    (lambda: build_world("explicit", 0.01).step(-1.0), "dt must be > 0"),
])
def test_bad_arguments_raise_value_error(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_module_imports_no_ros_and_messages_import_beside_it():
    code = ("import sys, msm_sim; assert not any(m.split('.')[0] in ('rospy', 'roscpp', "
            "'genpy', 'rosgraph') for m in sys.modules), sorted(sys.modules)")
    subprocess.run([sys.executable, "-c", code], check=True)
    subprocess.run([sys.executable, "-c", "import msm_sim.msg, msm_sim.srv; "
                    "msm_sim.msg.ContactArray; msm_sim.srv.SetMaterial"], check=True)
