#include "rasm/core/AtomicFile.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <vector>

#include "rasm/core/Error.h"

namespace fs = std::filesystem;

namespace rasm {

namespace {
/// Creates `path` as a new empty file, never through an existing name or link: false when the
/// name exists (EEXIST; a symlink there, dangling or not, counts), std::runtime_error on any
/// other failure.
bool createNew(const std::string& path, const std::string& final_path) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd >= 0) {
    ::close(fd);
    return true;
  }
  if (errno == EEXIST) return false;
  const int err = errno;
  const std::string why = std::strerror(err);
  errno = err;
  throw std::runtime_error("cannot create a temporary for " + final_path + " (" + path +
                           "): " + why);
}

std::string randomHex8() {
  static thread_local std::mt19937 gen{std::random_device{}()};
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08x", unsigned(gen()));
  return buf;
}
}  // namespace

std::string createExclusiveTemp(const std::string& final_path, const std::string& suffix) {
  std::string temp = final_path + suffix;
  if (createNew(temp, final_path)) return temp;
  // "<final><suffix>" is taken (a stale temporary, a user's file, a planted link): leave it be.
  for (int attempt = 0; attempt < 64; ++attempt) {
    temp = final_path + "." + randomHex8() + suffix;
    if (createNew(temp, final_path)) return temp;
  }
  errno = EEXIST;
  throw std::runtime_error("cannot create a temporary for " + final_path + ": " + final_path +
                           suffix + " and 64 random names beside it exist");
}

AtomicFile::AtomicFile(std::string final_path, const std::string& suffix)
    : m_final(std::move(final_path)), m_temp(createExclusiveTemp(m_final, suffix)) {}

AtomicFile::~AtomicFile() {
  if (!m_done) ::unlink(m_temp.c_str());
}

void AtomicFile::commit() {
  if (m_done) throw std::logic_error("AtomicFile::commit: " + m_final + " already committed");
  m_done = true;
  if (::rename(m_temp.c_str(), m_final.c_str()) == 0) return;
  const int err = errno;
  ::unlink(m_temp.c_str());
  errno = err;
  throw std::runtime_error("cannot rename " + m_temp + " to " + m_final + ": " +
                           std::strerror(err));
}

void writeFileAtomic(const std::string& path, const std::string& bytes) {
  AtomicFile file(path);
  std::FILE* f = std::fopen(file.path().c_str(), "wb");
  if (!f) throw std::runtime_error("cannot open " + file.path() + ": " + std::strerror(errno));
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int err = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written) errno = err;
  if (!written || !closed)
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno) +
                             (written ? " (at close)" : ""));
  file.commit();
}

void writeThroughTemporary(const std::string& path,
                           const std::function<bool(const std::string& temp)>& fill,
                           const std::string& suffix) {
  AtomicFile file(path, suffix);
  if (!fill(file.path())) throw std::runtime_error("cannot write " + path);
  file.commit();
}

void requireParentFolder(const std::string& path, const std::string& what) {
  fs::path p = fs::path(path).lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "out/" is the folder "out"
  const fs::path parent = p.parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  if (fs::is_directory(parent, ec)) return;
  throwInputError(what, "its folder '" + parent.string() + "' " +
                            (fs::exists(parent, ec) ? "is not a folder"
                                                    : "does not exist (create it first; rasm "
                                                      "creates no parent folders)"));
}

ScratchFolder::ScratchFolder(const std::string& prefix) {
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  if (ec) throw std::runtime_error("no temporary folder ($TMPDIR): " + ec.message());
  std::string pattern = (tmp / (prefix + "XXXXXX")).string();
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (!::mkdtemp(buf.data()))
    throw std::runtime_error("cannot create a folder " + pattern + ": " + std::strerror(errno));
  m_path = buf.data();
}

ScratchFolder::~ScratchFolder() {
  std::error_code ec;
  fs::remove_all(m_path, ec);  // symlinks inside are removed, never followed
}

}  // namespace rasm
