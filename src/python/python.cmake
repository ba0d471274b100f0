# --- Python module msm_sim._core (docs/python.md) ------------------------------------------
# The compiled half of the Python package src/msm_sim/ (catkin_python_setup() above installs
# that package; the generated msm_sim.msg and msm_sim.srv sit beside it). Built into the devel
# space's package directory so that sourcing devel/setup.bash makes `import msm_sim` work. Needs
# Debian's pybind11-dev; links the ROS-free libraries only.
# catkin has found Python3 already, which makes pybind11 use FindPython's python3_add_library;
# that command exists only where FindPython ran, hence here again.
find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
find_package(pybind11 CONFIG REQUIRED)
pybind11_add_module(_core
  src/python/module.cpp
  src/python/lab_binding.cpp
  src/python/model_binding.cpp
  src/python/world_binding.cpp
  src/python/world_colliders.cpp)
target_link_libraries(_core PRIVATE msm_sim_lab msm_sim_experiments)
set_target_properties(_core PROPERTIES
  LIBRARY_OUTPUT_DIRECTORY ${CATKIN_DEVEL_PREFIX}/${CATKIN_PACKAGE_PYTHON_DESTINATION})
install(TARGETS _core LIBRARY DESTINATION ${CATKIN_PACKAGE_PYTHON_DESTINATION})

# The same scene stepped by the C++ World, which test/python/test_world.py and
# bench/python_step_benchmark.py compare the Python-driven World with.
add_executable(msm_world_reference test/python/world_reference.cpp)
target_link_libraries(msm_world_reference msm_sim_core)

if(CATKIN_ENABLE_TESTING)
  # pytest under catkin's environment (the devel space sourced), its JUnit XML where
  # catkin_test_results reads it. The sweep tests start their own dask-scheduler and workers.
  # run_tests.py takes the command as one string.
  set(MSM_SIM_PYTEST "/usr/bin/python3 -m pytest -q -p no:cacheprovider"
    "${CMAKE_CURRENT_SOURCE_DIR}/test/python --msm-lab $<TARGET_FILE:msm_lab>"
    "--world-reference $<TARGET_FILE:msm_world_reference>"
    "--junitxml=${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/pytest-python.xml")
  string(JOIN " " MSM_SIM_PYTEST ${MSM_SIM_PYTEST})
  catkin_run_tests_target("pytest" "python" "pytest-python.xml" COMMAND "${MSM_SIM_PYTEST}"
    DEPENDENCIES _core msm_lab msm_world_reference)
endif()
