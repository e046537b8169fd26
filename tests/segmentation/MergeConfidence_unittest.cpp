// Section III's merge evidence Psi and the merge itself, on hand-made label pairs.
#include "rasm/segmentation/MergeConfidence.h"

#include <gtest/gtest.h>

using namespace rasm::segmentation;

TEST(MergeConfidence, SharedSegmentsGainApartInViewLoseAndThePairOverTheThresholdIsDue) {
  MergeConfidence psi;
  // Labels 3 and 7 fall into one segment in three frames; 3 and 9 are in view but apart.
  for (int f = 0; f < 3; ++f) {
    const auto due = psi.update({{3, 7}}, {3, 7, 9}, 3);
    EXPECT_TRUE(due.empty()) << "frame " << f << ": 3 frames reach the threshold, not exceed it";
  }
  EXPECT_EQ(psi.confidence(3, 7), 3);
  EXPECT_EQ(psi.confidence(7, 3), 3);
  EXPECT_EQ(psi.confidence(3, 9), 0) << "never together: no evidence";
  const auto due = psi.update({{3, 7}}, {3, 7}, 3);
  ASSERT_EQ(due.size(), 1u);
  EXPECT_EQ(due[0], MergeConfidence::Pair(3, 7));
  // Both in view, apart: the evidence falls again.
  psi.update({}, {3, 7}, 3);
  EXPECT_EQ(psi.confidence(3, 7), 3);
}

TEST(MergeConfidence, RenamedLabelsCarryTheirEvidence) {
  MergeConfidence psi;
  psi.update({{2, 5}, {4, 5}}, {2, 4, 5}, 10);
  psi.rename(4, 2);  // 4 merged into 2: (4, 5) becomes (2, 5), the evidence sums
  EXPECT_EQ(psi.confidence(2, 5), 2);
  EXPECT_EQ(psi.size(), 1u);
  psi.remap({0, 0, 1, 0, 0, 2});  // 2 -> 1, 5 -> 2
  EXPECT_EQ(psi.confidence(1, 2), 2);
  psi.remap({0, 0, 0});  // both gone
  EXPECT_EQ(psi.size(), 0u);
}

TEST(MergeTable, ChainsJoinIntoTheirSmallestLabelAndUnionsCountOnce) {
  int merges = -1;
  // 8-3 and 3-6 chain into one set {3, 6, 8}; 5-2 is another; 6-8 is already joined.
  const std::vector<std::uint32_t> t = mergeTable({{3, 8}, {3, 6}, {2, 5}, {6, 8}}, merges);
  ASSERT_EQ(t.size(), 9u);
  EXPECT_EQ(merges, 3);
  for (std::uint32_t l : {3u, 6u, 8u}) EXPECT_EQ(t[l], 3u) << l;
  EXPECT_EQ(t[5], 2u);
  EXPECT_EQ(t[2], 2u);
  for (std::uint32_t l : {0u, 1u, 4u, 7u}) EXPECT_EQ(t[l], l) << "untouched label " << l;
  EXPECT_TRUE(mergeTable({}, merges).size() == 1 && merges == 0);
}
