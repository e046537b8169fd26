#pragma once
// Class evidence of one surfel (IV): the paper's independent (multilabel) class probabilities
// p_c, kept as clamped fixed-point log-odds in kClassSlots slots. Plain header (compute/ and
// Eigen only): kernels on both backends, the store and the classification stage use it.
//
// Log-odds. With L = logit(p) = ln(p / (1 - p)) the Bayes update of IV,
//     p <- p_d p / (p_d p + (1 - p_d)(1 - p)),
// is exactly L <- L + logit(p_d): an addition. L is stored in fixed point, 1 unit = 1/1024 nat
// (kClassLogitUnitsPerNat), as an int16 clamped to +-7 nats (kClassLogitMax: p in [0.00091,
// 0.99909]). Each update rounds logit(p_d) to the nearest unit, so n updates that never reach the
// clamp differ from the paper's formula applied in double precision by at most n (1/2048 + 1e-6)
// nat in L (rounding plus the float evaluation of logit), i.e. a quarter of that in p
// (|dp/dL| = p (1 - p) <= 1/4); the additions themselves are exact. The clamp (as OctoMap's
// occupancy clamping) keeps a surfel able to change its mind: from the clamp, ceil(7 / logit(0.9))
// = 4 contrary detections at p_d = 0.9 take it below the prior.
//
// Slots instead of n_c values. A surfel sees a handful of classes at most (the detections of its
// segment), so a full vector of n_c >= 88 probabilities (1 byte each before) is mostly the 0.5
// prior. Each slot holds a class id (1..255; 0 = empty) and its L; a class without a slot is at
// the prior (L = 0, p = 0.5). 4 slots x (u8 id + i16 L) = 12 bytes per surfel for any number of
// classes. Evidence is kept per surfel, not per segment, because segments are relabelled and
// merged (III) and a surfel changes segment when its segment weight drops to zero: per-surfel
// evidence is what the paper's p_c(i) is, and it survives segmentation errors.
//
// Slot rule (classEvidenceAdd): evidence for a class that has a slot is added to it (clamped);
// a slot whose L returns to exactly 0 is emptied. A class without a slot takes the first empty
// slot; when all are taken it competes with the weakest slot by classEvidenceRank: any positive
// L (the class is likely) outranks any negative one (it is unlikely), then larger |L| wins. The
// newcomer replaces the lowest-ranked slot (the lowest slot index on ties) only if it ranks
// strictly higher, otherwise its evidence is dropped. Consequences: at most kClassSlots classes
// per surfel differ from the prior; a replaced class falls back to p = 0.5 (its history is
// forgotten) and starts from the prior if it is seen again; evidence for a fifth class is lost
// while four higher-ranked ones are held. Negative evidence only fills spare slots and goes first,
// so the best class (bestClass) is never displaced by evidence against other classes, nor by a
// weaker class: a surfel with a class above the prior keeps it until that class's own L falls or
// a stronger class arrives.

#include <cmath>
#include <cstdint>

#include "rasm/compute/Platform.h"

