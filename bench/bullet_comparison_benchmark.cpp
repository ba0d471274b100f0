// Google Benchmark: one explicit msm_sim step against one step of Bullet's btSoftBody (Debian
// libbullet-dev, single precision, the legacy btSoftRigidDynamicsWorld pipeline) on the identical
// lattice (issue "Real time at real resolution": the 12k-node step <= 0.3 ms and >= 10x Bullet).
//
// The lattice is the 12k-node block of bench/dynamics_benchmark.cpp: 0.4 x 0.2 x 0.15 m at
// a = 1 cm, node-centred cubic A+B lattice, E = 100 kPa, nu = 0.45, rho = 1100 kg/m^3, resting
// on the ground. Both engines get it from the same msm_sim Model: the same node positions and
// masses, one Bullet link per msm_sim spring between the same node pair, gravity -9.81 m/s^2
// along z, the same fixed step (msm_sim's stable step), ground contact at the same height, and
// 200 settling steps before timing. What each side does per timed step:
//
// msm_sim (World::Step at the stable step: exactly one substep):
//   - eMSM spring forces, two-pass dispersion (nu = 0.45), with spring dampers c = beta k,
//     beta = 1e-4 s, in single precision (the World's default, as Bullet's soft body) or double
//     (the "single" argument); gravity;
//   - position Verlet (half drift, kick, half drift);
//   - microcollisions of every border node (its collision sphere, radius = mean half spring
//     length) against the ground plane, with Coulomb friction, restitution and 8 Gauss-Seidel
//     contact sweeps; the step's sanity check (speeds, finiteness) and saved state for rollback.
//   Threads: the spring passes may use 2 (World::SetThreads, the worker pool), so msm_sim is
//   timed with 1 and with 2 threads (the "threads" argument); Bullet's soft body is
//   single-threaded.
//
// Bullet (btSoftRigidDynamicsWorld::stepSimulation(dt, 0): exactly one internal step of dt):
//   - the rigid world's step (broadphase pair soft body / ground, narrowphase, which runs the
//     soft body's collision handler; the static ground does not move);
//   - btSoftBody::predictMotion: gravity, explicit velocity and position update of every node,
//     the update of the node bounding-volume tree;
//   - collision detection with its own method, fCollision::SDF_RS (the default): the nodes whose
//     leaf in the node tree overlaps the ground's bounding box (here the bottom layer) are
//     looked up in Bullet's sparse signed distance field of the ground (cells of 0.25 m voxels,
//     trilinear) and become contacts when closer than the soft body's margin;
//   - btSoftBody::solveConstraints with Bullet's default iteration counts: piterations = 1
//     position iteration (each over anchors, rigid contacts, soft contacts and the links, a
//     Gauss-Seidel projection of each link's length), viterations = 0, diterations = 0; the
//     velocities are then (x - x_prev) / dt; no damping (kDP = 0, Bullet's default).
//   Link stiffness: Bullet's links are position-based constraints, not springs. A link's
//   material kLST in (0, 1] is the fraction of its length error removed per iteration, and the
//   solver iterates m_cfg.piterations times per step, so the resulting stiffness depends on dt
//   and the iteration count and is not calibrated the way msm_sim's springs are (nor does Bullet
//   have the eMSM dispersion, the dampers or msm_sim's restitution). We map each spring's k
//   (N/m) as XPBD does for one iteration: with w = 1/m_a + 1/m_b and compliance 1/(k dt^2),
//   kLST = w k dt^2 / (1 + w k dt^2), one Bullet material per distinct value.
//   Ground: Bullet's SDF_RS collision samples the distance to convex shapes only; its sparse
//   SDF returns 0 everywhere for a btStaticPlaneShape (non-convex), so every node tested is a
//   contact with an arbitrary normal (checked: a block on one drifts off it and never rests).
//   The ground is therefore a static btBoxShape 20 m x 20 m x 2 m whose top face is the plane
//   at msm_sim's ground height, with zero margin (its sampled face is then exactly there). Bullet
//   has one collision margin for all nodes of a soft body (its default is 0.25 m); we set it to the
//   distance between the bottom layer of nodes and msm_sim's ground, i.e. the largest collision
//   radius of msm_sim's bottom layer, so both bodies start just touching. Friction: Bullet's kDF
//   times the ground's friction, set to 1 x 0.5 = msm_sim's default coefficient 0.5.
//
// Counters: nodes, springs, dt_us (the step), ground_contacts (msm_sim: microcollisions of the
// last step; Bullet: its rigid contacts), for Bullet links, piterations, materials and the range
// of kLST; top_drop_mm, the mean drop of the top layer below its rest height after the run: a
// plausibility check that each block rests on the ground and carries its weight (a snapshot of
// a lightly damped oscillation: msm_sim's block oscillates about 0.9 mm, Bullet's sits at 1.6).
//
// Run (defaults added by main below: 5 repetitions, randomly interleaved so that both engines
// see the same machine load): msm_sim_bullet_benchmark [--benchmark_repetitions=N]
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include "msm_sim/dynamics/world.h"
#include "msm_sim/lattice/cubic_lattice_builder.h"

