// Class evidence (IV) as clamped fixed-point log-odds in four slots (ClassEvidence.h): the Bayes
// update against the paper's formula in double precision, the clamp, the slot rule, the best
// class, the store-level update and the memory per surfel.

#include "rasm/surfel_map/ClassEvidence.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "rasm/surfel_map/SurfelStore.h"

using namespace rasm;
using namespace rasm::maps;

namespace {

/// The paper's update (IV): p <- p_d p / (p_d p + (1 - p_d)(1 - p)), in double precision.
double bayes(double p, double p_d) {
  return p_d * p / (p_d * p + (1.0 - p_d) * (1.0 - p));
}
double logit(double p) {
  return std::log(p / (1.0 - p));
}

/// Per-update bound of |L_stored - L_exact| (nats): rounding logit(p_d) to the nearest 1/1024
/// nat (half a unit) plus the float evaluation of logit (p_d in [0.02, 0.98]: |logit| < 4, float
/// log and division within a few ulp, < 1e-6 nat).
constexpr double kPerUpdateNats = 0.5 / kClassLogitUnitsPerNat + 1e-6;

}  // namespace

// Repeated updates through the log-odds equal the paper's formula applied in double precision,
// within n * kPerUpdateNats in L and a quarter of that (|dp/dL| <= 1/4) plus the float sigmoid
// in p, as long as the clamp is not reached.
TEST(ClassEvidence, RepeatedBayesUpdatesMatchThePaperWithinTheQuantisationBound) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> pd(0.02f, 0.98f);
  double worst_l = 0.0, worst_p = 0.0, worst_ratio = 0.0;
  int sequences = 0, checked = 0;
  for (int seq = 0; seq < 2000; ++seq) {
    ClassEvidence e;
    const int cls = 1 + int(rng() % 96);
    double p = 0.5;  // the II-B prior
    for (int n = 1; n <= 60; ++n) {
      const float p_d = pd(rng);
      const double p_next = bayes(p, double(p_d));
      if (std::abs(logit(p_next)) > kClassLogitMax - 0.01) break;  // the clamp: next test
      p = p_next;
      classEvidenceUpdate(e, cls, p_d);
      const double l_q = dequantizeClassLogit(classLogitUnits(e, cls));
      const double bound_l = n * kPerUpdateNats;
      const double err_l = std::abs(l_q - logit(p));
      ASSERT_LE(err_l, bound_l) << "sequence " << seq << " update " << n;
      const double err_p = std::abs(double(classProbability(e, cls)) - p);
      ASSERT_LE(err_p, bound_l / 4 + 1e-6) << "sequence " << seq << " update " << n;
      worst_l = std::max(worst_l, err_l);
      worst_p = std::max(worst_p, err_p);
      worst_ratio = std::max(worst_ratio, err_l / bound_l);
      ++checked;
    }
    ++sequences;
  }
  EXPECT_GT(checked, 20000);
  // The bound is tight enough to mean something: some single updates reach most of it.
  EXPECT_GT(worst_ratio, 0.5);
  RecordProperty("worst_logit_error_nats", std::to_string(worst_l));
  RecordProperty("worst_probability_error", std::to_string(worst_p));
}

// A slot's L is an exact integer sum: updates in any order give the same bits.
TEST(ClassEvidence, UpdatesCommute) {
  const float pds[] = {0.9f, 0.3f, 0.75f, 0.6f, 0.12f, 0.97f};
  ClassEvidence a, b;
  for (int k = 0; k < 6; ++k) classEvidenceUpdate(a, 7, pds[k]);
  for (int k = 5; k >= 0; --k) classEvidenceUpdate(b, 7, pds[k]);
  EXPECT_EQ(classLogitUnits(a, 7), classLogitUnits(b, 7));
  int sum = 0;
  for (float p : pds) sum += quantizeClassLogit(float(logit(p)));
  EXPECT_EQ(classLogitUnits(a, 7), sum);
}