namespace rasm::maps {

constexpr int kClassSlots = 4;                 ///< slots per surfel
constexpr int kMaxClassId = 255;               ///< class ids are 1..255; 0 = no class / empty
constexpr int kClassLogitUnitsPerNat = 1024;   ///< fixed point: 1 unit = 1/1024 nat
constexpr int kClassLogitMaxUnits = 7 * 1024;  ///< clamp |L| <= 7 nats
constexpr float kClassLogitMax = 7.0f;         ///< = kClassLogitMaxUnits / 1024 (nats)
/// Default n_classes of a map: ids 1..80 are the COCO classes in their standard order (detector
/// output k is id k + 1), 81..96 the project's own (rasm/models/ClassVocabulary.h uses 81..88
/// today).
constexpr int kDefaultNumClasses = 96;

/// The class evidence of one surfel (12 bytes). All zero = no evidence (every class at 0.5).
struct ClassEvidence {
  std::uint8_t id[kClassSlots] = {0, 0, 0, 0};     ///< class id per slot, 0 = empty
  std::int16_t logit[kClassSlots] = {0, 0, 0, 0};  ///< L of the slot's class, 1/1024 nat units
};
static_assert(sizeof(ClassEvidence) == 12, "class evidence budget: 12 bytes per surfel");

/// What classEvidenceAdd did.
enum ClassEvidenceResult : int {
  kClassUpdated = 0,   ///< added to the class's slot
  kClassNewSlot = 1,   ///< the class took an empty slot
  kClassReplaced = 2,  ///< the class replaced the weakest slot
  kClassDropped = 3,   ///< no slot: all taken by stronger evidence (or zero evidence, bad id)
};

/// Nats -> fixed-point units, clamped to +-kClassLogitMaxUnits, rounded to nearest (half away
/// from zero). NaN gives 0.
RASM_HD_INLINE int quantizeClassLogit(float nats) {
  if (!(nats == nats)) return 0;
  if (nats > kClassLogitMax) nats = kClassLogitMax;
  if (nats < -kClassLogitMax) nats = -kClassLogitMax;
  const float u = nats * float(kClassLogitUnitsPerNat);  // exact: a power of two
  return u >= 0.0f ? int(u + 0.5f) : -int(-u + 0.5f);
}
RASM_HD_INLINE float dequantizeClassLogit(int units) {
  return float(units) * (1.0f / float(kClassLogitUnitsPerNat));
}

/// logit(p) = ln(p / (1 - p)) of a probability, clamped to +-kClassLogitMax (p = 0 and 1 give
/// the clamp; NaN gives 0, i.e. no evidence).
RASM_HD_INLINE float probabilityLogit(float p) {
  if (!(p == p)) return 0.0f;
  const float eps = 1e-6f;  // logit(1e-6) = -13.8 nats: beyond the clamp
  if (p < eps) p = eps;
  if (p > 1.0f - eps) p = 1.0f - eps;
  const float l = logf(p / (1.0f - p));
  return l > kClassLogitMax ? kClassLogitMax : (l < -kClassLogitMax ? -kClassLogitMax : l);
}
/// p = 1 / (1 + exp(-L)).
RASM_HD_INLINE float logitProbability(float nats) {
  return 1.0f / (1.0f + expf(-nats));
}

/// Slot of class_id in e, -1 when it has none.
RASM_HD_INLINE int classEvidenceSlot(const ClassEvidence& e, int class_id) {
  for (int k = 0; k < kClassSlots; ++k)
    if (class_id != 0 && e.id[k] == class_id) return k;
  return -1;
}
RASM_HD_INLINE bool classEvidenceEmpty(const ClassEvidence& e) {
  for (int k = 0; k < kClassSlots; ++k)
    if (e.id[k] != 0) return false;
  return true;
}
RASM_HD_INLINE void classEvidenceClear(ClassEvidence& e) {
  for (int k = 0; k < kClassSlots; ++k) {
    e.id[k] = 0;
    e.logit[k] = 0;
  }
}

/// Well formed for a map of n_classes classes: ids in 1..n_classes and unique, every used slot
/// with a nonzero L within the clamp, every empty slot with L = 0.
RASM_HD_INLINE bool classEvidenceValid(const ClassEvidence& e, int n_classes) {
  for (int k = 0; k < kClassSlots; ++k) {
    const int id = e.id[k], l = e.logit[k];
    if (id == 0) {
      if (l != 0) return false;
      continue;
    }
    if (id > n_classes || classEvidenceSlot(e, id) != k) return false;
    if (l == 0 || l > kClassLogitMaxUnits || l < -kClassLogitMaxUnits) return false;
  }
  return true;
}

/// Order in which slots compete (slot rule above): every positive L above every negative one,
/// then by |L|. 0 for L = 0.
RASM_HD_INLINE int classEvidenceRank(int logit_units) {
  return logit_units > 0 ? logit_units + kClassLogitMaxUnits + 1 : -logit_units;
}

/// L <- clamp(L + logit_units) for class_id (1..kMaxClassId) by the slot rule of the header
/// comment. logit_units is in 1/1024 nat (quantizeClassLogit).
RASM_HD_INLINE ClassEvidenceResult classEvidenceAdd(ClassEvidence& e, int class_id,
                                                    int logit_units) {
  if (class_id <= 0 || class_id > kMaxClassId) return kClassDropped;
  if (logit_units > kClassLogitMaxUnits) logit_units = kClassLogitMaxUnits;
  if (logit_units < -kClassLogitMaxUnits) logit_units = -kClassLogitMaxUnits;
  const int k = classEvidenceSlot(e, class_id);
  if (k >= 0) {
    int l = int(e.logit[k]) + logit_units;
    l = l > kClassLogitMaxUnits ? kClassLogitMaxUnits
                                : (l < -kClassLogitMaxUnits ? -kClassLogitMaxUnits : l);
    e.logit[k] = std::int16_t(l);
    if (l == 0) e.id[k] = 0;  // back at the prior: the slot is free again
    return kClassUpdated;
  }
  if (logit_units == 0) return kClassDropped;  // the prior: nothing to store
  int weakest = -1, weakest_rank = 0;
  for (int s = 0; s < kClassSlots; ++s) {
    if (e.id[s] == 0) {
      e.id[s] = std::uint8_t(class_id);
      e.logit[s] = std::int16_t(logit_units);
      return kClassNewSlot;
    }
    const int r = classEvidenceRank(e.logit[s]);
    if (weakest < 0 || r < weakest_rank) {
      weakest = s;
      weakest_rank = r;
    }
  }
  if (classEvidenceRank(logit_units) <= weakest_rank) return kClassDropped;
  e.id[weakest] = std::uint8_t(class_id);
  e.logit[weakest] = std::int16_t(logit_units);
  return kClassReplaced;
}

/// The Bayes update of IV for one class: a detection of class_id with probability p_detection,
/// as L += logit(p_detection), quantised and clamped.
RASM_HD_INLINE ClassEvidenceResult classEvidenceUpdate(ClassEvidence& e, int class_id,
                                                       float p_detection) {
  return classEvidenceAdd(e, class_id, quantizeClassLogit(probabilityLogit(p_detection)));
}

/// L of class_id in fixed-point units (0 = prior when it has no slot).
RASM_HD_INLINE int classLogitUnits(const ClassEvidence& e, int class_id) {
  const int k = classEvidenceSlot(e, class_id);
  return k >= 0 ? int(e.logit[k]) : 0;
}
/// p_c of class_id (0.5 when it has no slot).
RASM_HD_INLINE float classProbability(const ClassEvidence& e, int class_id) {
  return logitProbability(dequantizeClassLogit(classLogitUnits(e, class_id)));
}

/// The most probable class and its probability.
struct BestClass {
  int id = 0;                ///< 0 when no class rose above the 0.5 prior
  float probability = 0.5f;  ///< p of `id`; 0.5 when id = 0 (every class at or below the prior)
  int logit_units = 0;       ///< L of `id`
};
/// The class with the largest L > 0 (the lower id on ties: independent of the slot order).
RASM_HD_INLINE BestClass bestClass(const ClassEvidence& e) {
  BestClass b;
  for (int k = 0; k < kClassSlots; ++k) {
    const int id = e.id[k], l = e.logit[k];
    if (id == 0 || l <= 0) continue;
    if (l > b.logit_units || (l == b.logit_units && id < b.id)) {
      b.id = id;
      b.logit_units = l;
    }
  }
  if (b.id != 0) b.probability = logitProbability(dequantizeClassLogit(b.logit_units));
  return b;
}

}  // namespace rasm::maps
