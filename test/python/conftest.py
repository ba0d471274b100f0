"""Where the tests find the executables they compare with: the options the catkin test target
passes, else the devel spaces on CMAKE_PREFIX_PATH (a sourced workspace)."""
import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def pytest_addoption(parser):
    parser.addoption("--msm-lab", help="the msm_lab executable")
    parser.addoption("--world-reference", help="the msm_world_reference executable")


def _executable(config, option, name):
    given = config.getoption(option)
    if given:
        return given
    for prefix in os.environ.get("CMAKE_PREFIX_PATH", "").split(os.pathsep):
        candidate = os.path.join(prefix, "lib", "msm_sim", name)
        if prefix and os.access(candidate, os.X_OK):
            return candidate
    raise pytest.UsageError("%s not found: pass --%s or source the workspace" % (name, option))


@pytest.fixture(scope="session")
def msm_lab(request):
    return _executable(request.config, "--msm-lab", "msm_lab")


@pytest.fixture(scope="session")
def world_reference(request):
    return _executable(request.config, "--world-reference", "msm_world_reference")