TEST(ClassEvidence, ClampsAtTheDocumentedLimits) {
  EXPECT_EQ(kClassLogitMaxUnits, int(kClassLogitMax * kClassLogitUnitsPerNat));
  const float p_max = logitProbability(kClassLogitMax);
  EXPECT_NEAR(p_max, 1.0 / (1.0 + std::exp(-7.0)), 1e-6);  // 0.99909
  EXPECT_GT(p_max, 0.999f);
  ClassEvidence e;
  for (int k = 0; k < 20; ++k) classEvidenceUpdate(e, 3, 0.99f);  // +4.6 nats each
  EXPECT_EQ(classLogitUnits(e, 3), kClassLogitMaxUnits);
  EXPECT_FLOAT_EQ(classProbability(e, 3), p_max);
  // From the clamp, 4 contrary detections at 0.9 (-2.197 nats each) go below the prior, 3 do not.
  for (int k = 0; k < 3; ++k) classEvidenceUpdate(e, 3, 0.1f);
  EXPECT_GT(classProbability(e, 3), 0.5f);
  classEvidenceUpdate(e, 3, 0.1f);
  EXPECT_LT(classProbability(e, 3), 0.5f);
  for (int k = 0; k < 20; ++k) classEvidenceUpdate(e, 3, 0.01f);
  EXPECT_EQ(classLogitUnits(e, 3), -kClassLogitMaxUnits);
  EXPECT_NEAR(classProbability(e, 3), 1.0f - p_max, 1e-6f);
  // Certain detections (p_d = 0 or 1) are one clamped step; NaN is no evidence.
  ClassEvidence c;
  classEvidenceUpdate(c, 1, 1.0f);
  classEvidenceUpdate(c, 2, 0.0f);
  EXPECT_EQ(classLogitUnits(c, 1), kClassLogitMaxUnits);
  EXPECT_EQ(classLogitUnits(c, 2), -kClassLogitMaxUnits);
  EXPECT_EQ(classEvidenceUpdate(c, 4, std::numeric_limits<float>::quiet_NaN()), kClassDropped);
  EXPECT_EQ(classEvidenceSlot(c, 4), -1);
  // Raw additions beyond the range are clamped too.
  ClassEvidence d;
  classEvidenceAdd(d, 9, 100000);
  EXPECT_EQ(classLogitUnits(d, 9), kClassLogitMaxUnits);
  EXPECT_EQ(quantizeClassLogit(-1e9f), -kClassLogitMaxUnits);
  EXPECT_EQ(quantizeClassLogit(0.5f / 1024), 1);  // half a unit rounds away from zero
  EXPECT_EQ(quantizeClassLogit(-0.5f / 1024), -1);
}

TEST(ClassEvidence, SlotRule) {
  ClassEvidence e;
  // Four classes take the four slots: L = 0.5, -1, 2, 3 nats.
  EXPECT_EQ(classEvidenceAdd(e, 10, 512), kClassNewSlot);
  EXPECT_EQ(classEvidenceAdd(e, 20, -1024), kClassNewSlot);
  EXPECT_EQ(classEvidenceAdd(e, 30, 2048), kClassNewSlot);
  EXPECT_EQ(classEvidenceAdd(e, 40, 3072), kClassNewSlot);
  EXPECT_EQ(classEvidenceAdd(e, 30, 100), kClassUpdated);
  EXPECT_EQ(classLogitUnits(e, 30), 2148);
  // Negative evidence for a fifth class never displaces positive evidence; against the negative
  // slot (20: -1 nat) it needs a strictly larger |L|.
  EXPECT_EQ(classEvidenceAdd(e, 50, -1024), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(e, 50, -300), kClassDropped);
  EXPECT_EQ(classProbability(e, 50), 0.5f);
  EXPECT_EQ(classEvidenceAdd(e, 50, -2000), kClassReplaced);
  EXPECT_EQ(classEvidenceSlot(e, 20), -1);
  EXPECT_EQ(classProbability(e, 20), 0.5f);  // the replaced class falls back to the prior
  EXPECT_EQ(classLogitUnits(e, 50), -2000);
  EXPECT_EQ(classLogitUnits(e, 10), 512);
  EXPECT_EQ(classLogitUnits(e, 40), 3072);
  // Any positive evidence outranks negative evidence: a weak positive newcomer takes its slot.
  EXPECT_EQ(classEvidenceAdd(e, 60, 10), kClassReplaced);
  EXPECT_EQ(classEvidenceSlot(e, 50), -1);
  // All four slots positive (10: 512, 60: 10, 30: 2148, 40: 3072): a newcomer must beat the
  // weakest positive one, and no negative evidence gets in.
  EXPECT_EQ(classEvidenceAdd(e, 70, -kClassLogitMaxUnits), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(e, 70, 10), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(e, 70, 11), kClassReplaced);
  EXPECT_EQ(classEvidenceSlot(e, 60), -1);
  // Seen again later, a replaced class starts from the prior (its history is forgotten).
  EXPECT_EQ(classEvidenceAdd(e, 60, 600), kClassReplaced);  // replaces 70 (11)
  EXPECT_EQ(classLogitUnits(e, 60), 600);
  EXPECT_EQ(bestClass(e).id, 40);  // the best class was never displaced
  // Equal lowest rank: the lower slot is replaced.
  ClassEvidence t;
  classEvidenceAdd(t, 1, 100);
  classEvidenceAdd(t, 2, -100);
  classEvidenceAdd(t, 3, -100);
  classEvidenceAdd(t, 4, 500);
  EXPECT_EQ(classEvidenceAdd(t, 5, -200), kClassReplaced);
  EXPECT_EQ(t.id[1], 5);
  EXPECT_EQ(classLogitUnits(t, 3), -100);
  // A slot whose L returns to exactly 0 is free again (and taken before any replacement).
  EXPECT_EQ(classEvidenceAdd(t, 3, 100), kClassUpdated);
  EXPECT_EQ(classEvidenceSlot(t, 3), -1);
  EXPECT_EQ(t.id[2], 0);
  EXPECT_EQ(t.logit[2], 0);
  EXPECT_EQ(classEvidenceAdd(t, 6, -1), kClassNewSlot);
  EXPECT_EQ(t.id[2], 6);
  EXPECT_TRUE(classEvidenceValid(t, 6));
  EXPECT_FALSE(classEvidenceValid(t, 5));  // id 6 beyond n_classes = 5
  // The rank: positives above negatives, then |L|.
  EXPECT_GT(classEvidenceRank(1), classEvidenceRank(-kClassLogitMaxUnits));
  EXPECT_GT(classEvidenceRank(-5), classEvidenceRank(-4));
  EXPECT_EQ(classEvidenceRank(0), 0);
  // Zero evidence and ids outside 1..255 store nothing.
  ClassEvidence z;
  EXPECT_EQ(classEvidenceAdd(z, 3, 0), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(z, 0, 500), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(z, 256, 500), kClassDropped);
  EXPECT_EQ(classEvidenceAdd(z, -1, 500), kClassDropped);
  EXPECT_TRUE(classEvidenceEmpty(z));
  EXPECT_EQ(classEvidenceAdd(z, 255, 500), kClassNewSlot);  // the largest id
}

