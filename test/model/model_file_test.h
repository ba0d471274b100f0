#pragma once
// The model-file tests' fixture and models (test_model_file.cpp, test_vtk_export.cpp): a cubic
// eMSM and a Baudet lattice, bit-for-bit comparisons, and a temporary directory whose LoadModel
// messages must name the file.
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "model_file_bytes.h"
#include "msm_sim/lattice/baudet_lattice_builder.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"
#include "msm_sim/model/model.h"

namespace msm_sim::core {

inline Model CubicModel() {
  CubicLatticeOptions options;
  options.size = Eigen::Vector3d(0.4, 0.3, 0.3);
  options.lattice.spacing = 0.1;
  return BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1000.0), options);
}

inline Model BaudetModel(double size = 0.3) {
  BaudetLatticeOptions options;
  options.size = Eigen::Vector3d(size, size, size);
  options.lattice.spacing = 0.1;
  options.lattice.spring_law = SpringLaw::kNonlinear;
  return BuildBaudetLattice(Material::FromYoungsPoisson(1e5, 0.4, 1100.0), options);
}

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

template <typename Derived>
bool SameBits(const Eigen::DenseBase<Derived>& a, const Eigen::DenseBase<Derived>& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.derived().data(), b.derived().data(), a.size() * sizeof(double)) == 0;
}

inline bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

class ModelFileTest : public ModelFileDirectoryTest {
 protected:
  // LoadModel's one-line message for `bytes`, which names the file.
  std::string LoadError(const Bytes& bytes) {
    const std::string message = ModelFileDirectoryTest::LoadError(bytes);
    EXPECT_NE(message.find(Path("edited.msm")), std::string::npos) << message;
    return message;
  }
};

}  // namespace msm_sim::core
