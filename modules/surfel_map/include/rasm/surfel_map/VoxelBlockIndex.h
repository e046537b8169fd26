#pragma once
// Coarse spatial index of the surfel map (DESIGN.md "The surfel map"): the world is cut into cubic
// blocks of `block_size_m`; a hash map takes a block key to a dense block id, and each block keeps
// the list of the surfels whose centre lies in it. Rendering culls whole blocks against the camera
// frustum (CameraFrustum) and then visits only the members of the blocks in view, so projecting
// the map costs O(B + S_in) per frame (B = number of non-empty blocks, a few thousand for a room
// at 0.5 m; S_in = surfels in the visited blocks), never O(whole map).
//
// Every surfel knows its block and its slot in that block's member list, so insert, erase, move
// (re-binning after fusion moved a surfel across a block border) and renumber (compaction moved a
// surfel to another index) are O(1) each. Memory: 12 bytes per surfel (member entry, block id,
// slot) plus ~100 bytes per non-empty block.
//
// Each member list keeps the stable surfels first (members[0, stableCount)), so a render of the
// stable surfels only (a third of the surfels in view on 7-Scenes; the II-C tracking model when
// [tracking] model_min_confidence = 0) visits just those. The index learns a surfel's stability
// when it is inserted and through setStable(); SurfelStore keeps it in step with the kSurfelStable
// flag (SurfelStore.h).
//
// Host-only (std containers); no MRPT.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "rasm/compute/Types.h"

namespace rasm::maps {

/// Six inward-facing planes (n . p + d >= 0 inside) of a pinhole camera's view volume, in world
/// coordinates: the image borders (pixel edges at -0.5 and size - 0.5), the near and far planes.
struct CameraFrustum {
  Vec4f planes[6];

  /// T_world_cam as a plain rigid transform (optical frame), intrinsics, depth range (m).
  static CameraFrustum fromCamera(const RigidF& T_world_cam, const PinholeF& K, float min_depth_m,
                                  float max_depth_m);
  /// True when the sphere (centre c, radius r) is not entirely outside one plane (conservative).
  bool intersectsSphere(const Vec3f& c, float r) const {
    for (const Vec4f& p : planes)
      if (p.head<3>().dot(c) + p.w() < -r) return false;
    return true;
  }
  /// True when the sphere lies entirely inside every plane.
  bool containsSphere(const Vec3f& c, float r) const {
    for (const Vec4f& p : planes)
      if (p.head<3>().dot(c) + p.w() < r) return false;
    return true;
  }
};

class VoxelBlockIndex {
 public:
  explicit VoxelBlockIndex(float block_size_m = 0.5f);

  float blockSize() const { return block_size_m_; }
  /// Packs the integer block coordinates of p (21 bits per axis, +-1e6 blocks) into a key.
  std::uint64_t keyOf(const Vec3f& p) const;
  /// Integer block coordinates of block `block_id`.
  Eigen::Vector3i blockCoords(int block_id) const { return blocks_[block_id].coords; }
  /// Axis-aligned bounds of block `block_id` (world, m).
  Vec3f blockMin(int block_id) const {
    return blocks_[block_id].coords.cast<float>() * block_size_m_;
  }