TEST(ClassEvidence, BestClassAndProbability) {
  ClassEvidence e;
  BestClass b = bestClass(e);
  EXPECT_EQ(b.id, 0);
  EXPECT_EQ(b.probability, 0.5f);
  classEvidenceUpdate(e, 12, 0.2f);  // only negative evidence: no class above the prior
  b = bestClass(e);
  EXPECT_EQ(b.id, 0);
  EXPECT_EQ(b.probability, 0.5f);
  classEvidenceUpdate(e, 40, 0.7f);
  classEvidenceUpdate(e, 5, 0.6f);
  b = bestClass(e);
  EXPECT_EQ(b.id, 40);
  EXPECT_NEAR(b.probability, 0.7f, 1e-3f);  // one update: within half a unit of logit(0.7)
  EXPECT_EQ(b.probability, classProbability(e, 40));
  // More evidence for 5 makes it the best (after the third detection).
  classEvidenceUpdate(e, 5, 0.6f);  // 5: 2 logit(0.6) = 0.811 nat, below logit(0.7) = 0.847
  EXPECT_EQ(bestClass(e).id, 40);
  classEvidenceUpdate(e, 5, 0.6f);
  EXPECT_EQ(bestClass(e).id, 5);
  EXPECT_NEAR(bestClass(e).probability, bayes(bayes(bayes(0.5, 0.6f), 0.6f), 0.6f), 1e-3);
  // Equal L: the lower id, wherever its slot is.
  ClassEvidence tie;
  classEvidenceAdd(tie, 90, 700);
  classEvidenceAdd(tie, 8, 700);
  EXPECT_EQ(bestClass(tie).id, 8);
  EXPECT_EQ(bestClass(tie).logit_units, 700);
}

