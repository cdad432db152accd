// Lobe-table plumbing: the speed grid (evenly_spaced_speeds) and the CSV/JSON
// writers, the contract CAM integrators parse (include/chatter/io/table_writer.hpp).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/lobes.hpp"

namespace {

using chatter::StabilityLimit;

// The writers print 10 significant digits: a value read back differs from the
// one written by at most half a unit in the 10th digit (5e-10 relative).
constexpr double kPrintedRelTol = 1e-9;
// Interior grid points come from one multiply-add in double precision; allow a
// few ulps of the range.
constexpr double kGridRelTol = 1e-12;

const double kInf = std::numeric_limits<double>::infinity();

std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream is(s);
  for (std::string line; std::getline(is, line);) out.push_back(line);
  return out;
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

StabilityLimit bounded_row() {
  StabilityLimit r;
  r.spindle_rpm = 1234.5;
  r.depth_limit_m = 1.2783456789e-3;
  r.chatter_frequency_hz = 97.123456789;
  r.lobe = 3;
  r.branch = 0;
  return r;
}

StabilityLimit unbounded_row() {
  StabilityLimit r;  // defaults: depth +inf, frequency NaN, lobe -1
  r.spindle_rpm = 2000.0;
  return r;
}

void expect_rel_near(double expected, double actual, double rel, const std::string& what) {
  EXPECT_LE(std::abs(actual - expected), rel * std::abs(expected)) << what << ": expected " << expected
                                                                   << ", got " << actual;
}

// ------------------------------------------------------------ evenly_spaced_speeds

TEST(EvenlySpacedSpeeds, IncludesBothEndsExactly) {
  for (int count : {2, 3, 7, 400, 1001}) {
    const double lo = 50.0, hi = 2000.0;
    const auto v = chatter::evenly_spaced_speeds(lo, hi, count);
    ASSERT_EQ(v.size(), static_cast<std::size_t>(count));
    EXPECT_EQ(v.front(), lo) << "count " << count;
    EXPECT_EQ(v.back(), hi) << "count " << count;
  }
  // Awkward values whose interior arithmetic does not round-trip.
  const auto v = chatter::evenly_spaced_speeds(0.1, 0.7, 3);
  EXPECT_EQ(v.front(), 0.1);
  EXPECT_EQ(v.back(), 0.7);
}

TEST(EvenlySpacedSpeeds, EvenSpacingAndIncreasing) {
  const double lo = 5000.0, hi = 25000.0;
  const int count = 401;
  const auto v = chatter::evenly_spaced_speeds(lo, hi, count);
  const double step = (hi - lo) / (count - 1);
  for (int i = 0; i < count; ++i) {
    EXPECT_NEAR(v[static_cast<std::size_t>(i)], lo + step * i, kGridRelTol * hi) << "i = " << i;
    if (i > 0) {
      EXPECT_GT(v[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(i - 1)]);
      EXPECT_NEAR(v[static_cast<std::size_t>(i)] - v[static_cast<std::size_t>(i - 1)], step, kGridRelTol * hi);
    }
  }
}

TEST(EvenlySpacedSpeeds, SinglePointWhenEndsCoincide) {
  const auto v = chatter::evenly_spaced_speeds(1200.0, 1200.0, 1);
  ASSERT_EQ(v.size(), 1u);
  EXPECT_EQ(v[0], 1200.0);
}

TEST(EvenlySpacedSpeeds, BadRangesThrowInputError) {
  // Negative or zero speeds.
  EXPECT_THROW(chatter::evenly_spaced_speeds(-5.0, 100.0, 10), chatter::InputError);
  EXPECT_THROW(chatter::evenly_spaced_speeds(0.0, 100.0, 10), chatter::InputError);
  EXPECT_THROW(chatter::evenly_spaced_speeds(-100.0, -5.0, 10), chatter::InputError);
  // rpm_max below rpm_min.
  EXPECT_THROW(chatter::evenly_spaced_speeds(2000.0, 50.0, 10), chatter::InputError);
  // Empty range for several points.
  EXPECT_THROW(chatter::evenly_spaced_speeds(1000.0, 1000.0, 10), chatter::InputError);
  // count < 1.
  EXPECT_THROW(chatter::evenly_spaced_speeds(50.0, 2000.0, 0), chatter::InputError);
  EXPECT_THROW(chatter::evenly_spaced_speeds(50.0, 2000.0, -3), chatter::InputError);
  // One point but two different ends.
  EXPECT_THROW(chatter::evenly_spaced_speeds(50.0, 2000.0, 1), chatter::InputError);
  // Non-finite ends.
  EXPECT_THROW(chatter::evenly_spaced_speeds(50.0, kInf, 10), chatter::InputError);
  EXPECT_THROW(chatter::evenly_spaced_speeds(std::nan(""), 2000.0, 10), chatter::InputError);
}

TEST(EvenlySpacedSpeeds, MessageNamesTheField) {
  try {
    chatter::evenly_spaced_speeds(2000.0, 50.0, 10);
    FAIL() << "no exception";
  } catch (const chatter::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rpm_max"), std::string::npos) << e.what();
  }
  try {
    chatter::evenly_spaced_speeds(50.0, 2000.0, 0);
    FAIL() << "no exception";
  } catch (const chatter::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rpm_points"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------ write_lobe_csv

TEST(WriteLobeCsv, HeaderOnlyForNoRows) {
  std::ostringstream os;
  chatter::write_lobe_csv(os, {});
  EXPECT_EQ(os.str(), "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe\n");
}

TEST(WriteLobeCsv, BoundedAndUnboundedRows) {
  std::ostringstream os;
  chatter::write_lobe_csv(os, {bounded_row(), unbounded_row()});
  const std::string text = os.str();
  const auto lines = split_lines(text);
  ASSERT_EQ(lines.size(), 3u) << text;
  EXPECT_EQ(lines[0], "spindle_rpm,depth_limit_mm,chatter_frequency_hz,lobe");

  // Bounded row: depth converted from m to mm.
  const auto b = split_fields(lines[1]);
  ASSERT_EQ(b.size(), 4u) << lines[1];
  expect_rel_near(1234.5, std::stod(b[0]), kPrintedRelTol, "rpm");
  expect_rel_near(1.2783456789, std::stod(b[1]), kPrintedRelTol, "depth_limit_mm");
  expect_rel_near(97.123456789, std::stod(b[2]), kPrintedRelTol, "frequency");
  EXPECT_EQ(b[3], "3");

  // Unbounded row: inf and empty frequency / lobe.
  EXPECT_EQ(lines[2], "2000,inf,,") << "unbounded row";

  EXPECT_EQ(text.find("nan"), std::string::npos) << text;
  EXPECT_EQ(text.find("NaN"), std::string::npos) << text;
}

TEST(WriteLobeCsv, UnboundedRowNeverPrintsNanEvenWithJunkFields) {
  // A solver may leave frequency/lobe set on an unbounded row; the table still
  // prints inf and empty fields.
  StabilityLimit r = unbounded_row();
  r.chatter_frequency_hz = std::nan("");
  r.lobe = 7;
  std::ostringstream os;
  chatter::write_lobe_csv(os, {r});
  const auto lines = split_lines(os.str());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1], "2000,inf,,");
}

TEST(WriteLobeCsv, ByteIdenticalForIdenticalInput) {
  std::ostringstream a, b;
  chatter::write_lobe_csv(a, {bounded_row(), unbounded_row(), bounded_row()});
  chatter::write_lobe_csv(b, {bounded_row(), unbounded_row(), bounded_row()});
  EXPECT_EQ(a.str(), b.str());
}

// ----------------------------------------------------------------- write_lobe_json

chatter::Config small_config() {
  chatter::Config cfg;
  cfg.name = "unit_test_config";
  cfg.source = "unit/test.toml";
  cfg.model.workpiece.modes.push_back(chatter::Mode::from_stiffness(94.22, 0.033, 45e6, {1.0, 0.0}));
  cfg.process = chatter::Process::turning({2.4e9});
  return cfg;
}

chatter::TableProvenance provenance(const chatter::Config* cfg) {
  chatter::TableProvenance p;
  p.method = "analytic";
  p.config = cfg;
  p.rpm_min = 50.0;
  p.rpm_max = 2000.0;
  p.rpm_points = 2;
  p.depth_max_mm = 20.0;
  chatter::AbsoluteLimit abs;
  abs.depth_m = 1.2783e-3;
  abs.chatter_frequency_hz = 97.0;
  abs.branch = 0;
  p.absolute_limit = abs;
  p.options_json = R"({"depth_max_m": 0.02})";
  return p;
}

TEST(WriteLobeJson, ParsesBackWithSameNumbers) {
  const chatter::Config cfg = small_config();
  std::ostringstream os;
  chatter::write_lobe_json(os, {bounded_row(), unbounded_row()}, provenance(&cfg));
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(os.str())) << os.str();

