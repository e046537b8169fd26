// The documentation of a run folder cannot drift from what a run writes (issue 19, 4): a short
// simulated run's frames.csv columns, report.json fields and files are each described by `rasm
// help outputs`, which docs/outputs.md reproduces; report.json says which schema, binary and date
// it comes from; the PLY files type their ids as int32.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "RasmProcess.h"

namespace fs = std::filesystem;
using namespace rasm::app::testing;

namespace {

/// One short exploring run of the office for every test here (a few seconds).
class OutputsDoc : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = freshDir("outputs_doc");
    const Result r = runRasm("run --out " + dir_ + " " + shortRunArgs(6));
    ASSERT_EQ(r.status, 0) << r.output;
    doc_ = runRasm("help outputs", true);
    ASSERT_EQ(doc_.status, 0) << doc_.output;
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  /// The part of the documentation under "## <title>" (up to the next "## ").
  static std::string section(const std::string& title) {
    const std::size_t b = doc_.output.find("\n## " + title + "\n");
    if (b == std::string::npos) return "";
    const std::size_t e = doc_.output.find("\n## ", b + 4);
    return doc_.output.substr(b, e == std::string::npos ? std::string::npos : e - b);
  }
  /// Whether `table` has a row for `name` with a meaning.
  static bool documents(const std::string& table, const std::string& name) {
    const std::size_t row = table.find("\n| `" + name + "` |");
    if (row == std::string::npos) return false;
    const std::string line = table.substr(row + 1, table.find('\n', row + 1) - row - 1);
    return line.find("(undocumented)") == std::string::npos;
  }

  static std::string dir_;
  static Result doc_;
};
std::string OutputsDoc::dir_;
Result OutputsDoc::doc_;

}  // namespace

TEST_F(OutputsDoc, EveryFramesCsvColumnOfARunIsDocumented) {
  std::istringstream csv(readFile(dir_ + "/frames.csv"));
  std::string header;
  ASSERT_TRUE(std::getline(csv, header));
  ASSERT_EQ(header.rfind("index,timestamp_s,tracked,", 0), 0u) << "no header first: " << header;
  const std::string table = section("frames.csv");
  ASSERT_FALSE(table.empty()) << doc_.output;
  std::istringstream cols(header);
  std::string col;
  int n = 0;
  for (; std::getline(cols, col, ','); ++n)
    EXPECT_TRUE(documents(table, col)) << "frames.csv column '" << col
                                       << "' is not described in rasm help outputs "
                                          "(modules/pipeline/src/OutputsDoc.cpp kColumns)";
  EXPECT_GT(n, 50);  // the stages' columns and one ms_ column per timer
  // In the file's order, with the stage that writes it.
  EXPECT_NE(table.find("| `status` | tracking |"), std::string::npos) << table;
  EXPECT_NE(table.find("| `ms_seg_edges` | mapper | part of the `segmentation` stage"),
            std::string::npos)
      << table;
  EXPECT_LT(table.find("`index`"), table.find("`rss_mb`"));
}

TEST_F(OutputsDoc, EveryReportFieldAndFileOfARunIsDocumented) {
  const nlohmann::json rep = nlohmann::json::parse(readFile(dir_ + "/report.json"));
  const std::string fields = section("report.json"), files = section("Files");
  for (const auto& [key, value] : rep.items())
    EXPECT_TRUE(documents(fields, key)) << "report.json field '" << key
                                        << "' is not described in rasm help outputs "
                                           "(modules/pipeline/src/OutputsDoc.cpp kReport)";
  ASSERT_TRUE(rep["files"].is_array());
  EXPECT_GE(rep["files"].size(), 15u);
  for (const auto& f : rep["files"]) EXPECT_TRUE(documents(files, f.get<std::string>())) << f;
  EXPECT_EQ(doc_.output.find("(undocumented)"), std::string::npos) << doc_.output;
}

TEST_F(OutputsDoc, ReportSaysItsSchemaBinaryAndDate) {
  const nlohmann::json rep = nlohmann::json::parse(readFile(dir_ + "/report.json"));
  EXPECT_EQ(rep["report_schema"], 1);
  EXPECT_EQ(rep["frames_schema"], 1);
  const Result version = runRasm("--version");
  EXPECT_EQ(version.output, "rasm " + rep["rasm"]["version"].get<std::string>() + "\ncommit " +
                                rep["rasm"]["commit"].get<std::string>() + "\nbuilt " +
                                rep["rasm"]["build_date"].get<std::string>() + "\n");
  const std::regex utc("20[0-9]{2}-[01][0-9]-[0-3][0-9]T[0-2][0-9]:[0-5][0-9]:[0-6][0-9]Z");
  const std::string started = rep["started_utc"], finished = rep["finished_utc"];
  EXPECT_TRUE(std::regex_match(started, utc)) << started;
  EXPECT_TRUE(std::regex_match(finished, utc)) << finished;
  EXPECT_LE(started, finished);  // ISO 8601 sorts as time
}

TEST_F(OutputsDoc, PlyFilesTypeTheirIdsAsInt32) {
  for (const char* name : {"map.ply", "map_segments.ply", "map_classes.ply"}) {
    const std::string text = readFile(dir_ + "/" + name);
    const std::string header = text.substr(0, text.find("end_header"));
    ASSERT_FALSE(header.empty()) << name;
    EXPECT_NE(header.find("property int segment\nproperty int class\n"), std::string::npos)
        << name << ":\n"
        << header;
    EXPECT_EQ(header.find("uint"), std::string::npos) << name << ":\n" << header;
  }
  // The project's readers take them back.
  const Result check = runRasm("sim check-map office " + dir_ + "/map.ply");
  EXPECT_EQ(check.status, 0) << check.output;
  EXPECT_NE(check.output.find("surfels"), std::string::npos) << check.output;
}

TEST_F(OutputsDoc, DocsOutputsMdIsTheGeneratedText) {
  EXPECT_EQ(readFile(RASM_SOURCE_DIR "/docs/outputs.md"), doc_.output)
      << "docs/outputs.md is out of date: build/rasm help outputs > docs/outputs.md";
}
