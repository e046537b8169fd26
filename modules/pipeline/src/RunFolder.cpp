#include "rasm/pipeline/RunFolder.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "rasm/core/Error.h"
#include "rasm/pipeline/OutputFiles.h"

namespace fs = std::filesystem;

namespace rasm::pipeline {

// overwritePolicy() is defined in RunParams.cpp, beside the [output] loader that validates
// with it (the INI fuzzer links the loaders without the folder code).

namespace {
/// The names an earlier run in `dir` listed, when it left a marker (or, from a rasm older than
/// the marker, a report.json with its "files"); only names a run can write count. nullopt: no
/// run of rasm marked the folder.
std::optional<std::set<std::string>> earlierRunNames(const fs::path& dir) {
  nlohmann::json listing;
  bool from_report = false;
  for (const char* name : {kRunMarkerName, "report.json"}) {
    std::error_code ec;
    if (!fs::is_regular_file(fs::symlink_status(dir / name, ec))) continue;
    std::ifstream f(dir / name);
    listing = nlohmann::json::parse(f, nullptr, false);
    from_report = std::string(name) == "report.json";
    if (from_report && !(listing.is_object() && listing.contains("report_schema")))
      listing = nullptr;  // not the report of a rasm run
    if (listing.is_object() && listing.contains("files") && listing["files"].is_array()) break;
    listing = nullptr;
  }
  if (listing.is_null()) return std::nullopt;
  std::set<std::string> names;
  if (from_report) names.insert("report.json");
  const auto& known = OutputFolder::knownNames();
  for (const auto& f : listing["files"])
    if (f.is_string() && std::find(known.begin(), known.end(), f.get<std::string>()) != known.end())
      names.insert(f.get<std::string>());
  return names;
}

/// "<name>.part" or "<name>.<8 hex digits>.part": a temporary of `name` (AtomicFile).
bool isTemporaryOf(const std::string& entry, const std::string& name) {
  if (entry == name + ".part") return true;
  const std::size_t n = name.size();
  if (entry.size() != n + 14 || entry.compare(0, n + 1, name + ".") != 0 ||
      entry.compare(n + 9, 5, ".part") != 0)
    return false;
  return std::all_of(entry.begin() + long(n) + 1, entry.begin() + long(n) + 9,
                     [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; });
}

/// Whether the earlier run that listed `names` wrote `entry`.
bool writtenByEarlierRun(const std::string& entry, const std::set<std::string>& names) {
  if (names.count(entry) || isTemporaryOf(entry, kRunMarkerName)) return true;
  // The annotated rawlog's external images, should an earlier version have written them.
  if (entry == "annotated_Images" && names.count("annotated.rawlog")) return true;
  return std::any_of(names.begin(), names.end(),
                     [&](const std::string& n) { return isTemporaryOf(entry, n); });
}

std::string quotedList(const std::vector<std::string>& names, std::size_t max_shown) {
  std::string list;
  for (std::size_t i = 0; i < names.size() && i < max_shown; ++i)
    list += (i ? ", '" : "'") + names[i] + "'";
  if (names.size() > max_shown)
    list += " and " + std::to_string(names.size() - max_shown) + " more";
  return list;
}
}  // namespace

RunFolderContents inspectRunFolder(const std::string& dir) {
  RunFolderContents c;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return c;
  const std::optional<std::set<std::string>> names = earlierRunNames(dir);
  c.marked = names.has_value();
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string entry = e.path().filename().string();
    if (entry == kRunMarkerName || entry == kRunLockName) continue;
    (names && writtenByEarlierRun(entry, *names) ? c.earlier_run : c.others).push_back(entry);
  }
  std::sort(c.earlier_run.begin(), c.earlier_run.end());
  std::sort(c.others.begin(), c.others.end());
  return c;
}

void refuseUnlessAllowed(const std::string& dir, const RunFolderContents& contents,
                         OverwritePolicy policy) {
  const std::string what = "[output] dir '" + dir + "'";
  if (policy == OverwritePolicy::BesideOthers) return;
  if (policy == OverwritePolicy::Never && !contents.earlier_run.empty())
    throwInputError(what, "holds the files of an earlier run (" +
                              quotedList(contents.earlier_run, 6) +
                              ") and [output] overwrite = false; nothing was changed");
  if (contents.others.empty()) return;
  const std::string found = contents.marked ? "holds files its earlier rasm run did not write: "
                                            : "is not the folder of a rasm run (no " +
                                                  std::string(kRunMarkerName) +
                                                  " or report.json of one) and holds: ";
  throwInputError(what, found + quotedList(contents.others, 8) +
                            ". Nothing was changed: choose an empty or new folder, or pass --force "
                            "([output] overwrite = true) to write rasm's files beside them (they "
                            "are left alone; only rasm's own file names are replaced)");
}

RunFolderLock::RunFolderLock(const std::string& dir) {
  const std::string path = (fs::path(dir) / kRunLockName).string();
  m_fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (m_fd < 0)
    throwInputError("[output] dir '" + dir + "'",
                    "cannot open its lock file " + path + ": " + std::strerror(errno));
  if (::flock(m_fd, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    char pid[32] = {};
    const ssize_t n = ::pread(m_fd, pid, sizeof pid - 1, 0);
    ::close(m_fd);
    m_fd = -1;
    if (err != EWOULDBLOCK)
      throwInputError("[output] dir '" + dir + "'", "cannot lock " + path + ": " + strerror(err));
    std::string holder(pid, n > 0 ? std::size_t(n) : 0);
    holder.erase(
        std::remove_if(holder.begin(), holder.end(),
                       [](char c) { return !std::isdigit(static_cast<unsigned char>(c)); }),
        holder.end());
    throw InputError(dir + " is in use by another rasm run (pid " +
                     (holder.empty() ? std::string("unknown") : holder) +
                     "); nothing was changed: wait for it to end or choose another --out");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  // Without the pid (a full disk) the lock still holds: a second run then says "pid unknown".
  if (::ftruncate(m_fd, 0) == 0) (void)!::pwrite(m_fd, pid.data(), pid.size(), 0);
}

RunFolderLock::~RunFolderLock() {
  if (m_fd >= 0) ::close(m_fd);  // releases the flock
}

}  // namespace rasm::pipeline
