#pragma once
// The project's class vocabulary: the class ids of the simulator's ground truth (gt_class images,
// detections), of the map's default class list (classification/ClassList.h, classes.json) and of
// the procedural models (ProceduralModels.h).
//  - 0: no class ("unknown" objects and pixels that hit nothing).
//  - 1..80: the 80 COCO detection classes in their standard contiguous order, so the output index
//    k of a COCO-trained detector (YOLO, NanoDet: coco.names line k) is class id k + 1.
//  - 81..: project classes COCO lacks (objects of interest for the zero-shot classifier, IV-A,
//    and structure), see kProject in ClassVocabulary.cpp.
// Names are the official COCO 2017 names ("dining table", "tv", "couch"); Darknet's spellings
// ("diningtable", "tvmonitor", "sofa", ...) are accepted as aliases by classIdFromName.

#include <cstdint>
#include <string>
#include <vector>

namespace rasm::models {

using ClassId = std::uint16_t;

constexpr ClassId kNoClass = 0;
constexpr int kNumCocoClasses = 80;

/// Names of classes 1..kNumClasses()-1 indexed by id (entry 0 is "none").
const std::vector<std::string>& classNames();
int numClasses();  ///< including id 0

/// Class id of `name` (COCO name, Darknet alias or project name); "none", "unknown" and "" give
/// kNoClass. Returns -1 for names that are not classes.
int classIdFromName(const std::string& name);
/// Name of a class id; throws std::out_of_range for ids >= numClasses().
const std::string& className(int id);
/// True for 1..80.
inline bool isCocoClass(int id) {
  return id >= 1 && id <= kNumCocoClasses;
}
/// Classes that are structure of the building rather than objects (floor, wall, ceiling, door).
bool isStructureClass(int id);

}  // namespace rasm::models
