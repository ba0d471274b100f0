#include "mechanics/node_shares.h"

#include "mechanics/share_plan.h"
#include "mechanics/single_pipeline.h"

namespace msm_sim::core::internal {

void NodeShares::SetForces(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& positions,
                           const Eigen::Matrix3Xd& velocities, double damping_beta,
                           Eigen::Matrix3Xd* forces, const NodeStages& stages) {
  if (!Rounds(*evaluator)) {
    const int n = evaluator->model().num_nodes();
    stages.before(0, 0, n);
    evaluator->SetForces(positions, velocities, damping_beta, forces);
    stages.after(0, 0, n);
    return;
  }
  evaluator->single_loops_.stages = &stages;
  evaluator->SetForces(positions, velocities, damping_beta, forces);
  evaluator->single_loops_.stages = nullptr;
}

void NodeShares::ForEach(ForceEvaluator* evaluator,
                         const std::function<void(int, int, int)>& task) {
  const int count = Count(*evaluator);
  SharePlan::Run(count, [&](int t) {
    const SingleShare share = evaluator->plan_->NodeShare(t, count);
    task(t, share.begin, share.end);
  });
}

int NodeShares::Count(const ForceEvaluator& evaluator) {
  return Rounds(evaluator) ? evaluator.plan_->NodeShareCount() : 1;
}

void NodeShares::Cut(ForceEvaluator* evaluator, const std::vector<NodeIndex>& busy,
                     double busy_work) {
  // The overflows move with the shares: nothing taken ahead holds.
  if (evaluator->plan_->Cut(busy, busy_work)) evaluator->single_loops_.passes->ForgetAhead();
}

bool NodeShares::Rounds(const ForceEvaluator& evaluator) { return evaluator.UsesSingleLoops(); }

void NodeShares::Round(ForceEvaluator* evaluator, const Eigen::Matrix3Xd& positions,
                       const Eigen::Matrix3Xd* velocities, int begin, int end,
                       const double origin[3]) {
  evaluator->single_loops_.passes->Round(*evaluator->single_loops_.springs, positions.data(),
                                         velocities != nullptr ? velocities->data() : nullptr,
                                         begin, end, origin);
}

}  // namespace msm_sim::core::internal
