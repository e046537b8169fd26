#pragma once
// Structure-of-arrays storage of the surfel attributes of section II-A, as plain spans that
// kernels read and write on both backends (ElasticFusion-style packing of the hot attributes).
//
// Per surfel, bytes:
//   pos_conf       Vec4f  16  position p (world, m) and confidence weight w          (II-A, II-B)
//   normal_radius  Vec4f  16  unit normal n (world) and radius r (m)                  (II-A, II-B)
//   colour_flags   u32     4  B,G,R (bits 0-23) and flags (bits 24-31: kStable, ...)  (II-A)
//   t_init         float   4  instantiation time t (s)                                (II-A)
//   t_last         float   4  last time the surfel was fused (s)                      (II-D)
//   basis          Vec3f  12  in-plane basis direction b (unit, world)                (V-B)
//   ---------------- geometric core 56 bytes
//   segment        u32     4  segment label l (0 = none)                              (III)
//   segment_w      float   4  segment weight w_l                                      (III)
//   class_ev              12  class evidence p_c: 4 slots of class id + clamped       (IV)
//                             log-odds (ClassEvidence.h) for any n_classes <= 255;
//                             absent when n_classes = 0
//   view_ic        u8 x n_view_bins  b_v quantised to [0,1] in 1/255 steps            (V-B)
//   => 64 bytes + 12 (n_classes > 0) + n_view_bins: 92 with classes and the default 8 x 2
//      bins (the linear u8 per class layout before: 64 + n_classes + n_view_bins, 176 with 96).
//
// Times are seconds relative to the map's time origin (the first inserted frame), stored as float.

#include <cstddef>
#include <cstdint>

#include "rasm/compute/Types.h"
#include "rasm/surfel_map/ClassEvidence.h"

namespace rasm::maps {

enum SurfelFlags : std::uint32_t {
  kSurfelStable = 1u << 24,  ///< confidence reached the stability threshold (II-D)
  kSurfelFree = 1u << 25,    ///< slot is free (removed surfel, reused by the allocator)
};

RASM_HD_INLINE std::uint32_t packColour(const Bgr8& c, std::uint32_t flags = 0) {
  return std::uint32_t(c.b) | (std::uint32_t(c.g) << 8) | (std::uint32_t(c.r) << 16) | flags;
}
RASM_HD_INLINE Bgr8 unpackColour(std::uint32_t v) {
  Bgr8 c;
  c.b = std::uint8_t(v & 0xff);
  c.g = std::uint8_t((v >> 8) & 0xff);
  c.r = std::uint8_t((v >> 16) & 0xff);
  return c;
}

/// [0,1] <-> u8 quantisation of view-information bins (1/255 steps).
RASM_HD_INLINE std::uint8_t quantizeUnit(float v) {
  v = v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v);
  return std::uint8_t(v * 255.0f + 0.5f);
}
RASM_HD_INLINE float dequantizeUnit(std::uint8_t q) {
  return float(q) * (1.0f / 255.0f);
}

/// Raw pointers to the arrays of a map (host or device memory); `size` surfels, strides for the
/// per-surfel vectors. Cheap to copy into kernel functors.
struct SurfelArrays {
  Vec4f* pos_conf = nullptr;
  Vec4f* normal_radius = nullptr;
  std::uint32_t* colour_flags = nullptr;
  float* t_init = nullptr;
  float* t_last = nullptr;
  Vec3f* basis = nullptr;
  std::uint32_t* segment = nullptr;
  float* segment_w = nullptr;
  ClassEvidence* class_ev = nullptr;  ///< size entries; null when n_classes = 0
  std::uint8_t* view_ic = nullptr;    ///< size * n_view_bins
  int size = 0;
  int n_classes = 0;  ///< class ids 1..n_classes are valid (ClassEvidence.h)
  int n_view_bins = 0;

  RASM_HD_INLINE bool stable(int i) const { return (colour_flags[i] & kSurfelStable) != 0; }
  RASM_HD_INLINE bool alive(int i) const { return (colour_flags[i] & kSurfelFree) == 0; }
  RASM_HD_INLINE Vec3f position(int i) const { return pos_conf[i].head<3>(); }
  RASM_HD_INLINE Vec3f normal(int i) const { return normal_radius[i].head<3>(); }
  RASM_HD_INLINE float confidence(int i) const { return pos_conf[i].w(); }
  RASM_HD_INLINE float radius(int i) const { return normal_radius[i].w(); }
  RASM_HD_INLINE Bgr8 colour(int i) const { return unpackColour(colour_flags[i]); }
  /// Class evidence of surfel i (requires n_classes > 0).
  RASM_HD_INLINE ClassEvidence& classEvidence(int i) const { return class_ev[i]; }
  /// Row of n_view_bins quantised IC values of surfel i.
  RASM_HD_INLINE std::uint8_t* viewRow(int i) const {
    return view_ic + std::size_t(i) * n_view_bins;
  }
};

}  // namespace rasm::maps
