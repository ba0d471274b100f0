"""The scene test/python/world_reference.cpp steps in C++, built and stepped from Python: a
cube dropped on the ground while a sphere presses down. Change both files together."""
import msm_sim


def build_world(integrator, spacing):
    """The scene's World, not yet stepped; the cube is body 0."""
    material = msm_sim.Material(youngs=5e4, poisson=0.3, density=1000.0)
    cube = msm_sim.build_model(material, "box", size=[0.04, 0.04, 0.04], spacing=spacing)
    world = msm_sim.World(integrator=integrator)
    world.add_body("cube", cube.transformed([0.0, 0.0, 0.021]), damping=0.001)
    world.add_collider("ground", "plane")
    finger = world.add_collider("finger", "sphere", radius=0.01, position=[0.0, 0.0, 0.052])
    world.set_collider_twist(finger, [0.0, 0.0, -0.05])
    return world
