// Speed against quality: the Pareto front of configurations and the equal-quality
// speedup read along two fronts.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace fov {

// Indices of the rows on the Pareto front of (x, y), both to be minimised: no other row
// is at least as good in both and better in one. Sorted by x. Rows with NaN are skipped.
std::vector<size_t> pareto_front(const std::vector<double>& x, const std::vector<double>& y);

// Equal-error speedup: along two Pareto fronts of (time, error) points, the baseline's
// time over the foveated one's at the same error, log-time interpolated linearly in error
// between front points; NaN outside either front's error range.
double time_at_error(const std::vector<std::pair<double, double>>& front, double error);
double equal_error_speedup(const std::vector<std::pair<double, double>>& foveated,
                           const std::vector<std::pair<double, double>>& baseline, double error);

}  // namespace fov
