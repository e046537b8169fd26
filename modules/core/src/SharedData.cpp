#include "rasm/core/SharedData.h"

#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace rasm {

namespace {
const std::string kSharedPrefix = "../shared/data/";
}  // namespace

std::vector<std::string> sharedDataFolders() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("RASM_SHARED_DATA"); env && *env) out.emplace_back(env);
#ifdef RASM_SHARED_DATA_DIR
  out.emplace_back(RASM_SHARED_DATA_DIR);
#endif
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    out.push_back((exe.parent_path().parent_path().parent_path() / "shared" / "data").string());
  return out;
}

std::string resolveSharedData(const std::string& path) {
  std::error_code ec;
  if (path.rfind(kSharedPrefix, 0) != 0 || fs::exists(path, ec)) return path;
  const std::string rest = path.substr(kSharedPrefix.size());
  for (const std::string& folder : sharedDataFolders())
    if (fs::exists(fs::path(folder) / rest, ec)) return (fs::path(folder) / rest).string();
  return path;
}

}  // namespace rasm
