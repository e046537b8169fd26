#include "rasm/models/ClassVocabulary.h"

#include <map>
#include <stdexcept>

namespace rasm::models {
namespace {

// COCO 2017 detection classes in contiguous order (the order of every coco.names).
const char* const kCoco[kNumCocoClasses] = {"person",        "bicycle",      "car",
                                            "motorcycle",    "airplane",     "bus",
                                            "train",         "truck",        "boat",
                                            "traffic light", "fire hydrant", "stop sign",
                                            "parking meter", "bench",        "bird",
                                            "cat",           "dog",          "horse",
                                            "sheep",         "cow",          "elephant",
                                            "bear",          "zebra",        "giraffe",
                                            "backpack",      "umbrella",     "handbag",
                                            "tie",           "suitcase",     "frisbee",
                                            "skis",          "snowboard",    "sports ball",
                                            "kite",          "baseball bat", "baseball glove",
                                            "skateboard",    "surfboard",    "tennis racket",
                                            "bottle",        "wine glass",   "cup",
                                            "fork",          "knife",        "spoon",
                                            "bowl",          "banana",       "apple",
                                            "sandwich",      "orange",       "broccoli",
                                            "carrot",        "hot dog",      "pizza",
                                            "donut",         "cake",         "chair",
                                            "couch",         "potted plant", "bed",
                                            "dining table",  "toilet",       "tv",
                                            "laptop",        "mouse",        "remote",
                                            "keyboard",      "cell phone",   "microwave",
                                            "oven",          "toaster",      "sink",
                                            "refrigerator",  "book",         "clock",
                                            "vase",          "scissors",     "teddy bear",
                                            "hair drier",    "toothbrush"};

// Project classes (ids 81..): objects of interest without COCO training data (paper IV-A uses a
// conference phone and headphones), plus furniture and structure the worlds are built from.
const char* const kProject[] = {"conference_phone", "headphones", "shelf", "box", "floor", "wall",
                                "ceiling",          "door"};

const std::vector<std::string>& table() {
  static const std::vector<std::string> t = [] {
    std::vector<std::string> v{"none"};
    for (const char* n : kCoco) v.emplace_back(n);
    for (const char* n : kProject) v.emplace_back(n);
    return v;
  }();
  return t;
}

}  // namespace

const std::vector<std::string>& classNames() {
  return table();
}
int numClasses() {
  return int(table().size());
}

int classIdFromName(const std::string& name) {
  static const std::map<std::string, int> index = [] {
    std::map<std::string, int> m;
    const auto& t = table();
    for (int i = 0; i < int(t.size()); ++i) m[t[i]] = i;
    m["unknown"] = 0;
    m[""] = 0;
    // Darknet / VOC-style spellings of coco.names.
    const std::pair<const char*, const char*> aliases[] = {{"motorbike", "motorcycle"},
                                                           {"aeroplane", "airplane"},
                                                           {"sofa", "couch"},
                                                           {"pottedplant", "potted plant"},
                                                           {"diningtable", "dining table"},
                                                           {"tvmonitor", "tv"},
                                                           {"monitor", "tv"},
                                                           {"desk", "dining table"},
                                                           {"mug", "cup"}};
    for (const auto& [alias, name] : aliases) m[alias] = m.at(name);
    return m;
  }();
  const auto it = index.find(name);
  return it == index.end() ? -1 : it->second;
}

const std::string& className(int id) {
  if (id < 0 || id >= numClasses())
    throw std::out_of_range("rasm::models::className: bad id " + std::to_string(id));
  return table()[id];
}

bool isStructureClass(int id) {
  static const int first = classIdFromName("floor");
  return id >= first && id < first + 4;
}

}  // namespace rasm::models
