#include "rasm/classification/ClassList.h"

#include <stdexcept>

#include "rasm/core/Error.h"
#include "rasm/models/ClassVocabulary.h"

namespace rasm::classification {

std::vector<maps::MapClass> ClassList::defaultClasses() {
  std::vector<maps::MapClass> v;
  const auto& names = models::classNames();  // entry 0 is "none"
  for (int id = 1; id < int(names.size()); ++id)
    v.push_back({names[id], models::isCocoClass(id) ? "coco" : "rasm"});
  return v;
}

ClassList::ClassList(std::vector<maps::MapClass> classes, int max_classes)
    : m_classes(std::move(classes)), m_max_classes(std::min(max_classes, maps::kMaxClassId)) {}

int ClassList::find(const std::string& name) const {
  for (int k = 0; k < int(m_classes.size()); ++k)
    if (m_classes[k].name == name) return k + 1;
  const int id = models::classIdFromName(name);  // aliases: the vocabulary's canonical name
  if (id > 0) {
    const std::string& canonical = models::className(id);
    for (int k = 0; k < int(m_classes.size()); ++k)
      if (m_classes[k].name == canonical) return k + 1;
  }
  return -1;
}

int ClassList::idFor(const std::string& name, const std::string& source) {
  const int id = find(name);
  if (id > 0) return id;
  if (name.empty() || name == "none")
    throw InputError("class list: detector '" + source + "' has a class without a name");
  if (int(m_classes.size()) >= m_max_classes)
    throw InputError("class list: cannot add class '" + name + "' of detector '" + source +
                     "': the map holds at most " + std::to_string(m_max_classes) +
                     " classes ([map] n_classes)");
  m_classes.push_back({name, source});
  return int(m_classes.size());
}

std::vector<int> ClassList::registerDetector(const Detector& detector) {
  std::vector<int> ids;
  for (const std::string& n : detector.classNames()) ids.push_back(idFor(n, detector.name()));
  return ids;
}

const std::string& ClassList::name(int id) const {
  static const std::string none = "none";
  if (id == 0) return none;
  if (id < 0 || id > int(m_classes.size()))
    throw std::out_of_range("class list: no class id " + std::to_string(id));
  return m_classes[id - 1].name;
}

}  // namespace rasm::classification
