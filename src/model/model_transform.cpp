#include "msm_sim/model/model_transform.h"

#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {

namespace {

// `model` rebuilt with its rest positions moved by `pose` and its springs following `law`.
Model Rebuilt(const Model& model, const Eigen::Isometry3d& pose, SpringLaw law,
              const PowerSpringLaw& power) {
  ModelBuilder builder(model.material());
  builder.SetSpringLaw(law, power);
  builder.SetDispersionFraction(model.dispersion_fraction());
  builder.SetSelfCalibration(model.self_calibration());
  builder.SetMassScaling(model.added_mass(), model.mass_scaling_limited());
  for (NodeIndex i = 0; i < model.num_nodes(); ++i) {
    builder.AddNode(pose * Eigen::Vector3d(model.rest_positions().col(i)), model.masses()[i],
                    model.surface_insets()[i]);
  }
  for (SpringIndex s = 0; s < model.num_springs(); ++s) {
    const NodeIndex a = model.spring_node_a()[s];
    const NodeIndex b = model.spring_node_b()[s];
    builder.AddSpring(a, b, model.spring_stiffness()[s]);
    builder.SetDispersionWeight(s, a, model.dispersion_weight_a()[s]);
    builder.SetDispersionWeight(s, b, model.dispersion_weight_b()[s]);
  }
  for (std::size_t e = 0; e < model.correction_edges().size(); ++e) {
    builder.AddCorrectionElement(model.correction_edges()[e], model.correction_coefficients()[e]);
  }
  return builder.Build(model.volume(), model.characteristic_length());
}

}  // namespace

Model TransformedModel(const Model& model, const Eigen::Isometry3d& pose) {
  return Rebuilt(model, pose, model.spring_law(), model.power_spring_law());
}

Model WithSpringLaw(const Model& model, SpringLaw law, const PowerSpringLaw& power) {
  return Rebuilt(model, Eigen::Isometry3d::Identity(), law, power);
}

}  // namespace msm_sim::core
