#include "rasm/pipeline/Interrupts.h"

#include <fcntl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "rasm/pipeline/BuildInfo.h"
#include "rasm/pipeline/OutputSchema.h"

namespace rasm::pipeline {

namespace {
constexpr int kSlots = 16;
constexpr std::size_t kPathBytes = 4096;

/// A temporary the handler removes: state 0 free, 1 being filled, 2 registered.
struct Slot {
  std::atomic<int> state{0};
  char path[kPathBytes] = {};
};
Slot g_slots[kSlots];

std::atomic<int> g_signals{0};      // signals received
std::atomic<int> g_stop_signal{0};  // the first one
std::atomic<long long> g_frames_done{0};
std::atomic<bool> g_report_set{false};
char g_report_path[kPathBytes] = {};
char g_report_part[kPathBytes] = {};
char g_report_head[512] = {};  // the schema and binary fields, formatted by setAbortReport

void put(int fd, const char* s) {
  ssize_t r = ::write(fd, s, std::strlen(s));
  (void)r;
}

/// Decimal digits of v >= 0 into buf (async-signal-safe).
const char* digits(long long v, char (&buf)[24]) {
  char* p = buf + sizeof buf - 1;
  *p = '\0';
  do {
    *--p = char('0' + v % 10);
    v /= 10;
  } while (v > 0 && p > buf);
  return p;
}

const char* nameOf(int sig) {
  return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "a signal";
}

void writeAbortReport(int sig) {
  if (!g_report_set.load()) return;
  // Never through a file or link at that name (the registered temporaries are gone by now).
  const int fd = ::open(g_report_part, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0644);
  if (fd < 0) return;
  char buf[24];
  put(fd, "{\n");
  put(fd, g_report_head);
  put(fd, "  \"status\": \"aborted\",\n  \"error\": \"a second ");
  put(fd, nameOf(sig));
  put(fd,
      " aborted the run at once: the files of this run in this folder are complete, the others "
      "were not written\",\n  \"files_listed_in\": \".rasm-run.json\",\n  \"frames\": ");
  put(fd, digits(g_frames_done.load(), buf));
  put(fd, "\n}\n");
  if (::close(fd) == 0) ::rename(g_report_part, g_report_path);
}

std::atomic<bool> g_folder_set{false};
char g_folder[kPathBytes] = {};

/// Removes the files directly in g_folder, then the folder (async-signal-safe: the entries are
/// read with the getdents64 system call, not readdir).
void removeFolder() {
  if (!g_folder_set.load()) return;
  const int fd = ::open(g_folder, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buf[4096];
  for (;;) {
    const long n = ::syscall(SYS_getdents64, fd, buf, sizeof buf);
    if (n <= 0) break;
    for (long off = 0; off < n;) {
      // struct linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name.
      unsigned short reclen = 0;
      std::memcpy(&reclen, buf + off + 16, sizeof reclen);
      const char* name = buf + off + 19;
      if (std::strcmp(name, ".") != 0 && std::strcmp(name, "..") != 0)
        if (::unlinkat(fd, name, 0) != 0) ::unlinkat(fd, name, AT_REMOVEDIR);
      off += reclen;
    }
  }
  ::close(fd);
  ::rmdir(g_folder);
}

void onSignal(int sig) {
  if (g_signals.fetch_add(1) == 0) {
    g_stop_signal.store(sig);
    put(2, "\nrasm: ");
    put(2, nameOf(sig));
    put(2, ": finishing the current frame and writing the outputs (again to abort)\n");
    return;
  }
  for (Slot& s : g_slots)
    if (s.state.load() == 2) ::unlink(s.path);
  writeAbortReport(sig);
  removeFolder();
  put(2, "\nrasm: aborted\n");
  ::_exit(128 + sig);
}
}  // namespace

void installInterruptHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // A file size limit (ulimit -f) then fails the write (EFBIG) as a full disk does, and the
  // run reports it, instead of the process being killed with a partial file.
  std::signal(SIGXFSZ, SIG_IGN);
}

void uninstallInterruptHandlers() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGXFSZ, SIG_DFL);
  g_signals.store(0);
  g_stop_signal.store(0);
  g_report_set.store(false);
  g_frames_done.store(0);
}

int stopSignal() {
  return g_stop_signal.load();
}

std::string signalName(int sig) {
  if (sig == SIGINT || sig == SIGTERM) return nameOf(sig);
  return "signal " + std::to_string(sig);
}

ScopedTemporary::ScopedTemporary(const std::string& part) {
  if (part.size() >= kPathBytes) return;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (!g_slots[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_slots[i].path, part.c_str(), part.size() + 1);
    g_slots[i].state.store(2);
    m_slot = i;
    return;
  }
}

ScopedTemporary::~ScopedTemporary() {
  if (m_slot >= 0) g_slots[m_slot].state.store(0);
}

ScopedAbortRemovesFolder::ScopedAbortRemovesFolder(const std::string& dir) {
  g_folder_set.store(false);
  if (dir.empty() || dir.size() >= kPathBytes) return;
  std::memcpy(g_folder, dir.c_str(), dir.size() + 1);
  g_folder_set.store(true);
}

ScopedAbortRemovesFolder::~ScopedAbortRemovesFolder() {
  g_folder_set.store(false);
}

void setAbortReport(const std::string& report_path) {
  g_report_set.store(false);
  const std::string part = report_path + ".part";
  if (report_path.empty() || part.size() >= kPathBytes) return;
  std::memcpy(g_report_path, report_path.c_str(), report_path.size() + 1);
  std::memcpy(g_report_part, part.c_str(), part.size() + 1);
  const BuildInfo& b = buildInfo();
  std::snprintf(g_report_head, sizeof g_report_head,
                "  \"report_schema\": %d,\n  \"frames_schema\": %d,\n  \"rasm\": {\"version\": "
                "\"%s\", \"commit\": \"%s\", \"build_date\": \"%s\"},\n",
                kReportSchema, kFramesSchema, b.version.c_str(), b.commit.c_str(), b.date.c_str());
  g_report_set.store(true);
}

void setFramesDone(long long frames) {
  g_frames_done.store(frames);
}

}  // namespace rasm::pipeline
