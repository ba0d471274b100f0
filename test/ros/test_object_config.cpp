// A scene's object keys read without a ROS master (ReadObjects on a parameter tree as getParam
// gives it): the spring law and the fitted power law's tensile_law (docs/physics.md §4.1) on the
// object or its material, the model they build, and one ConfigError naming the key for each bad
// value.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "msm_sim/material/material.h"
#include "object_builder.h"
#include "object_config_reader.h"

namespace msm_sim::ros_interface {
namespace {

using XmlRpc::XmlRpcValue;

// The law `msm_lab fit --tensile` gives for test/data/ecoflex_00_30_tensile.csv (docs/lab.md).
constexpr double kAlpha = -4.54;
constexpr double kBeta = 0.116;

XmlRpcValue TensileLaw(double alpha, double beta) {
  XmlRpcValue law;
  law["alpha"] = alpha;
  law["beta"] = beta;
  law["rms_error"] = 0.0123;  // written by the fit, allowed and ignored
  return law;
}

// A 4 cm cube of 1 cm spacing; its material comes from the test.
XmlRpcValue Cube() {
  XmlRpcValue object;
  object["name"] = std::string("cube");
  object["shape"]["type"] = std::string("box");
  XmlRpcValue size;
  for (int i = 0; i < 3; ++i) size[i] = 0.04;
  object["shape"]["size"] = size;
  object["spacing"] = 0.01;
  return object;
}

XmlRpcValue CubeOfYoungs() {
  XmlRpcValue object = Cube();
  object["youngs"] = 1e5;
  object["poisson"] = 0.45;
  object["density"] = 1070.0;
  return object;
}

// A fitted material entry as `msm_lab fit --tensile` writes it (source included).
XmlRpcValue FittedMaterial() {
  XmlRpcValue material;
  material["youngs"] = 1e5;
  material["poisson"] = 0.45;
  material["density"] = 1070.0;
  material["tensile_law"] = TensileLaw(kAlpha, kBeta);
  material["source"]["tensile_curve"] = std::string("ecoflex_00_30_tensile.csv");
  return material;
}

XmlRpcValue Scene(const XmlRpcValue& object) {
  XmlRpcValue root;
  root["objects"][0] = object;
  root["materials"]["fitted"] = FittedMaterial();
  return root;
}

ObjectConfig ReadOne(const XmlRpcValue& object) {
  XmlRpcValue root = Scene(object);
  return ReadObjects(root, WorldConfig{}).at(0);
}

// ReadObjects's message for the object; fails the test unless it is one ConfigError line.
std::string Error(const XmlRpcValue& object) {
  XmlRpcValue root = Scene(object);
  try {
    ReadObjects(root, WorldConfig{});
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "the object was accepted";
  return "";
}

#define EXPECT_CONTAINS(text, part) EXPECT_NE((text).find(part), std::string::npos) << (text)

TEST(ObjectSpringLaw, LinearByDefaultAndByName) {
  EXPECT_EQ(ReadOne(CubeOfYoungs()).lattice.spring_law, core::SpringLaw::kLinear);
  XmlRpcValue object = CubeOfYoungs();
  object["spring"] = std::string("nonlinear");
  EXPECT_EQ(ReadOne(object).lattice.spring_law, core::SpringLaw::kNonlinear);
}

TEST(ObjectSpringLaw, AnObjectsTensileLawSelectsThePowerLaw) {
  XmlRpcValue object = CubeOfYoungs();
  object["tensile_law"] = TensileLaw(kAlpha, kBeta);
  const ObjectConfig config = ReadOne(object);
  EXPECT_EQ(config.lattice.spring_law, core::SpringLaw::kPower);
  EXPECT_EQ(config.lattice.power_law.alpha, kAlpha);
  EXPECT_EQ(config.lattice.power_law.beta, kBeta);
  object["spring"] = std::string("power");
  EXPECT_EQ(ReadOne(object).lattice.spring_law, core::SpringLaw::kPower);
}

TEST(ObjectSpringLaw, AFittedMaterialsTensileLawSelectsThePowerLaw) {
  XmlRpcValue object = Cube();
  object["material"] = std::string("fitted");
  const ObjectConfig config = ReadOne(object);
  EXPECT_EQ(config.lattice.spring_law, core::SpringLaw::kPower);
  EXPECT_EQ(config.lattice.power_law.alpha, kAlpha);
  EXPECT_EQ(config.lattice.power_law.beta, kBeta);
  // The object's own tensile_law overrides the material's, as youngs does.
  object["tensile_law"] = TensileLaw(-2.0, 0.5);
  EXPECT_EQ(ReadOne(object).lattice.power_law.alpha, -2.0);
  EXPECT_EQ(ReadOne(object).lattice.power_law.beta, 0.5);
}

TEST(ObjectSpringLaw, AnExplicitLawIgnoresTheMaterialsTensileLaw) {
  XmlRpcValue object = Cube();
  object["material"] = std::string("fitted");
  object["spring"] = std::string("linear");
  EXPECT_EQ(ReadOne(object).lattice.spring_law, core::SpringLaw::kLinear);
  object["spring"] = std::string("nonlinear");
  EXPECT_EQ(ReadOne(object).lattice.spring_law, core::SpringLaw::kNonlinear);
}

TEST(ObjectSpringLaw, ThePowerLawReachesTheBuiltModel) {
  XmlRpcValue object = Cube();
  object["material"] = std::string("fitted");
  const ObjectConfig config = ReadOne(object);
  const auto model = BuildObjectModel(
      config, core::Material::FromYoungsPoisson(config.youngs, config.poisson, config.density));
  EXPECT_EQ(model->spring_law(), core::SpringLaw::kPower);
  EXPECT_EQ(model->power_spring_law().alpha, kAlpha);
  EXPECT_EQ(model->power_spring_law().beta, kBeta);
}

TEST(ObjectSpringLaw, BadKeysNameTheParameter) {
  XmlRpcValue object = CubeOfYoungs();
  object["spring"] = std::string("quadratic");
  const std::string unknown = Error(object);
  EXPECT_CONTAINS(unknown, "~objects[0]/spring");
  EXPECT_CONTAINS(unknown, "power");

  object["spring"] = std::string("power");
  const std::string missing = Error(object);
  EXPECT_CONTAINS(missing, "parameter ~objects[0]/spring: power needs tensile_law");

  const auto with_law = [](XmlRpcValue law) {
    XmlRpcValue object = CubeOfYoungs();
    object["tensile_law"] = law;
    return Error(object);
  };
  XmlRpcValue no_beta;
  no_beta["alpha"] = kAlpha;
  EXPECT_CONTAINS(with_law(no_beta), "parameter ~objects[0]/tensile_law/beta: missing");
  EXPECT_CONTAINS(with_law(TensileLaw(kAlpha, -0.1)),
                  "parameter ~objects[0]/tensile_law/beta: must be >= 0");
  EXPECT_CONTAINS(with_law(TensileLaw(std::nan(""), kBeta)),
                  "parameter ~objects[0]/tensile_law/alpha: must be finite");
  XmlRpcValue misspelt = TensileLaw(kAlpha, kBeta);
  misspelt["gamma"] = 1.0;
  EXPECT_CONTAINS(with_law(misspelt), "~objects[0]/tensile_law");
  EXPECT_CONTAINS(with_law(misspelt), "gamma");
  EXPECT_CONTAINS(with_law(1.5), "~objects[0]/tensile_law");

  // The object's own law with another spring law: it would not be used.
  object = CubeOfYoungs();
  object["tensile_law"] = TensileLaw(kAlpha, kBeta);
  object["spring"] = std::string("linear");
  EXPECT_CONTAINS(Error(object), "parameter ~objects[0]/tensile_law: applies to spring: power");
}

TEST(ObjectSpringLaw, AMaterialsBadTensileLawNamesTheMaterial) {
  XmlRpcValue object = Cube();
  object["material"] = std::string("bad");
  XmlRpcValue root = Scene(object);
  root["materials"]["bad"] = FittedMaterial();
  root["materials"]["bad"]["tensile_law"]["beta"] = -1.0;
  try {
    ReadObjects(root, WorldConfig{});
    ADD_FAILURE() << "the material was accepted";
  } catch (const ConfigError& e) {
    EXPECT_CONTAINS(std::string(e.what()), "parameter ~materials/bad/tensile_law/beta");
  }
}

// objects[]/mass_scaling (docs/physics.md §7 "Selective mass scaling"): 1 % unless asked for, 0
// turns it off, and outside [0, 0.1] the object is refused with one line naming the key.
TEST(ObjectMassScaling, ReadWithItsDefaultAndRefusedOutOfRange) {
  EXPECT_EQ(ReadOne(CubeOfYoungs()).surface.mass_scaling, 0.01);
  XmlRpcValue object = CubeOfYoungs();
  object["mass_scaling"] = 0.0;
  EXPECT_EQ(ReadOne(object).surface.mass_scaling, 0.0);
  for (const double bad : {-0.01, 0.5}) {
    object["mass_scaling"] = bad;
    EXPECT_CONTAINS(Error(object), "parameter ~objects[0]/mass_scaling: must lie in [0, 0.1]");
  }
  object["mass_scaling"] = std::nan("");
  EXPECT_CONTAINS(Error(object), "parameter ~objects[0]/mass_scaling: must be finite");
}

}  // namespace
}  // namespace msm_sim::ros_interface