  EXPECT_EQ(j.at("method"), "analytic");
  ASSERT_TRUE(j.contains("version"));
  EXPECT_EQ(j.at("version"), chatter::version());
  EXPECT_EQ(j.at("format"), "chatter-lobe-table");
  ASSERT_TRUE(j.contains("config"));
  EXPECT_EQ(j.at("config").at("name"), "unit_test_config");
  EXPECT_EQ(j.at("options").at("depth_max_m"), 0.02);

  const auto& rows = j.at("rows");
  ASSERT_TRUE(rows.is_array());
  ASSERT_EQ(rows.size(), 2u);

  const auto& b = rows[0];
  expect_rel_near(1234.5, b.at("spindle_rpm").get<double>(), kPrintedRelTol, "rpm");
  expect_rel_near(1.2783456789, b.at("depth_limit_mm").get<double>(), kPrintedRelTol, "depth_limit_mm");
  expect_rel_near(97.123456789, b.at("chatter_frequency_hz").get<double>(), kPrintedRelTol, "frequency");
  EXPECT_EQ(b.at("lobe").get<int>(), 3);

  const auto& u = rows[1];
  expect_rel_near(2000.0, u.at("spindle_rpm").get<double>(), kPrintedRelTol, "rpm");
  EXPECT_TRUE(u.at("depth_limit_mm").is_null());
  EXPECT_TRUE(u.at("chatter_frequency_hz").is_null());
  EXPECT_TRUE(u.at("lobe").is_null());

