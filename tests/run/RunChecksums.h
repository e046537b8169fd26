#pragma once
// Byte-identical behaviour across refactorings: a short run's outputs against CRC-32 checksums
// stored in tests/run/run_checksums.txt. What varies between two runs of the same binary on the
// same input (wall-clock times, peak memory, the output folder's path) is left out before the
// checksum, and the checkout's path is replaced by a placeholder (another clone of the same commit
// gives the same checksums); everything else (poses, surfels, segments, objects, per-frame
// counters, plans) is in.
//
// A change that alters behaviour on purpose regenerates the file and says why in its commit:
//   RASM_WRITE_CHECKSUMS=1 build/tests/test_run --gtest_filter='RunChecksums.*'
//   RASM_WRITE_CHECKSUMS=1 build/tests/test_autonomy --gtest_filter='RunChecksums.*'

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace rasm::run::testing {

inline const std::string kRunChecksumsFile =
    std::string(RASM_SOURCE_DIR) + "/tests/run/run_checksums.txt";

/// CRC-32 (zlib's) of `bytes` as 8 lower-case hex digits.
inline std::string crc32Hex(const std::string& bytes) {
  const uLong crc = ::crc32(::crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()),
                            static_cast<uInt>(bytes.size()));
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08lx", static_cast<unsigned long>(crc));
  return buf;
}

/// True for a JSON key or CSV column that holds a wall-clock time, a rate, a memory peak or the
/// build that ran (report.json's rasm.commit and rasm.build_date).
inline bool variesBetweenIdenticalRuns(const std::string& key) {
  const auto ends_with = [&](const char* s) {
    const std::string t(s);
    return key.size() >= t.size() && key.compare(key.size() - t.size(), t.size(), t) == 0;
  };
  return key == "ms" || ends_with("_ms") || key.rfind("ms_", 0) == 0 || ends_with("_utc") ||
         key == "cpu_ms_per_frame" || key == "fps" || key == "seconds" || key == "rss_mb" ||
         key == "peak_rss_mb" || key == "commit" || key == "build_date";
}

inline void dropVaryingKeys(nlohmann::json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      if (variesBetweenIdenticalRuns(it.key())) {
        it = j.erase(it);
      } else {
        dropVaryingKeys(*it);
        ++it;
      }
    }
  } else if (j.is_array()) {
    for (auto& e : j) dropVaryingKeys(e);
  }
}

/// frames.csv without its timing and memory columns.
inline std::string csvWithoutVaryingColumns(const std::string& text) {
  std::istringstream in(text);
  std::string line, out;
  std::vector<bool> keep;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) cells.push_back(c);
    if (keep.empty())
      for (const auto& c : cells) keep.push_back(!variesBetweenIdenticalRuns(c));
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (i >= keep.size() || keep[i]) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

/// `text` with the repository's path (RASM_SOURCE_DIR, where the test's inputs lie) replaced by a
/// placeholder: report.json names its input by absolute path, which differs between checkouts.
inline std::string withoutCheckoutPath(std::string text) {
  const std::string dir = RASM_SOURCE_DIR;
  for (std::size_t at = text.find(dir); at != std::string::npos; at = text.find(dir, at))
    text.replace(at, dir.size(), "<RASM_SOURCE_DIR>");
  return text;
}

/// The deterministic content of one output file of a run (JSON and CSV filtered as above and
/// without the checkout's path, every other file as its bytes).
inline std::string deterministicContent(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) ADD_FAILURE() << "missing output " << path;
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string bytes = ss.str();
  const auto has_suffix = [&](const char* s) {
    const std::string t(s);
    return path.size() >= t.size() && path.compare(path.size() - t.size(), t.size(), t) == 0;
  };
  if (has_suffix(".json")) {
    nlohmann::json j = nlohmann::json::parse(bytes, nullptr, false);
    if (j.is_discarded()) ADD_FAILURE() << path << " is not JSON";
    dropVaryingKeys(j);
    return withoutCheckoutPath(j.dump());
  }
  if (has_suffix(".csv")) return withoutCheckoutPath(csvWithoutVaryingColumns(bytes));
  return bytes;
}

/// "<case> <name> <crc>" lines of the stored file, keyed "<case> <name>".
inline std::map<std::string, std::string> readStoredChecksums() {
  std::map<std::string, std::string> stored;
  std::ifstream f(kRunChecksumsFile);
  for (std::string line; std::getline(f, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream w(line);
    std::string run_case, name, crc;
    if (w >> run_case >> name >> crc) stored[run_case + " " + name] = crc;
  }
  return stored;
}

inline bool writingChecksums() {
  const char* w = std::getenv("RASM_WRITE_CHECKSUMS");
  return w != nullptr && std::string(w) == "1";
}

/// Replaces the lines of `run_case` in the stored file by `crcs` (name -> crc).
inline void writeStoredChecksums(const std::string& run_case,
                                 const std::map<std::string, std::string>& crcs) {
  std::map<std::string, std::string> stored = readStoredChecksums();
  for (auto it = stored.begin(); it != stored.end();)
    it = it->first.rfind(run_case + " ", 0) == 0 ? stored.erase(it) : std::next(it);
  for (const auto& [name, crc] : crcs) stored[run_case + " " + name] = crc;
  std::ofstream f(kRunChecksumsFile);
  f << "# CRC-32 of short runs' outputs (tests/run/RunChecksums.h): <case> <file> <crc>.\n"
       "# Regenerated only for a change of behaviour that its commit names.\n";
  for (const auto& [key, crc] : stored) f << key << " " << crc << "\n";
}

/// Compares the outputs `files` of the run folder `dir` (and `extra`: name -> crc of something
/// else the case checks) with the stored checksums of `run_case`, or stores them under
/// RASM_WRITE_CHECKSUMS=1.
inline void expectStoredChecksums(const std::string& run_case, const std::string& dir,
                                  const std::vector<std::string>& files,
                                  std::map<std::string, std::string> extra = {}) {
  std::map<std::string, std::string> crcs = std::move(extra);
  for (const auto& name : files) {
    const std::string content = deterministicContent(dir + "/" + name);
    crcs[name] = crc32Hex(content);
    // What was compared, kept for a diff against a run of the commit before (RASM_CHECKSUM_DUMP).
    if (const char* dump = std::getenv("RASM_CHECKSUM_DUMP"))
      std::ofstream(std::string(dump) + "/" + run_case + "_" + name, std::ios::binary) << content;
  }
  if (writingChecksums()) {
    writeStoredChecksums(run_case, crcs);
    return;
  }
  const auto stored = readStoredChecksums();
  for (const auto& [name, crc] : crcs) {
    const auto it = stored.find(run_case + " " + name);
    if (it == stored.end()) {
      ADD_FAILURE() << run_case << ": no stored checksum of " << name << " in "
                    << kRunChecksumsFile;
      continue;
    }
    EXPECT_EQ(crc, it->second)
        << run_case << ": " << name << " differs from the stored run (" << kRunChecksumsFile
        << "): the behaviour changed. If on purpose, regenerate (RunChecksums.h) and say why in "
           "the commit";
  }
}

}  // namespace rasm::run::testing
