#pragma once
// The map's one class list (IV): the class sets of several detectors merged by name. Class id
// k + 1 is classes()[k] (ClassEvidence.h: ids 1..255, 0 = none). It starts as the default list
// (the 80 COCO classes in their standard order, source "coco", then the project's own classes of
// rasm/models/ClassVocabulary.h, source "rasm"), so a COCO detector's output k is id k + 1 and the
// simulator's ground-truth class ids are map ids. A detector's class that is not in the list yet
// (e.g. a zero-shot model named "cabinet") is appended with the detector as its source. Names are
// matched exactly, then through the class vocabulary's aliases (Darknet's "diningtable",
// "tvmonitor", "sofa", ...). The list is persisted with the map (CSurfelMap::classes(), version 3).

#include <string>
#include <vector>

#include "rasm/classification/Detector.h"
#include "rasm/surfel_map/CSurfelMap.h"

namespace rasm::classification {

class ClassList {
 public:
  /// COCO 1..80, then rasm's project classes.
  static std::vector<maps::MapClass> defaultClasses();

  /// `max_classes`: the map's n_classes (ids beyond it cannot be stored).
  explicit ClassList(std::vector<maps::MapClass> classes = defaultClasses(),
                     int max_classes = maps::kMaxClassId);

  /// Id of `name` (exact or alias); -1 when absent.
  int find(const std::string& name) const;
  /// Id of `name`, appended with `source` when absent. Throws InputError when the list is full.
  int idFor(const std::string& name, const std::string& source);
  /// Map id of each of the detector's classes (index = the detector's class index).
  std::vector<int> registerDetector(const Detector& detector);

  /// Name of class id (1..size()); "none" for 0; throws std::out_of_range otherwise.
  const std::string& name(int id) const;
  int size() const { return int(m_classes.size()); }
  const std::vector<maps::MapClass>& classes() const { return m_classes; }

 private:
  std::vector<maps::MapClass> m_classes;
  int m_max_classes;
};

}  // namespace rasm::classification
