#pragma once
// The persistent merge-confidence matrix Psi of section III, sparse. Every frame, each pair of map
// labels that falls into one current segment gains one; each pair whose labels are both in view
// but in different segments loses one (clamped at 0, and dropped at 0, so Psi holds only pairs
// with standing evidence: its size is bounded by the pairs seen together lately). A pair above
// merge_threshold is merged into the smaller label. Pairs of labels that disappear (merged,
// remapped) are renamed or dropped with them.

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace rasm::segmentation {

class MergeConfidence {
 public:
  using Pair = std::pair<std::uint32_t, std::uint32_t>;  ///< (a, b), a < b

  /// One frame: `cosegmented` pairs (a < b, sorted) gain, other pairs of `visible` labels
  /// (sorted) lose. Returns the pairs over `threshold` (to merge; a < b).
  std::vector<Pair> update(const std::vector<Pair>& cosegmented,
                           const std::vector<std::uint32_t>& visible, int threshold);
  /// Label `from` became `to` (a merge or a remap): its pairs follow (a pair with itself is
  /// dropped; evidence of two pairs that become one is summed).
  void rename(std::uint32_t from, std::uint32_t to);
  /// A general renaming, new = table[old] (0 = the label is gone).
  void remap(const std::vector<std::uint32_t>& table);

  std::size_t size() const { return m_psi.size(); }
  int confidence(std::uint32_t a, std::uint32_t b) const;

 private:
  static std::uint64_t key(std::uint32_t a, std::uint32_t b) {
    if (a > b) std::swap(a, b);
    return (std::uint64_t(a) << 32) | b;
  }
  std::unordered_map<std::uint64_t, int> m_psi;
};

/// The merge of section III: the labels of `due` (pairs over the threshold) joined by union-find,
/// each connected set into its smallest label. Returns the relabelling table, new = table[old],
/// over labels 0..max label of `due` (labels beyond it keep their id), and the number of unions
/// made in `merges` (pairs already joined through others count once).
std::vector<std::uint32_t> mergeTable(const std::vector<MergeConfidence::Pair>& due, int& merges);

}  // namespace rasm::segmentation