namespace msm_sim::core {
namespace {

constexpr int kSettleSteps = 200;
constexpr double kGravity = -9.81;  // m/s^2, along z (msm_sim's default)
constexpr double kDampingBeta = 1e-4;

// The lattice of BM_DynamicsStep12k (bench/dynamics_benchmark.cpp), built once for both sides.
std::shared_ptr<const Model> Lattice12k() {
  static const std::shared_ptr<const Model> model = [] {
    CubicLatticeOptions lattice_options;
    lattice_options.size = Eigen::Vector3d(0.4, 0.2, 0.15);
    lattice_options.lattice.spacing = 0.01;
    return std::make_shared<const Model>(
        BuildCubicLattice(Material::FromYoungsPoisson(1e5, 0.45, 1100.0), lattice_options));
  }();
  return model;
}

// Mean drop (m) of the nodes of the top layer from their rest height.
double TopLayerDrop(const Eigen::Matrix3Xd& rest, const std::vector<double>& z_now) {
  const double top = rest.row(2).maxCoeff();
  double drop = 0.0;
  int count = 0;
  for (Eigen::Index i = 0; i < rest.cols(); ++i) {
    if (rest(2, i) > top - 1e-9) {
      drop += rest(2, i) - z_now[i];
      ++count;
    }
  }
  return drop / count;
}

// msm_sim exactly as in BM_DynamicsStep12k, settled once per spring precision and kept for
// every repetition. The spring passes' threads are set per benchmark (World::SetThreads: 1 or
// 2), as the README's figures were measured; a World's default is one.
WorldOptions WorldWith(SpringPrecision precision) {
  WorldOptions options;
  options.spring_precision = precision;
  return options;
}

struct MsmScene {
  explicit MsmScene(SpringPrecision precision) : model(Lattice12k()), world(WorldWith(precision)) {
    BodyOptions options;
    options.damping_beta = kDampingBeta;
    body = world.AddBody("block", model, options);
    const Collider ground = GroundTouching(model->rest_positions(), world.border(body));
    ground_height = ground.pose.translation().z();
    world.AddCollider(ground);
    step = world.stable_time_step();
    for (int settle = 0; settle < kSettleSteps; ++settle) world.Step(step);  // in contact, loaded
  }
  std::shared_ptr<const Model> model;
  World world;
  int body = 0;
  double ground_height = 0.0;  // m
  double step = 0.0;           // s
};

MsmScene& Msm(SpringPrecision precision = SpringPrecision::kSingle) {
  static MsmScene single(SpringPrecision::kSingle);
  static MsmScene exact(SpringPrecision::kDouble);
  return precision == SpringPrecision::kSingle ? single : exact;
}

// Bullet's soft body on the same nodes, springs, masses, step, gravity and ground, settled once.
class BulletScene {
 public:
  BulletScene() {
    const MsmScene& msm = Msm();
    const Model& model = *msm.model;
    step = msm.step;
    world_ = std::make_unique<btSoftRigidDynamicsWorld>(&dispatcher_, &broadphase_, &solver_,
                                                        &configuration_, &soft_solver_);
    const btVector3 gravity(0, 0, static_cast<btScalar>(kGravity));
    world_->setGravity(gravity);
    world_->getWorldInfo().m_gravity = gravity;  // soft bodies read their own copy
    AddGround(model.rest_positions(), msm.ground_height);
    AddNodes(model);
    AppendLinks(model);
    FitMargin(model.rest_positions(), msm.ground_height);
    body_->m_cfg.kDF = 1;  // x the ground's 0.5 = msm_sim's default friction coefficient
    // Bullet's defaults, stated: collisions = SDF_RS, piterations = 1, viterations = 0.
    world_->addSoftBody(body_.get());

    for (int settle = 0; settle < kSettleSteps; ++settle) Step();
  }
  BulletScene(const BulletScene&) = delete;
  BulletScene& operator=(const BulletScene&) = delete;
  ~BulletScene() {
    world_->removeSoftBody(body_.get());
    world_->removeRigidBody(ground_.get());
  }

