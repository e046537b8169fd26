#pragma once
// Timestamp association of the TUM RGB-D tools (associate.py, Sturm et al. 2012): candidate pairs
// (a, b) with |t_a - (t_b + offset)| < max_dt, taken greedily by increasing |dt|, each stamp used
// at most once, the result sorted by t_a. Candidates are enumerated over a sliding window of the
// sorted stamps, so the cost is O(n log n + pairs) instead of the script's O(n m).

#include <cstddef>
#include <utility>
#include <vector>

namespace rasm::io {

/// Indices (i into a, j into b) of associated stamps, sorted by a[i]. `a` and `b` need not be
/// sorted.
std::vector<std::pair<std::size_t, std::size_t>> associateTimestamps(const std::vector<double>& a,
                                                                     const std::vector<double>& b,
                                                                     double max_dt_s = 0.02,
                                                                     double offset_s = 0.0);

/// Index of the element of the sorted `stamps` closest to t (ties: the earlier). stamps must not
/// be empty.
std::size_t closestIndex(const std::vector<double>& sorted_stamps, double t);

}  // namespace rasm::io
