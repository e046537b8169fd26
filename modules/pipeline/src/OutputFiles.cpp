#include "rasm/pipeline/OutputFiles.h"

#include <filesystem>
#include <fstream>

#include "rasm/core/Error.h"

namespace rasm::pipeline {

void writeFileAtomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".part";
  {
    std::ofstream f(tmp, std::ios::binary);
    if (!f) throwInputError("output file '" + path + "'", "cannot be created");
    f << text;
    if (!f) throwInputError("output file '" + path + "'", "write failed");
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace rasm::pipeline
