#pragma once
// The body recipe tests' material and box, and the field-by-field comparison of a recipe's model
// with a builder's (test_body_recipe.cpp, test_body_recipe_limits.cpp).
#include <memory>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "msm_sim/geometry/mesh_primitives.h"
#include "msm_sim/geometry/solid_mesh.h"
#include "msm_sim/material/material.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

const Material kMaterial = Material::FromYoungsPoisson(1e5, 0.3, 1000.0);
const Eigen::Vector3d kBox(0.6, 0.4, 0.3);

// Field by field, exactly: the recipe must call the builder with the same options, not similar.
inline void ExpectSameModel(const Model& actual, const Model& expected) {
  ASSERT_EQ(actual.num_nodes(), expected.num_nodes());
  ASSERT_EQ(actual.num_springs(), expected.num_springs());
  EXPECT_TRUE(actual.rest_positions() == expected.rest_positions());
  EXPECT_TRUE(actual.masses() == expected.masses());
  EXPECT_EQ(actual.spring_node_a(), expected.spring_node_a());
  EXPECT_EQ(actual.spring_node_b(), expected.spring_node_b());
  EXPECT_EQ(actual.spring_rest_length(), expected.spring_rest_length());
  EXPECT_EQ(actual.spring_stiffness(), expected.spring_stiffness());
  EXPECT_EQ(actual.dispersion_weight_a(), expected.dispersion_weight_a());
  EXPECT_EQ(actual.dispersion_weight_b(), expected.dispersion_weight_b());
  EXPECT_EQ(actual.correction_edges(), expected.correction_edges());
  EXPECT_EQ(actual.correction_coefficients(), expected.correction_coefficients());
  EXPECT_EQ(actual.incidence_offsets(), expected.incidence_offsets());
  EXPECT_EQ(actual.incident_springs(), expected.incident_springs());
  EXPECT_EQ(actual.spring_law(), expected.spring_law());
  EXPECT_EQ(actual.dispersion_fraction(), expected.dispersion_fraction());
  EXPECT_EQ(actual.volume(), expected.volume());
  EXPECT_EQ(actual.characteristic_length(), expected.characteristic_length());
  EXPECT_EQ(actual.material().youngs_modulus(), expected.material().youngs_modulus());
  EXPECT_EQ(actual.material().poisson_ratio(), expected.material().poisson_ratio());
  EXPECT_EQ(actual.material().density(), expected.material().density());
}

inline std::shared_ptr<const SolidMesh> BoxSolid(const Eigen::Vector3d& size) {
  return std::make_shared<const SolidMesh>(MakeBoxMesh(size));
}

}  // namespace msm_sim::core