  EXPECT_EQ(os.str().find("nan"), std::string::npos);
  EXPECT_EQ(os.str().find("NaN"), std::string::npos);
  EXPECT_EQ(os.str().find("inf"), std::string::npos);
}

TEST(WriteLobeJson, SameNumbersAsCsv) {
  const chatter::Config cfg = small_config();
  const std::vector<StabilityLimit> rows = {bounded_row(), unbounded_row()};
  std::ostringstream csv, js;
  chatter::write_lobe_csv(csv, rows);
  chatter::write_lobe_json(js, rows, provenance(&cfg));
  const auto j = nlohmann::json::parse(js.str());
  const auto fields = split_fields(split_lines(csv.str())[1]);
  // Both go through the same 10-digit rounding, so the values agree exactly.
  EXPECT_EQ(j["rows"][0]["spindle_rpm"].get<double>(), std::stod(fields[0]));
  EXPECT_EQ(j["rows"][0]["depth_limit_mm"].get<double>(), std::stod(fields[1]));
  EXPECT_EQ(j["rows"][0]["chatter_frequency_hz"].get<double>(), std::stod(fields[2]));
  EXPECT_EQ(j["rows"][0]["lobe"].get<int>(), std::stoi(fields[3]));
}

TEST(WriteLobeJson, NoConfigWhenNoneGiven) {
  std::ostringstream os;
  chatter::write_lobe_json(os, {bounded_row()}, provenance(nullptr));
  const auto j = nlohmann::json::parse(os.str());
  EXPECT_FALSE(j.contains("config"));
  EXPECT_EQ(j.at("method"), "analytic");
  EXPECT_EQ(j.at("rows").size(), 1u);
}

TEST(WriteLobeJson, UnboundedAbsoluteLimitIsNull) {
  chatter::TableProvenance p = provenance(nullptr);
  p.absolute_limit = chatter::AbsoluteLimit{};  // +inf depth, NaN frequency
  std::ostringstream os;
  chatter::write_lobe_json(os, {unbounded_row()}, p);
  const auto j = nlohmann::json::parse(os.str());
  EXPECT_TRUE(j.at("absolute_limit").at("depth_mm").is_null());
  EXPECT_TRUE(j.at("absolute_limit").at("chatter_frequency_hz").is_null());
}

// ---- write_text_files: all-or-nothing, and never replaces a special file ----

std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("chatter_write_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

TEST(WriteTextFiles, NothingIsCreatedWhenOneTargetFails) {
  const auto d = fresh_dir("allornothing");
  EXPECT_THROW(chatter::write_text_files({{d / "table.csv", "a\n"}, {d / "missing" / "t.json", "{}"}}), chatter::InputError);
  EXPECT_TRUE(std::filesystem::is_empty(d)) << "no target and no temporary may remain";
  std::filesystem::remove_all(d);
}

TEST(WriteTextFiles, ReplacesARegularFileWhole) {
  const auto d = fresh_dir("replace");
  chatter::write_text_file(d / "t.csv", "a much longer first version\n");
  chatter::write_text_file(d / "t.csv", "short\n");
  std::ifstream in(d / "t.csv");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "short\n");
  std::filesystem::remove_all(d);
}

TEST(WriteTextFiles, SpecialFileIsWrittenInPlaceNotReplaced) {
  // A FIFO stands for /dev/null or /dev/stdout: renaming over it would turn
  // it into a regular file.
  const auto d = fresh_dir("fifo");
  const auto fifo = d / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] {
    std::ifstream in(fifo);
    got.assign(std::istreambuf_iterator<char>(in), {});
  });
  chatter::write_text_file(fifo, "hello\n");
  reader.join();
  EXPECT_EQ(got, "hello\n");
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  std::filesystem::remove_all(d);
}

TEST(WriteTextFiles, SymbolicLinkIsWrittenThroughNotReplaced) {
  const auto d = fresh_dir("symlink");
  chatter::write_text_file(d / "real.csv", "old contents, longer\n");
  std::filesystem::create_symlink(d / "real.csv", d / "link.csv");
  chatter::write_text_file(d / "link.csv", "new\n");
  EXPECT_TRUE(std::filesystem::is_symlink(d / "link.csv"));
  std::ifstream in(d / "real.csv");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "new\n");
  std::filesystem::remove_all(d);
}

}  // namespace