  void Step() { world_->stepSimulation(static_cast<btScalar>(step), 0); }
  const btSoftBody& body() const { return *body_; }

  double step = 0.0;  // s
  int num_materials = 0;
  // Bullet takes a link's rest length from its nodes' distance at the first step; msm_sim's L0
  // of a cubic lattice is that distance too.
  bool same_rest_lengths = true;
  btScalar k_lst_min = 0, k_lst_max = 0;

 private:
  // The ground: a static box whose top face is msm_sim's ground plane (see the header).
  void AddGround(const Eigen::Matrix3Xd& x, double ground_height) {
    constexpr double kHalfExtent = 10.0, kHalfThickness = 1.0;
    ground_shape_ =
        std::make_unique<btBoxShape>(btVector3(kHalfExtent, kHalfExtent, kHalfThickness));
    ground_shape_->setMargin(0);
    btTransform ground_pose;
    ground_pose.setIdentity();
    ground_pose.setOrigin(btVector3(static_cast<btScalar>(x.row(0).mean()),
                                    static_cast<btScalar>(x.row(1).mean()),
                                    static_cast<btScalar>(ground_height - kHalfThickness)));
    btRigidBody::btRigidBodyConstructionInfo ground_info(0, nullptr, ground_shape_.get());
    ground_info.m_startWorldTransform = ground_pose;
    ground_info.m_friction = 0.5;
    ground_ = std::make_unique<btRigidBody>(ground_info);
    world_->addRigidBody(ground_.get());
  }

  // The soft body: nodes at the model's rest positions, with its masses.
  void AddNodes(const Model& model) {
    const Eigen::Matrix3Xd& x = model.rest_positions();
    std::vector<btVector3> positions(model.num_nodes());
    for (int i = 0; i < model.num_nodes(); ++i) {
      positions[i] = btVector3(static_cast<btScalar>(x(0, i)), static_cast<btScalar>(x(1, i)),
                               static_cast<btScalar>(x(2, i)));
    }
    body_ = std::make_unique<btSoftBody>(&world_->getWorldInfo(), model.num_nodes(),
                                         positions.data(), nullptr);
    for (int i = 0; i < model.num_nodes(); ++i) {
      body_->setMass(i, static_cast<btScalar>(model.masses()[i]));
    }
  }

  // One link per spring, its kLST mapped from k as the header says; one material per kLST.
  void AppendLinks(const Model& model) {
    const Eigen::Matrix3Xd& x = model.rest_positions();
    const Eigen::VectorXd& m = model.masses();
    std::map<btScalar, btSoftBody::Material*> materials;
    for (int s = 0; s < model.num_springs(); ++s) {
      const int a = model.spring_node_a()[s], b = model.spring_node_b()[s];
      const double w = 1.0 / m[a] + 1.0 / m[b];
      const double stiffness = w * model.spring_stiffness()[s] * step * step;
      const btScalar k_lst = static_cast<btScalar>(stiffness / (1.0 + stiffness));
      btSoftBody::Material*& material = materials[k_lst];
      if (material == nullptr) {
        material = body_->appendMaterial();
        material->m_kLST = k_lst;
      }
      body_->appendLink(a, b, material);
      const double distance = (x.col(b) - x.col(a)).norm();
      const double rest_length = model.spring_rest_length()[s];
      if (std::abs(distance - rest_length) > 1e-9 * rest_length) same_rest_lengths = false;
    }
    num_materials = static_cast<int>(materials.size());
    k_lst_min = materials.begin()->first;
    k_lst_max = materials.rbegin()->first;
  }

  // One margin for all nodes: the bottom layer rests at msm_sim's largest bottom radius. The
  // constructor put every node in the node tree with the default margin (0.25 m), and Bullet
  // only refits a leaf that no longer contains its node's volume: with leaves that fat, every
  // node of the block would be tested against the ground at every step. Rebuild the tree.
  void FitMargin(const Eigen::Matrix3Xd& x, double ground_height) {
    const btScalar margin = static_cast<btScalar>(x.row(2).minCoeff() - ground_height);
    body_->getCollisionShape()->setMargin(margin);
    body_->m_ndbvt.clear();
    for (int i = 0; i < body_->m_nodes.size(); ++i) {
      btSoftBody::Node& node = body_->m_nodes[i];
      node.m_leaf = body_->m_ndbvt.insert(btDbvtVolume::FromCR(node.m_x, margin), &node);
    }
  }

