#pragma once
// What section III publishes beside the surfel map, for the stages after it (classification's
// object layer, IV) and for other threads (Mapper::snapshot, exploration V-B): the segment table
// as of its last refresh and the renamings of segment ids the map went through (merges, dense
// renumbering). The Mapper owns it; the segmentation stage is its one writer and the stages that
// read it get it at construction, so no stage holds a pointer to another.
//
// Renamings are tables new = table[old] (old ids past the table's end unchanged). They are
// applied to the map by the writer and handed, on the mapping thread and in order, to every
// listener: a reader holding segment ids of earlier frames (classification's L^p of frames still
// in flight, its object layer) renames them at once.

#include <cstdint>
#include <functional>
#include <vector>

#include "rasm/segmentation/SegmentTable.h"

namespace rasm::pipeline {

class SegmentLayer {
 public:
  using RelabelListener = std::function<void(const std::vector<std::uint32_t>& table)>;

  /// The segment statistics as of the last refresh (SegmentationStage::refreshTable, and the
  /// final map's at the end of a run).
  const segmentation::SegmentTable& table() const { return m_table; }
  /// Renamings published so far: a reader holding segment ids re-reads them when this changes.
  std::uint64_t relabelGeneration() const { return m_relabel_generation; }
  /// Called with every renaming from now on, on the mapping thread.
  void addRelabelListener(RelabelListener listener) { m_listeners.push_back(std::move(listener)); }

  /// The writer's side (the segmentation stage).
  segmentation::SegmentTable& tableToWrite() { return m_table; }
  /// Publishes a renaming the writer applied to the map: counted and handed to every listener in
  /// the order they were added.
  void publishRelabelling(const std::vector<std::uint32_t>& table) {
    ++m_relabel_generation;
    for (const RelabelListener& l : m_listeners) l(table);
  }

 private:
  segmentation::SegmentTable m_table;
  std::uint64_t m_relabel_generation = 0;
  std::vector<RelabelListener> m_listeners;
};

}  // namespace rasm::pipeline