TEST(SurfelStore, AddClassEvidenceOverSurfelsAndSegments) {
  SurfelStoreOptions opt;
  opt.n_classes = kDefaultNumClasses;
  EXPECT_GE(opt.n_classes, 88);  // 80 COCO + the project's classes (SimClasses.h)
  SurfelStore store(opt);
  for (int i = 0; i < 1000; ++i) {
    Surfel s;
    s.position = Vec3f(0.01f * i, 0.0f, 1.0f);
    s.segment = std::uint32_t(1 + i % 4);
    store.append(s);
  }
  const SurfelStore& cstore = store;  // read access that does not count as a modification
  const std::uint64_t g = store.generation();
  // Segment 2 (250 surfels) is detected as class 62 ("tv") with p_d = 0.8, twice.
  for (int k = 0; k < 2; ++k) {
    const auto st = store.addClassEvidenceToSegment(2, 62, 0.8f);
    EXPECT_EQ(st.surfels(), 250);
    EXPECT_EQ(k == 0 ? st.new_slot : st.updated, 250);
  }
  const double p2 = bayes(bayes(0.5, 0.8f), 0.8f);  // 0.941
  const SurfelArrays a = cstore.arrays();
  for (int i = 0; i < a.size; ++i) {
    const BestClass b = bestClass(a.classEvidence(i));
    if (a.segment[i] == 2u) {
      EXPECT_EQ(b.id, 62);
      EXPECT_NEAR(b.probability, p2, 2 * kPerUpdateNats / 4 + 1e-6);
    } else {
      EXPECT_EQ(b.id, 0);
    }
  }
  // The same update through an index list (a duplicate is updated twice).
  std::vector<int> some = {1, 5, 9, 5};
  const auto st = store.addClassEvidence(some, 81, 0.9f);
  EXPECT_EQ(st.new_slot, 3);
  EXPECT_EQ(st.updated, 1);
  EXPECT_EQ(classLogitUnits(cstore.arrays().classEvidence(5), 81),
            2 * quantizeClassLogit(float(logit(0.9f))));
  EXPECT_GE(classEvidenceSlot(store.get(9).classes, 81), 0);
  // Surfels 5 and 9 are in segment 2 (62 at 2 logit(0.8) = 2.77 nats): 9 has 81 at
  // logit(0.9) = 2.20 nats, 5 at twice that.
  EXPECT_EQ(bestClass(store.get(9).classes).id, 62);
  EXPECT_EQ(bestClass(store.get(5).classes).id, 81);
  // Class evidence updates do not invalidate fusion's caches (generation()).
  EXPECT_EQ(store.generation(), g);
  // Bad input is rejected before anything changes.
  const ClassEvidence before = cstore.arrays().classEvidence(1);
  EXPECT_THROW(store.addClassEvidence({1, 1000}, 3, 0.7f), std::invalid_argument);
  EXPECT_THROW(store.addClassEvidence({1}, 0, 0.7f), std::invalid_argument);
  EXPECT_THROW(store.addClassEvidence({1}, kDefaultNumClasses + 1, 0.7f), std::invalid_argument);
  EXPECT_THROW(store.addClassEvidence({1}, 3, 1.5f), std::invalid_argument);
  EXPECT_THROW(store.addClassEvidence({1}, 3, std::numeric_limits<float>::quiet_NaN()),
               std::invalid_argument);
  EXPECT_THROW(store.addClassEvidenceToSegment(0, 3, 0.7f), std::invalid_argument);
  const ClassEvidence after = cstore.arrays().classEvidence(1);
  for (int k = 0; k < kClassSlots; ++k) {
    EXPECT_EQ(after.id[k], before.id[k]);
    EXPECT_EQ(after.logit[k], before.logit[k]);
  }
  // A map without classes has no evidence to update; set() checks what it stores.
  SurfelStoreOptions none;
  none.n_classes = 0;
  SurfelStore plain(none);
  plain.append(Surfel());
  EXPECT_THROW(plain.addClassEvidence({0}, 1, 0.7f), std::invalid_argument);
  Surfel s;
  classEvidenceUpdate(s.classes, 1, 0.7f);
  EXPECT_THROW(plain.set(0, s), std::invalid_argument);
  EXPECT_THROW(plain.append(s), std::invalid_argument);
  EXPECT_EQ(plain.size(), 1);
  s.classes.id[1] = 1;  // the same class twice
  s.classes.logit[1] = 5;
  EXPECT_THROW(store.set(0, s), std::invalid_argument);
}

// Memory per surfel no longer grows with the number of classes: with 96 classes and the default
// 8 x 2 view bins a surfel costs 64 + 12 + 16 = 92 bytes of arrays, within the old fixed part
// (64 + 16 bins) + 16; the linear u8 per class layout cost 64 + 96 + 16 = 176.
TEST(SurfelStore, ClassEvidenceCostsAtMostSixteenBytesPerSurfel) {
  const std::size_t old_fixed = SurfelStore::bytesPerSurfel(0, 16);
  EXPECT_EQ(old_fixed, 80u);
  for (int nc : {1, 80, 90, 96, 255})
    EXPECT_LE(SurfelStore::bytesPerSurfel(nc, 16), old_fixed + 16) << nc << " classes";
  // Measured (capacity-based, spatial index included) on 300k surfels with and without classes.
  auto measure = [](int n_classes) {
    SurfelStoreOptions o;
    o.n_classes = n_classes;
    SurfelStore s(o);
    const int n = 300000;
    s.allocate(n);
    SurfelArrays a = s.arrays();
    for (int i = 0; i < n; ++i)
      a.pos_conf[i] = Vec4f(0.001f * (i % 1000), 0.001f * (i / 1000), 1, 1);
    s.indexAppended();
    return double(s.memoryBytes()) / n;
  };
  const double with = measure(96), without = measure(0);
  RecordProperty("bytes_per_surfel_96_classes", std::to_string(with));
  RecordProperty("bytes_per_surfel_no_classes", std::to_string(without));
  EXPECT_LE(with - without, 16.0);
  EXPECT_GE(with - without, 12.0);
}
