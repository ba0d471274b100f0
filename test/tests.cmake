# The package's tests (gtest, rostest, pytest), included by CMakeLists.txt after every target
# they link. `make test` runs them one at a time (Makefile).
if(CATKIN_ENABLE_TESTING)
  find_package(rostest REQUIRED)
  find_package(roslaunch REQUIRED)
  roslaunch_add_file_check(launch)

  catkin_add_gtest(test_core_units
    test/material/test_material.cpp
    test/material/test_shore_hardness.cpp
    test/material/test_spring_law.cpp
    test/model/test_model_builder.cpp
    test/model/test_model_transform.cpp
    test/model/test_body_frame.cpp
    test/lattice/test_body_recipe.cpp test/lattice/test_body_recipe_limits.cpp
    test/lattice/test_cubic_lattice_builder.cpp
    test/lattice/test_free_face_bending.cpp
    test/lattice/test_outer_layer_dispersion.cpp
    test/lattice/test_selective_mass_scaling.cpp
    test/lattice/test_random_lattice_builder.cpp
    test/mechanics/test_force_evaluator.cpp
    test/mechanics/test_force_kernels.cpp
    test/mechanics/test_single_precision_kernels.cpp test/mechanics/test_single_precision_shares.cpp
    test/mechanics/test_dispersion_stability.cpp
    test/mechanics/test_static_solver.cpp
    test/mechanics/test_uniaxial_compression.cpp
    test/mechanics/test_lattice_uniaxial_tension.cpp
    test/mechanics/test_node_array_krylov.cpp
    test/mechanics/test_spring_schedule.cpp
    test/mechanics/test_worker_pool.cpp
    test/mechanics/test_stable_time_step.cpp
    test/mechanics/test_orientation_barrier.cpp
    test/mechanics/test_orientation_barrier_tracking.cpp
    test/experiments/test_measurements.cpp
    test/experiments/test_indentation_experiment.cpp
    test/experiments/test_indentation_fit.cpp
    test/experiments/test_tensile_curve.cpp
    test/experiments/test_tensile_fit.cpp
    test/experiments/test_realtime_experiment.cpp
    test/experiments/test_grip_experiment.cpp
    test/experiments/test_calculix_reference.cpp
    test/experiments/test_cantilever_faces.cpp
    test/geometry/test_mesh.cpp
    test/geometry/test_surface_skin.cpp
    test/geometry/test_box_clipping.cpp
    test/geometry/test_spatial_hash_grid.cpp
    test/geometry/test_surface_strain.cpp
    test/geometry/test_mesh_header_check.cpp
    test/geometry/test_invalid_meshes.cpp
    test/geometry/test_mesh_fuzz.cpp
    test/io/test_regular_file.cpp
    test/dynamics/test_world.cpp test/dynamics/test_world_threads.cpp
    test/dynamics/test_border_nodes.cpp test/dynamics/test_contact_wrench_average.cpp
    test/dynamics/test_contact_points.cpp
    test/dynamics/test_penetration_recovery.cpp
    test/dynamics/test_collider_contacts.cpp
    test/dynamics/test_pair_contacts.cpp
    test/dynamics/test_collider_entries.cpp
    test/dynamics/test_body_entries.cpp
    test/dynamics/test_integrator_stages.cpp
    test/experiments/test_held_indentation.cpp
    test/model/test_model_file.cpp test/model/test_vtk_export.cpp
    test/model/test_model_file_self_calibration.cpp
    test/model/test_model_file_power_law.cpp
  )
  # The unit tests also test the library's private helpers (src/<concept>/*.h).
  target_include_directories(test_core_units PRIVATE src)
  target_link_libraries(test_core_units msm_sim_experiments gtest_main)
  target_compile_definitions(test_core_units PRIVATE
    MSM_SIM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data"
    MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

  # The squeeze against the stored CalculiX reference (issue 61); needs no ccx.
  catkin_add_gtest(test_squeeze_calculix test/experiments/test_squeeze_calculix.cpp TIMEOUT 900)
  target_link_libraries(test_squeeze_calculix msm_sim_lab gtest_main)
  target_compile_definitions(test_squeeze_calculix PRIVATE
    MSM_SIM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data")

  # The parallel-gripper grasp (issue "Grasp and lift"): shapes held, dropped, not squeezed out.
  catkin_add_gtest(test_grasp test/experiments/test_grasp_experiment.cpp TIMEOUT 600)
  target_link_libraries(test_grasp msm_sim_experiments gtest_main)
  target_compile_definitions(test_grasp PRIVATE MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

  # The physics acceptance tests of the calibrated models (issue: thesis tables 3.1 and 3.2.x).
  catkin_add_gtest(test_calibration
    test/lattice/test_calibration.cpp
    test/lattice/test_emsm_calibration.cpp
    test/lattice/test_random_self_calibration.cpp
    test/lattice/test_baudet.cpp
    test/lattice/test_mesh_models.cpp
    TIMEOUT 900
  )
  target_link_libraries(test_calibration msm_sim_experiments gtest_main)

  # The dynamics acceptance tests (issue "Dynamics": thesis 6.2-6.4).
  catkin_add_gtest(test_dynamics test/dynamics/test_dynamics.cpp
    test/dynamics/test_implicit_integrator.cpp test/dynamics/test_implicit_contacts.cpp
    test/dynamics/test_implicit_solve_stop.cpp test/experiments/test_hertz_contact.cpp
    test/dynamics/test_carrier_springs.cpp
    TIMEOUT 900)
  target_link_libraries(test_dynamics msm_sim_experiments gtest_main)

  # The node's contract, against the running node (rostest starts its own master).
  catkin_add_executable_with_gtest(test_msm_sim_node test/ros/test_msm_sim_node.cpp
    test/ros/test_node_config.cpp test/ros/test_robot_node.cpp
    test/ros/test_contact_points_node.cpp test/ros/test_node_self_calibration.cpp EXCLUDE_FROM_ALL)
  target_include_directories(test_msm_sim_node PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(test_msm_sim_node msm_sim_ros ${catkin_LIBRARIES} Eigen3::Eigen)
  add_dependencies(test_msm_sim_node ${PROJECT_NAME}_generate_messages_cpp msm_sim_node
    msm_sim_nodelet msm_replay)
  target_compile_definitions(test_msm_sim_node PRIVATE
    MSM_REPLAY_EXECUTABLE="$<TARGET_FILE:msm_replay>"
    MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
  foreach(scene push wrench bad_messages material ground markers simtime nodelet robot
      robot_bad_description robot_bad_links robot_tf_jump rviz_screenshot replay_equivalence
      contact_points
      runtime_tuning demo_plot grasp)
    add_rostest(test/ros/${scene}.test DEPENDENCIES test_msm_sim_node)
  endforeach()

  # Message storm (issue "Hardening"): bad messages at 1 kHz and service calls for 60 s.
  catkin_add_executable_with_gtest(test_message_storm test/ros/test_message_storm.cpp
    EXCLUDE_FROM_ALL)
  target_include_directories(test_message_storm PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(test_message_storm ${catkin_LIBRARIES})
  add_dependencies(test_message_storm ${PROJECT_NAME}_generate_messages_cpp msm_sim_node)
  add_rostest(test/ros/message_storm.test DEPENDENCIES test_message_storm)

  # msm_replay: determinism, regression against test/data, command-line contract.
  catkin_add_gtest(test_replay test/ros/test_replay.cpp TIMEOUT 300)
  target_include_directories(test_replay PRIVATE ${catkin_INCLUDE_DIRS})
  target_link_libraries(test_replay ${catkin_LIBRARIES})
  target_compile_definitions(test_replay PRIVATE
    MSM_REPLAY_EXECUTABLE="$<TARGET_FILE:msm_replay>"
    MSM_SIM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data"
    MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
  add_dependencies(test_replay msm_replay)

  # Soak (issue "Hardening"): 10 simulated minutes of random pushes; `make soak`, not a test.
  catkin_add_executable_with_gtest(test_soak test/soak/test_soak.cpp EXCLUDE_FROM_ALL)
  target_link_libraries(test_soak msm_sim_core gtest_main)
  target_compile_definitions(test_soak PRIVATE MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")

  # Config fuzz (issue "Hardening"): malformed scenes through the real msm_replay.
  catkin_add_gtest(test_config_fuzz test/ros/test_config_fuzz.cpp)
  target_include_directories(test_config_fuzz PRIVATE ${YAML_CPP_INCLUDE_DIR})
  target_link_libraries(test_config_fuzz ${YAML_CPP_LIBRARIES} gtest_main)
  target_compile_definitions(test_config_fuzz PRIVATE
    MSM_REPLAY_EXECUTABLE="$<TARGET_FILE:msm_replay>"
    MSM_SIM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data"
    MSM_SIM_PACKAGE_DIR="${CMAKE_CURRENT_SOURCE_DIR}")
  add_dependencies(test_config_fuzz msm_replay)

  # The scene's object keys (ReadObjects, the spring law) read and built without a ROS master.
  catkin_add_gtest(test_object_config test/ros/test_object_config.cpp)
  target_link_libraries(test_object_config msm_sim_ros gtest_main)

  # What hostile publishers send, into the Simulation without a ROS master (issue "Hardening").
  catkin_add_gtest(test_simulation_inputs test/ros/test_simulation_inputs.cpp TIMEOUT 300)
  target_link_libraries(test_simulation_inputs msm_sim_ros gtest_main)

  catkin_add_gtest(test_lab_cli test/lab/test_lab_cli.cpp test/lab/test_lab_sphere_cli.cpp
    test/lab/test_lab_mesh_cli.cpp test/lab/test_lab_fit_cli.cpp
    test/lab/test_lab_tensile_cli.cpp
    test/lab/test_lab_grip_cli.cpp
    test/lab/test_lab_grasp_cli.cpp
    test/lab/test_lab_squeeze_cli.cpp
    test/lab/test_lab_material_cli.cpp
    test/lab/test_lab_reference_cli.cpp
    test/lab/test_lab_power_law_cli.cpp)
  target_link_libraries(test_lab_cli msm_sim_lab gtest_main)
  target_compile_definitions(test_lab_cli PRIVATE MSM_LAB_EXECUTABLE="$<TARGET_FILE:msm_lab>"
    MSM_SIM_TEST_DATA_DIR="${CMAKE_CURRENT_SOURCE_DIR}/test/data")
  add_dependencies(test_lab_cli msm_lab)
endif()