  btSoftBodyRigidBodyCollisionConfiguration configuration_;
  btCollisionDispatcher dispatcher_{&configuration_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDefaultSoftBodySolver soft_solver_;
  std::unique_ptr<btSoftRigidDynamicsWorld> world_;
  std::unique_ptr<btBoxShape> ground_shape_;
  std::unique_ptr<btRigidBody> ground_;
  std::unique_ptr<btSoftBody> body_;
};

BulletScene& Bullet() {
  static BulletScene scene;
  return scene;
}

void BM_MsmSimStep12k(benchmark::State& state) {
  MsmScene& scene = Msm(state.range(1) == 1 ? SpringPrecision::kSingle : SpringPrecision::kDouble);
  scene.world.SetThreads(static_cast<int>(state.range(0)));
  int contacts = 0;
  for (auto _ : state) {
    const StepReport report = scene.world.Step(scene.step);
    contacts = report.microcollisions;
    benchmark::DoNotOptimize(report.accepted);
  }
  const Eigen::Matrix3Xd& x = scene.world.state(scene.body).positions;
  std::vector<double> z(x.cols());
  for (Eigen::Index i = 0; i < x.cols(); ++i) z[i] = x(2, i);
  state.counters["nodes"] = scene.model->num_nodes();
  state.counters["springs"] = scene.model->num_springs();
  state.counters["ground_contacts"] = contacts;
  state.counters["dt_us"] = scene.step * 1e6;
  state.counters["top_drop_mm"] = 1e3 * TopLayerDrop(scene.model->rest_positions(), z);
}
BENCHMARK(BM_MsmSimStep12k)
    ->ArgNames({"threads", "single"})
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(2.0)
    ->UseRealTime();

void BM_BulletSoftBodyStep12k(benchmark::State& state) {
  BulletScene& scene = Bullet();
  for (auto _ : state) {
    scene.Step();
    benchmark::ClobberMemory();
  }
  const btSoftBody& body = scene.body();
  const Model& model = *Msm().model;
  std::vector<double> z(body.m_nodes.size());
  double lowest = INFINITY;
  for (int i = 0; i < body.m_nodes.size(); ++i) {
    z[i] = body.m_nodes[i].m_x.z();
    lowest = std::min(lowest, z[i]);
  }
  // The comparison only holds while the block rests on the ground (not through it, not off it).
  const double gap = lowest - Msm().ground_height;
  if (body.m_rcontacts.size() == 0 || gap < 0.0 || gap > model.characteristic_length()) {
    state.SkipWithError("Bullet's block does not rest on the ground");
  }
  if (!scene.same_rest_lengths) state.SkipWithError("a spring's L0 differs from its rest distance");
  state.counters["nodes"] = body.m_nodes.size();
  state.counters["springs"] = model.num_springs();
  state.counters["links"] = body.m_links.size();
  state.counters["ground_contacts"] = body.m_rcontacts.size();
  state.counters["dt_us"] = scene.step * 1e6;
  state.counters["piterations"] = body.m_cfg.piterations;
  state.counters["materials"] = scene.num_materials;
  state.counters["kLST_min"] = scene.k_lst_min;
  state.counters["kLST_max"] = scene.k_lst_max;
  state.counters["top_drop_mm"] = 1e3 * TopLayerDrop(model.rest_positions(), z);
}
BENCHMARK(BM_BulletSoftBodyStep12k)->Unit(benchmark::kMicrosecond)->MinTime(2.0)->UseRealTime();

}  // namespace
}  // namespace msm_sim::core

// BENCHMARK_MAIN with two defaults put before the caller's flags (a later flag wins):
// 5 repetitions, randomly interleaved across the benchmarks, each repetition listed besides
// the mean, median, standard deviation and coefficient of variation.
int main(int argc, char** argv) {
  std::vector<std::string> defaults = {"--benchmark_repetitions=5",
                                       "--benchmark_enable_random_interleaving=true"};
  std::vector<char*> args = {argv[0]};
  for (std::string& flag : defaults) args.push_back(flag.data());
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  int count = static_cast<int>(args.size());
  args.push_back(nullptr);
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
