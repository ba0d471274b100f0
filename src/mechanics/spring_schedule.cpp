#include "mechanics/spring_schedule.h"

#include <algorithm>
#include <numeric>
#include <utility>

namespace msm_sim::core {

SpringSchedule ScheduleSprings(const Model& model) {
  const int count = model.num_springs();
  std::vector<NodeIndex> a(model.spring_node_a()), b(model.spring_node_b());
  SpringSchedule schedule;
  schedule.swapped.assign(count, 0);
  for (int s = 0; s < count; ++s) {
    if (a[s] > b[s]) {
      std::swap(a[s], b[s]);
      schedule.swapped[s] = 1;
    }
  }
  std::vector<SpringIndex> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](SpringIndex i, SpringIndex j) {
    const int di = b[i] - a[i], dj = b[j] - a[j];
    return di != dj ? di < dj : a[i] < a[j];
  });
  std::vector<char> swapped(count);
  for (int p = 0; p < count; ++p) swapped[p] = schedule.swapped[order[p]];
  schedule.swapped = std::move(swapped);
  for (int first = 0; first < count;) {
    const SpringIndex s = order[first];
    const int offset = b[s] - a[s];
    int end = first + 1;
    while (end < count && end - first < SpringSchedule::kMaxRunLength &&
           b[order[end]] - a[order[end]] == offset && a[order[end]] == a[order[end - 1]] + 1) {
      ++end;
    }
    schedule.runs.push_back({first, a[s], offset, end - first});
    first = end;
  }
  schedule.model_index = std::move(order);
  return schedule;
}

std::vector<double> SpringSchedule::ToSchedule(const double* model_order) const {
  std::vector<double> scheduled(model_index.size());
  for (std::size_t p = 0; p < model_index.size(); ++p) scheduled[p] = model_order[model_index[p]];
  return scheduled;
}

std::vector<double> SpringSchedule::ToScheduleEnd(const double* end_a, const double* end_b) const {
  std::vector<double> scheduled(model_index.size());
  for (std::size_t p = 0; p < model_index.size(); ++p) {
    scheduled[p] = swapped[p] ? end_b[model_index[p]] : end_a[model_index[p]];
  }
  return scheduled;
}

}  // namespace msm_sim::core
