"""msm_sim from Python: materials, models, the World and the lab commands (docs/python.md).

Nothing here imports ROS. With catkin the generated messages join this package as msm_sim.msg
and msm_sim.srv (those do need the ROS Python libraries).
"""
# With catkin the package is split: this directory, and the devel space's with _core, msg and
# srv. The devel space's __init__ joins them and puts this source directory first on sys.path,
# which processes started by spawning (Dask's local workers) inherit: imported from here, the
# package joins the devel space's directory itself.
from pkgutil import extend_path
__path__ = extend_path(__path__, __name__)

from msm_sim._core import Material, Model, World, load_model  # noqa: E402
from msm_sim._core import build_model as _core_build_model  # noqa: E402
from msm_sim import lab  # noqa: E402

__all__ = ["Material", "Model", "World", "build_model", "lab", "load_model"]


def build_model(material, shape="box", *, size=(0.1, 0.1, 0.1), radius=0.05, length=0.1,
                mesh="", scale=1.0, model="cubic", spacing=0.0, target_nodes=0,
                spring=None, tensile_law=None, antialias=True, seed=1,
                self_calibrate=False, free_face_bending=False, surface_dispersion=1.0,
                mass_scaling=0.01):
    """The calibrated model of a shape centred on the origin, by the scene YAML's names.

    shape: box (size, m), sphere (radius), cylinder (radius, length along z) or mesh (a closed
    mesh file, scaled by scale). model: cubic, random or baudet (boxes). One of spacing (m) and
    target_nodes is needed. tensile_law: a mapping with the fitted power law's alpha and beta
    (what `msm_lab fit --tensile`, or msm_sim.lab.fit(tensile=...), returns). spring: linear,
    nonlinear or power; default power with a tensile_law, else linear. antialias, seed,
    self_calibrate, free_face_bending, surface_dispersion and mass_scaling as in
    docs/scenes.md. Raises ValueError for options no builder takes.
    """
    if spring is None:
        spring = "power" if tensile_law is not None else "linear"
    if spring == "power" and tensile_law is None:
        raise ValueError("spring power needs a tensile_law {alpha, beta}")
    law = tensile_law if tensile_law is not None else {"alpha": 1.0, "beta": 0.0}
    lattice = {"model": model, "spacing": float(spacing), "target_nodes": int(target_nodes),
               "spring": spring, "alpha": float(law["alpha"]), "beta": float(law["beta"]),
               "antialias": bool(antialias), "seed": int(seed),
               "self_calibrate": bool(self_calibrate),
               "free_face_bending": bool(free_face_bending),
               "surface_dispersion": float(surface_dispersion),
               "mass_scaling": float(mass_scaling)}
    return _core_build_model(material, shape, [float(v) for v in size], float(radius),
                             float(length), str(mesh), float(scale), lattice)

