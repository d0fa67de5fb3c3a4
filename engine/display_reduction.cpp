#include "engine/display_reduction.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace napkin::engine {

std::vector<Eigen::Index> PeakPreservingSamples(const Eigen::Ref<const Eigen::MatrixXd>& traces,
                                                Eigen::Index max_points) {
  const Eigen::Index n = traces.rows();
  const Eigen::Index trace_count = std::max<Eigen::Index>(traces.cols(), 1);
  if (max_points < 2 * trace_count + 2)
    throw std::invalid_argument("PeakPreservingSamples: max_points " + std::to_string(max_points) +
                                " cannot hold one bucket of " + std::to_string(trace_count) + " traces");
  std::vector<Eigen::Index> kept;
  if (n <= max_points) {
    kept.resize(static_cast<std::size_t>(n));
    std::iota(kept.begin(), kept.end(), Eigen::Index{0});
    return kept;
  }
  const Eigen::Index bucket_count = (max_points - 2) / (2 * trace_count);
  kept.reserve(static_cast<std::size_t>(2 * trace_count * bucket_count + 2));
  kept.push_back(0);
  for (Eigen::Index bucket = 0; bucket < bucket_count; ++bucket) {
    const Eigen::Index begin = bucket * n / bucket_count;
    const Eigen::Index end = (bucket + 1) * n / bucket_count;
    for (Eigen::Index trace = 0; trace < traces.cols(); ++trace) {
      Eigen::Index lowest = begin;
      Eigen::Index highest = begin;
      for (Eigen::Index row = begin + 1; row < end; ++row) {
        const double value = traces(row, trace);
        if (value < traces(lowest, trace)) lowest = row;
        if (value > traces(highest, trace)) highest = row;
      }
      kept.push_back(lowest);
      kept.push_back(highest);
    }
  }
  kept.push_back(n - 1);
  std::sort(kept.begin(), kept.end());
  kept.erase(std::unique(kept.begin(), kept.end()), kept.end());
  return kept;
}

}  // namespace napkin::engine
