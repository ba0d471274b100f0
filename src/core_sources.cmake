# The core library's sources (ROS-free: Eigen, CGAL, assimp), for the package's CMakeLists.txt
# and for the libFuzzer build (test/fuzz/CMakeLists.txt). Set MSM_SIM_DIR to the package root
# before including.
set(MSM_SIM_CORE_SOURCES
  # material
  ${MSM_SIM_DIR}/src/material/extended_msm.cpp
  ${MSM_SIM_DIR}/src/material/material.cpp
  ${MSM_SIM_DIR}/src/material/shore_hardness.cpp
  ${MSM_SIM_DIR}/src/material/spring_law.cpp
  # model
  ${MSM_SIM_DIR}/src/model/body_frame.cpp
  ${MSM_SIM_DIR}/src/model/binary_file.cpp
  ${MSM_SIM_DIR}/src/model/model_builder.cpp
  ${MSM_SIM_DIR}/src/model/model_file.cpp
  ${MSM_SIM_DIR}/src/model/model_file_self_calibration.cpp
  ${MSM_SIM_DIR}/src/model/model_file_spring_law.cpp
  ${MSM_SIM_DIR}/src/model/model_statistics.cpp
  ${MSM_SIM_DIR}/src/model/model_transform.cpp
  ${MSM_SIM_DIR}/src/model/node_selection.cpp
  # lattice
  ${MSM_SIM_DIR}/src/lattice/baudet_lattice_builder.cpp
  ${MSM_SIM_DIR}/src/lattice/body_recipe.cpp
  ${MSM_SIM_DIR}/src/lattice/body_shape.cpp
  ${MSM_SIM_DIR}/src/lattice/cubic_lattice_builder.cpp
  ${MSM_SIM_DIR}/src/lattice/free_face_bending.cpp
  ${MSM_SIM_DIR}/src/lattice/lattice_geometry.cpp
  ${MSM_SIM_DIR}/src/lattice/mesh_lattice_builder.cpp
  ${MSM_SIM_DIR}/src/lattice/node_centred_lattice.cpp
  ${MSM_SIM_DIR}/src/lattice/outer_layer_dispersion.cpp
  ${MSM_SIM_DIR}/src/lattice/random_lattice_builder.cpp
  ${MSM_SIM_DIR}/src/lattice/random_self_calibration.cpp
  ${MSM_SIM_DIR}/src/lattice/selective_mass_scaling.cpp
  # io
  ${MSM_SIM_DIR}/src/io/regular_file.cpp
  # geometry
  ${MSM_SIM_DIR}/src/geometry/box_clipping.cpp
  ${MSM_SIM_DIR}/src/geometry/delaunay.cpp
  ${MSM_SIM_DIR}/src/geometry/gltf_header_check.cpp
  ${MSM_SIM_DIR}/src/geometry/mesh_header_check.cpp
  ${MSM_SIM_DIR}/src/geometry/mesh_import.cpp
  ${MSM_SIM_DIR}/src/geometry/mesh_primitives.cpp
  ${MSM_SIM_DIR}/src/geometry/ply_header_check.cpp
  ${MSM_SIM_DIR}/src/geometry/solid_mesh.cpp
  ${MSM_SIM_DIR}/src/geometry/spatial_hash_grid.cpp
  ${MSM_SIM_DIR}/src/geometry/surface_skin.cpp
  ${MSM_SIM_DIR}/src/geometry/surface_strain.cpp
  ${MSM_SIM_DIR}/src/geometry/tetrahedralization.cpp
  ${MSM_SIM_DIR}/src/geometry/triangle_mesh.cpp
  ${MSM_SIM_DIR}/src/geometry/vtk_export.cpp
  # mechanics
  ${MSM_SIM_DIR}/src/mechanics/dof_constraints.cpp
  ${MSM_SIM_DIR}/src/mechanics/force_evaluator.cpp
  ${MSM_SIM_DIR}/src/mechanics/force_evaluator_reference.cpp
  ${MSM_SIM_DIR}/src/mechanics/force_kernels.cpp
  ${MSM_SIM_DIR}/src/mechanics/lattice_uniaxial_tension.cpp
  ${MSM_SIM_DIR}/src/mechanics/single_precision_kernels.cpp
  ${MSM_SIM_DIR}/src/mechanics/single_precision_schedule.cpp
  ${MSM_SIM_DIR}/src/mechanics/force_evaluator_stiffness.cpp
  ${MSM_SIM_DIR}/src/mechanics/force_evaluator_runs_stiffness.cpp
  ${MSM_SIM_DIR}/src/mechanics/linearization_kernels.cpp
  ${MSM_SIM_DIR}/src/mechanics/masked_pcg.cpp
  ${MSM_SIM_DIR}/src/mechanics/node_shares.cpp
  ${MSM_SIM_DIR}/src/mechanics/momentum_flow.cpp
  ${MSM_SIM_DIR}/src/mechanics/orientation_barrier.cpp
  ${MSM_SIM_DIR}/src/mechanics/orientation_barrier_tracking.cpp
  ${MSM_SIM_DIR}/src/mechanics/share_plan.cpp
  ${MSM_SIM_DIR}/src/mechanics/single_pipeline.cpp
  ${MSM_SIM_DIR}/src/mechanics/spring_schedule.cpp
  ${MSM_SIM_DIR}/src/mechanics/stable_time_step.cpp
  ${MSM_SIM_DIR}/src/mechanics/static_solver.cpp
  ${MSM_SIM_DIR}/src/mechanics/uniaxial_compression.cpp
  ${MSM_SIM_DIR}/src/mechanics/worker_pool.cpp
  # dynamics
  ${MSM_SIM_DIR}/src/dynamics/border_nodes.cpp
  ${MSM_SIM_DIR}/src/dynamics/collider.cpp
  ${MSM_SIM_DIR}/src/dynamics/contact_point_average.cpp
  ${MSM_SIM_DIR}/src/dynamics/contact_wrench_average.cpp
  ${MSM_SIM_DIR}/src/dynamics/collider_contacts.cpp
  ${MSM_SIM_DIR}/src/dynamics/collider_entries.cpp
  ${MSM_SIM_DIR}/src/dynamics/body_entries.cpp
  ${MSM_SIM_DIR}/src/dynamics/explicit_integrator.cpp
  ${MSM_SIM_DIR}/src/dynamics/implicit_contact_holds.cpp
  ${MSM_SIM_DIR}/src/dynamics/implicit_integrator.cpp
  ${MSM_SIM_DIR}/src/dynamics/node_stages.cpp
  ${MSM_SIM_DIR}/src/dynamics/pair_contacts.cpp
  ${MSM_SIM_DIR}/src/dynamics/step_loop.cpp
  ${MSM_SIM_DIR}/src/dynamics/step_rollback.cpp
  ${MSM_SIM_DIR}/src/dynamics/world.cpp
  ${MSM_SIM_DIR}/src/dynamics/world_body.cpp
)