  /// Adds surfel `surfel` (which must not be indexed yet) at position p.
  void insert(int surfel, const Vec3f& p, bool stable = false);
  /// Adds surfels [first, first + count) at positions pos[i] (pos indexed by surfel id), stable
  /// where flags[i] & stable_mask (flags may be null: none stable).
  /// Faster than single inserts: consecutive surfels usually share a block.
  void insertRange(int first, int count, const Vec4f* pos_conf,
                   const std::uint32_t* flags = nullptr, std::uint32_t stable_mask = 0);
  /// Moves an indexed surfel into (or out of) its block's stable part. O(1).
  void setStable(int surfel, bool stable);
  /// Whether an indexed surfel is in its block's stable part.
  bool isStable(int surfel) const {
    return surfel_slot_[surfel] < blocks_[surfel_block_[surfel]].n_stable;
  }
  /// Removes surfel `surfel` from its block (blocks that become empty are recycled).
  void erase(int surfel);
  /// Re-bins surfel `surfel` if p lies in another block than its current one; returns true if so.
  bool move(int surfel, const Vec3f& p);
  /// Whether move(surfel, p) would re-bin (read-only: safe to call from many threads).
  bool needsMove(int surfel, const Vec3f& p) const {
    const int b = blockOf(surfel);
    return b >= 0 && blockCoordsOf(p) != blocks_[b].coords;
  }
  Eigen::Vector3i blockCoordsOf(const Vec3f& p) const {
    return Eigen::Vector3i(int(std::floor(p.x() * inv_block_size_)),
                           int(std::floor(p.y() * inv_block_size_)),
                           int(std::floor(p.z() * inv_block_size_)));
  }
  /// The surfel stored at index `from` now lives at index `to` (compaction); `to` must be free.
  void renumber(int from, int to);
  /// Renames every indexed surfel i to new_of_old[i] (a permutation of [0, numSurfels()), e.g.
  /// SurfelStore::sortByBlock's); blocks and the order of their member lists stay. O(N).
  void permute(const std::vector<int>& new_of_old);
  /// Drops everything.
  void clear();

  /// Number of surfels indexed (the largest indexed surfel id + 1 after compaction).
  int numSurfels() const { return int(surfel_block_.size()); }
  /// Non-empty blocks.
  int numBlocks() const { return int(blocks_.size() - free_blocks_.size()); }
  /// Size of the dense block table (ids are in [0, blockCapacity()); empty slots have no members).
  int blockCapacity() const { return int(blocks_.size()); }
  /// Block id of an indexed surfel, -1 if not indexed.
  int blockOf(int surfel) const {
    return surfel < int(surfel_block_.size()) ? surfel_block_[surfel] : -1;
  }
  const std::vector<int>& members(int block_id) const { return blocks_[block_id].members; }
  /// The first stableCount(b) entries of members(b) are its stable surfels.
  int stableCount(int block_id) const { return blocks_[block_id].n_stable; }

  /// Appends the ids of the non-empty blocks whose bounding sphere, grown by `margin_m` (the
  /// largest splat radius), intersects the frustum. O(B). The ids are in increasing order.
  /// `fully_inside`, when given, receives per returned block whether the whole block lies inside
  /// the frustum (then every surfel centre in it does, and per-surfel frustum tests can be
  /// skipped).
  void blocksInFrustum(const CameraFrustum& frustum, float margin_m, std::vector<int>& block_ids,
                       std::vector<std::uint8_t>* fully_inside = nullptr) const;

  /// Checks the invariants against surfel positions (tests): every surfel in [0, n) is in exactly
  /// the block containing it, at its recorded slot, and (flags given) in the stable part exactly
  /// when flags[i] & stable_mask. Returns false and a reason otherwise.
  bool checkConsistency(const Vec4f* pos_conf, int n, std::string* why = nullptr,
                        const std::uint32_t* flags = nullptr, std::uint32_t stable_mask = 0) const;

  /// Bytes held (capacity based).
  std::size_t memoryBytes() const;

 private:
  struct Block {
    Eigen::Vector3i coords = Eigen::Vector3i::Zero();
    std::uint64_t key = 0;
    std::vector<int> members;  ///< stable ones first
    int n_stable = 0;
  };
  int blockFor(std::uint64_t key, const Eigen::Vector3i& coords);  // find or create
  void addToBlock(int surfel, int block_id, bool stable);
  void swapSlots(Block& b, int slot_a, int slot_b);
  void eraseFromBlock(int surfel);
  void ensureSurfel(int surfel);

  float block_size_m_;
  float inv_block_size_;
  std::unordered_map<std::uint64_t, int> key_to_block_;
  std::vector<Block> blocks_;
  std::vector<int> free_blocks_;
  std::vector<int> surfel_block_;  ///< block id per surfel (-1 none)
  std::vector<int> surfel_slot_;   ///< position in that block's member list
};

}  // namespace rasm::maps
