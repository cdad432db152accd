// Lobe-table plumbing: the speed grids (evenly_spaced_speeds, and the adaptive
// refine_envelope / adaptive_envelope checked on case A in closed form) and the CSV/JSON
// writers, the contract CAM integrators parse (include/chatter/io/table_writer.hpp).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <complex>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <random>
#include <fstream>
#include <iterator>
#include <thread>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/columns.hpp"
#include "chatter/io/table_writer.hpp"
#include "chatter/records/lobes.hpp"
#include "chatter/lobes.hpp"
#include "chatter/semi_discretization.hpp"
#include "chatter/transfer_function.hpp"

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

// The tables print a number as printf's "%.10g" (docs/results.md): the
// writer's faster conversion must give the same text for every double.
TEST(TableNumber, IsPrintfsTenSignificantDigits) {
  auto printf10 = [](double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return std::string(buf);
  };
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-320, 308);
  std::uniform_int_distribution<std::uint64_t> bits;
  for (int i = 0; i < 200000; ++i) {
    const double x = mantissa(rng) * std::pow(10.0, exponent(rng));
    ASSERT_EQ(chatter::table_number(x), printf10(x)) << std::hexfloat << x;
    double y = 0.0;  // any bit pattern but NaN and inf
    const std::uint64_t b = bits(rng);
    std::memcpy(&y, &b, sizeof y);
    if (std::isfinite(y)) {
      ASSERT_EQ(chatter::table_number(y), printf10(y)) << std::hexfloat << y;
    }
  }
  for (const double x : {0.0, -0.0, 1.0, 0.1, 1e-5, 1e-4, 123456789.0, 1234567890.0, 12345678901.0, 9.9999999995,
                         9.99999999949, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 0.5e-5, 2.5, 3.5})
    EXPECT_EQ(chatter::table_number(x), printf10(x)) << x;
  EXPECT_EQ(chatter::table_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(chatter::table_number(-std::numeric_limits<double>::infinity()), "-inf");
}

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

// The columns of a table result (chatter/io/columns.hpp) as the CLI's CSV:
// numbers as table_number, NaN empty, +inf "inf", booleans 1/0, text as is.
TEST(ColumnsCsv, CellsAsEveryTableWritesThem) {
  const double nan = std::nan(""), inf = std::numeric_limits<double>::infinity();
  const std::vector<chatter::Column> t = {{"a_mm", std::vector<double>{1.0 / 3.0, nan, inf}},
                                          {"k", std::vector<int>{3, -1, 0}},
                                          {"stable", std::vector<bool>{true, false, true}},
                                          {"type", std::vector<std::string>{"hopf", "", "flip"}}};
  EXPECT_EQ(chatter::columns_csv(t), "a_mm,k,stable,type\n0.3333333333,3,1,hopf\n,-1,0,\ninf,0,1,flip\n");
  EXPECT_EQ(chatter::columns_csv({{"x", std::vector<double>{}}}), "x\n");
  // A grid, a complex column or columns of two lengths are no CSV table.
  EXPECT_THROW(chatter::columns_csv({{"rho", std::vector<double>{1, 2, 3, 4}, 2}}), std::logic_error);
  EXPECT_THROW(chatter::columns_csv({{"g", std::vector<std::complex<double>>{{1, 2}}}}), std::logic_error);
  EXPECT_THROW(chatter::columns_csv({{"a", std::vector<double>{1}}, {"b", std::vector<double>{1, 2}}}),
               std::logic_error);
}

// Python's lobe table (lobe_columns, full precision) against the CLI's CSV
// (write_lobe_csv, a separate writer): the same columns in the same order,
// every number equal to the printed one within its 10 digits, +inf where the
// CSV says inf, NaN frequency and lobe -1 where its cells are empty.
TEST(LobeColumns, AreTheCsvColumnsAtFullPrecision) {
  const std::vector<StabilityLimit> rows = {bounded_row(), unbounded_row()};
  std::ostringstream os;
  chatter::write_lobe_csv(os, rows);
  const auto lines = split_lines(os.str());
  const chatter::ColumnRecord r = chatter::lobe_columns(rows, {}, {}, {"sdm", nullptr, {"a note"}, 12.0});
  std::string header;
  for (const chatter::Column& c : r.columns) header += (header.empty() ? "" : ",") + c.name;
  EXPECT_EQ(header, lines[0]);
  const auto& rpm = std::get<std::vector<double>>(r.columns[0].values);
  const auto& depth = std::get<std::vector<double>>(r.columns[1].values);
  const auto& freq = std::get<std::vector<double>>(r.columns[2].values);
  const auto& lobe = std::get<std::vector<int>>(r.columns[3].values);
  const auto b = split_fields(lines[1]);
  expect_rel_near(std::stod(b[0]), rpm[0], kPrintedRelTol, "rpm");
  expect_rel_near(std::stod(b[1]), depth[0], kPrintedRelTol, "depth_limit_mm");
  expect_rel_near(std::stod(b[2]), freq[0], kPrintedRelTol, "frequency");
  EXPECT_EQ(std::to_string(lobe[0]), b[3]);
  EXPECT_EQ(lines[2], "2000,inf,,");
  EXPECT_TRUE(std::isinf(depth[1]) && depth[1] > 0.0);
  EXPECT_TRUE(std::isnan(freq[1]));
  EXPECT_EQ(lobe[1], -1);
  EXPECT_EQ(r.fields["method"], "sdm");
  EXPECT_EQ(r.fields["notes"], nlohmann::json::array({"a note"}));
  EXPECT_EQ(r.fields["depth_max_mm"], 12.0);
}

TEST(WriteLobeCsv, ByteIdenticalForIdenticalInput) {
  std::ostringstream a, b;
  chatter::write_lobe_csv(a, {bounded_row(), unbounded_row(), bounded_row()});
  chatter::write_lobe_csv(b, {bounded_row(), unbounded_row(), bounded_row()});
  EXPECT_EQ(a.str(), b.str());
}

// ---------------------------------------------------- lobe_table_record (JSON)

// The record as `chatter lobes --json` writes it.
void write_lobe_json(std::ostream& os, const std::vector<StabilityLimit>& rows, const chatter::TableProvenance& p) {
  os << chatter::lobe_table_record(rows, p).dump(2) << '\n';
}

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
  p.options = {{"depth_max_m", 0.02}};
  return p;
}

TEST(WriteLobeJson, ParsesBackWithSameNumbers) {
  const chatter::Config cfg = small_config();
  std::ostringstream os;
  write_lobe_json(os, {bounded_row(), unbounded_row()}, provenance(&cfg));
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
  write_lobe_json(js, rows, provenance(&cfg));
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
  write_lobe_json(os, {bounded_row()}, provenance(nullptr));
  const auto j = nlohmann::json::parse(os.str());
  EXPECT_FALSE(j.contains("config"));
  EXPECT_EQ(j.at("method"), "analytic");
  EXPECT_EQ(j.at("rows").size(), 1u);
}

TEST(WriteLobeJson, UnboundedAbsoluteLimitIsNull) {
  chatter::TableProvenance p = provenance(nullptr);
  p.absolute_limit = chatter::AbsoluteLimit{};  // +inf depth, NaN frequency
  std::ostringstream os;
  write_lobe_json(os, {unbounded_row()}, p);
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

// ------------------------------------------------------------ refine_envelope / adaptive_envelope

namespace {

// Case A (docs/physics.md, validation case A) in closed form, independent of the library's phase
// search: G(ω) = 1 / (k (1 − r² + 2jζr)), b = −1/(2 K_f Re G),
// ε = 3π + 2 atan2(Im G, Re G), N_k(ω) = 60 ω / (ε + 2πk) (turning).
struct CaseA {
  double wn = 2 * M_PI * 94.22, zeta = 0.033, k = 45e6, kf = 2.4e9;
  std::complex<double> g(double w) const {
    const double r = w / wn;
    return 1.0 / (k * std::complex<double>(1 - r * r, 2 * zeta * r));
  }
  double depth(double w) const { return -1.0 / (2 * kf * g(w).real()); }
  double rpm(double w, int lobe) const {
    const std::complex<double> G = g(w);
    return 60 * w / (3 * M_PI + 2 * std::atan2(G.imag(), G.real()) + 2 * M_PI * lobe);
  }
  // Depth (m) of lobe `lobe` at `n` rev/min: N_k(ω) rises monotonically from
  // N_k(ω_n) on ω > ω_n, so bisection on ω; +inf below the lobe's first speed.
  double lobe_depth(int lobe, double n) const {
    double lo = wn * (1 + 1e-12), hi = 2 * wn;
    if (rpm(lo, lobe) >= n) return kInf;
    while (rpm(hi, lobe) < n) hi *= 2;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (rpm(mid, lobe) < n ? lo : hi) = mid;
    }
    return depth(0.5 * (lo + hi));
  }
  // The speed where lobes `lobe` and `lobe + 1` cross, bisecting their depth
  // difference inside [lo, hi] (which must bracket the crossing).
  double cusp_rpm(int lobe, double lo, double hi) const {
    auto diff = [&](double n) { return lobe_depth(lobe, n) - lobe_depth(lobe + 1, n); };
    const bool lo_positive = diff(lo) > 0;
    EXPECT_NE(lo_positive, diff(hi) > 0) << "no crossing of lobes " << lobe << ", " << lobe + 1 << " in [" << lo
                                         << ", " << hi << "]";
    for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      ((diff(mid) > 0) == lo_positive ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

chatter::AnalyticSolver case_a_solver() {
  const chatter::Config cfg = chatter::load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml");
  chatter::TransferFunctionOptions o;
  o.depth_max_m = 20e-3;
  return chatter::AnalyticSolver(cfg.model, cfg.process, o);
}

// Depth of the straight line through the rows at `rpm` (rows increasing).
double interpolate(const std::vector<StabilityLimit>& rows, double rpm) {
  auto it = std::upper_bound(rows.begin(), rows.end(), rpm,
                             [](double x, const StabilityLimit& r) { return x < r.spindle_rpm; });
  if (it == rows.begin()) return rows.front().depth_limit_m;
  if (it == rows.end()) return rows.back().depth_limit_m;
  const StabilityLimit &b = *it, &a = *(it - 1);
  const double t = (rpm - a.spindle_rpm) / (b.spindle_rpm - a.spindle_rpm);
  return a.depth_limit_m + t * (b.depth_limit_m - a.depth_limit_m);
}

// The refinement's own criterion (EnvelopeRefinement): 0.5 % of the local depth.
constexpr double kRefineRelTol = 0.005;
// Case A's lobes are at most about 3 mm/(rev/min) steep next to a cusp at 50
// rev/min; a cusp bracket 1e-6 × 50 rev/min wide then leaves its rows within
// 1.5e-4 mm of the cusp depth, 1.2e-4 of 1.28 mm: allow 3e-4.
constexpr double kCuspDepthRelTol = 3e-4;
// A cusp is bracketed by two rows at most cusp_rel_tol (1e-6) × speed apart;
// its midpoint is within half of that of the crossing (plus round-off).
constexpr double kCuspRpmRelTol = 0.6e-6;
// The analytic solver and the closed form both solve to round-off (Brent's
// method to 1e-15 relative on ω); ω-to-depth conditioning near a cusp's
// steep side costs a few digits.
constexpr double kExactRelTol = 1e-9;

chatter::RefinedEnvelope refined_case_a(const chatter::AnalyticSolver& solver, unsigned threads = 1) {
  const auto speeds = chatter::evenly_spaced_speeds(50, 2000, 400);
  chatter::EnvelopeRefinement o;
  o.depth_rel_tol = kRefineRelTol;
  o.cusp_rel_tol = 1e-6;
  return chatter::refine_envelope(solver, chatter::lobe_envelope(solver, speeds), o, threads);
}

}  // namespace

TEST(RefineEnvelope, CaseACuspsAreTheCrossingsOfNeighbouringLobes) {
  const chatter::AnalyticSolver solver = case_a_solver();
  const chatter::RefinedEnvelope r = refined_case_a(solver);
  ASSERT_TRUE(r.converged) << r.solves << " solves";
  const CaseA a;
  int cusps = 0;
  double worst_depth = 0, worst_rpm = 0;
  for (std::size_t i = 0; i + 1 < r.rows.size(); ++i) {
    const StabilityLimit &lo = r.rows[i], &hi = r.rows[i + 1];
    ASSERT_TRUE(lo.bounded() && hi.bounded());
    if (lo.lobe == hi.lobe) continue;
    // Lobe numbers fall by one from one lobe to the next as the speed rises.
    ASSERT_EQ(lo.lobe, hi.lobe + 1) << "at " << lo.spindle_rpm << " rev/min";
    ++cusps;
    const double pad = 1e-3 * hi.spindle_rpm;
    const double n_star = a.cusp_rpm(hi.lobe, lo.spindle_rpm - pad, hi.spindle_rpm + pad);
    const double n_mid = 0.5 * (lo.spindle_rpm + hi.spindle_rpm);
    EXPECT_LE(std::abs(n_mid - n_star), kCuspRpmRelTol * n_star)
        << "cusp " << hi.lobe << "/" << lo.lobe << ": refined " << n_mid << ", crossing " << n_star;
    const double d_star = a.lobe_depth(hi.lobe, n_star);
    const double d_rows = std::max(lo.depth_limit_m, hi.depth_limit_m);
    EXPECT_LE(std::abs(d_rows - d_star), kCuspDepthRelTol * d_star)
        << "cusp at " << n_star << " rev/min: rows " << d_rows << " m, crossing " << d_star << " m";
    // The exact solve at the crossing is the crossing's depth.
    const StabilityLimit exact = solver.limit_at(chatter::SpindleSpeed(n_star));
    EXPECT_LE(std::abs(exact.depth_limit_m - d_star), kExactRelTol * d_star)
        << "limit_at(" << n_star << ") = " << exact.depth_limit_m << " m, closed form " << d_star << " m";
    worst_depth = std::max(worst_depth, std::abs(d_rows - d_star) / d_star);
    worst_rpm = std::max(worst_rpm, std::abs(n_mid - n_star) / n_star);
  }
  // 50-2000 rev/min holds lobes k = 2 to about 112: every crossing between.
  EXPECT_GE(cusps, 100);
  std::cout << "case A: " << r.rows.size() << " rows (" << r.solves << " solves), " << cusps
            << " cusps, worst cusp depth error " << worst_depth << ", worst cusp speed error " << worst_rpm << "\n";
}

TEST(RefineEnvelope, CaseALineStaysWithinToleranceAtRandomSpeeds) {
  const chatter::AnalyticSolver solver = case_a_solver();
  const chatter::RefinedEnvelope r = refined_case_a(solver);
  ASSERT_TRUE(r.converged);
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> speed(50.0, 2000.0);
  double worst = 0;
  for (int i = 0; i < 3000; ++i) {
    const double n = i < 1500 ? speed(rng) : 50.0 + 250.0 * (i - 1500) / 1500.0 + 0.0137;  // dense lobes below 300
    const double line = interpolate(r.rows, n), exact = solver.limit_at(chatter::SpindleSpeed(n)).depth_limit_m;
    const double tol = kRefineRelTol * exact + 1e-7;
    EXPECT_LE(line - exact, tol) << "above the exact envelope at " << n << " rev/min: line " << line
                                 << " m, exact " << exact << " m";
    EXPECT_LE(exact - line, tol) << "below the exact envelope at " << n << " rev/min: line " << line
                                 << " m, exact " << exact << " m";
    worst = std::max(worst, std::abs(line - exact) / exact);
  }
  std::cout << "worst relative distance of the line from the exact envelope: " << worst << "\n";
}

TEST(RefineEnvelope, SameRowsWhateverTheThreadCount) {
  const chatter::AnalyticSolver solver = case_a_solver();
  const auto one = refined_case_a(solver, 1), two = refined_case_a(solver, 3);
  ASSERT_EQ(one.rows.size(), two.rows.size());
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    EXPECT_EQ(one.rows[i].spindle_rpm, two.rows[i].spindle_rpm) << "row " << i;
    EXPECT_EQ(one.rows[i].depth_limit_m, two.rows[i].depth_limit_m) << "row " << i;
  }
}

// The adaptive sdm table (`lobes --rpm-spacing adaptive`) on case C, 2-DOF
// milling: every row (speed, depth, frequency, lobe, branch) the same on 1,
// 2 and 3 threads: the midpoints of one refinement level are solved in
// parallel and merged in speed order.
TEST(RefineEnvelope, AdaptiveSdmTableSameRowsWhateverTheThreadCount) {
  const chatter::Config cfg = chatter::load_config(std::string(CHATTER_SOURCE_DIR) + "/configs/milling_up_ae05_2dof.toml");
  const chatter::SemiDiscretizationSolver sdm(cfg.model, cfg.process);
  const auto limit = [&](double rpm) { return sdm.limit_at(chatter::SpindleSpeed(rpm)); };
  const chatter::EnvelopeRefinement o;
  const auto one = chatter::adaptive_envelope(limit, 5000, 25000, 120, o, 1);
  for (unsigned threads : {2u, 3u}) {
    const auto many = chatter::adaptive_envelope(limit, 5000, 25000, 120, o, threads);
    ASSERT_EQ(one.rows.size(), many.rows.size()) << threads << " threads";
    EXPECT_EQ(one.solves, many.solves);
    for (std::size_t i = 0; i < one.rows.size(); ++i) {
      SCOPED_TRACE("row " + std::to_string(i) + ", " + std::to_string(threads) + " threads");
      EXPECT_EQ(one.rows[i].spindle_rpm, many.rows[i].spindle_rpm);
      EXPECT_EQ(one.rows[i].depth_limit_m, many.rows[i].depth_limit_m);
      EXPECT_EQ(one.rows[i].chatter_frequency_hz, many.rows[i].chatter_frequency_hz);
      EXPECT_EQ(one.rows[i].lobe, many.rows[i].lobe);
      EXPECT_EQ(one.rows[i].branch, many.rows[i].branch);
    }
  }
  EXPECT_GT(one.rows.size(), 60u);
}

TEST(RefineEnvelope, KeepsToTheSolveBudget) {
  const chatter::AnalyticSolver solver = case_a_solver();
  const auto start = chatter::lobe_envelope(solver, chatter::evenly_spaced_speeds(50, 2000, 40));
  chatter::EnvelopeRefinement o;
  o.max_solves = 57;
  std::atomic<std::size_t> calls{0};
  const auto r = chatter::refine_envelope(
      [&](double n) {
        ++calls;
        return solver.limit_at(chatter::SpindleSpeed(n));
      },
      start, o, 2);
  EXPECT_EQ(r.solves, 57u);
  EXPECT_EQ(calls.load(), 57u);
  EXPECT_EQ(r.rows.size(), 40u + 57u);
  EXPECT_FALSE(r.converged);
  for (std::size_t i = 0; i + 1 < r.rows.size(); ++i) EXPECT_LT(r.rows[i].spindle_rpm, r.rows[i + 1].spindle_rpm);
}

// A problem built from its answer: two parabolic "lobes" d1 = 1 + (n − 3)²,
// d2 = 1 + (n − 7)²/4 (lobe 1 and 0), envelope their minimum; they cross at
// n* = 13/3 − √(64/9 − 4·... ) solved exactly below; above depth 4 there is
// "no limit" (+inf), so the gap edges are located too.
TEST(RefineEnvelope, SyntheticLobesCuspAndGapEdgesAreLocated) {
  const double cap = 4.0;
  auto env = [&](double n) {
    StabilityLimit r;
    r.spindle_rpm = n;
    const double d1 = 1 + (n - 3) * (n - 3), d2 = 1 + (n - 7) * (n - 7) / 4;
    const double d = std::min(d1, d2);
    if (d >= cap) return r;  // unbounded
    r.depth_limit_m = d;
    r.lobe = d1 < d2 ? 1 : 0;
    r.branch = 0;
    return r;
  };
  // d1 = d2: 4(n−3)² = (n−7)²  ->  2(n−3) = ±(n−7): n = −1 or n = 13/3.
  const double n_cusp = 13.0 / 3.0;
  // Gap edges: d1 = 4 at n = 3 − √3 (left), d2 = 4 at n = 7 + 2√3 (right).
  const double n_left = 3 - std::sqrt(3.0), n_right = 7 + 2 * std::sqrt(3.0);
  std::vector<StabilityLimit> start;
  for (double n : chatter::evenly_spaced_speeds(0.5, 12.0, 5)) start.push_back(env(n));
  chatter::EnvelopeRefinement o;
  o.cusp_rel_tol = 1e-9;
  const auto r = chatter::refine_envelope(env, start, o);
  ASSERT_TRUE(r.converged);
  int edges = 0;
  for (std::size_t i = 0; i + 1 < r.rows.size(); ++i) {
    const StabilityLimit &a = r.rows[i], &b = r.rows[i + 1];
    const double mid = 0.5 * (a.spindle_rpm + b.spindle_rpm);
    // Every switch is bracketed within cusp_rel_tol of the speed.
    constexpr double kBracketRelTol = 1e-9;
    if (a.bounded() != b.bounded()) {
      ++edges;
      const double expect = a.bounded() ? n_right : n_left;
      EXPECT_NEAR(mid, expect, kBracketRelTol * expect) << "gap edge";
    } else if (a.bounded() && a.lobe != b.lobe) {
      ++edges;
      EXPECT_NEAR(mid, n_cusp, kBracketRelTol * n_cusp) << "cusp";
      EXPECT_NEAR(std::max(a.depth_limit_m, b.depth_limit_m), 1 + (n_cusp - 3) * (n_cusp - 3), 1e-7) << "cusp depth";
    }
  }
  EXPECT_EQ(edges, 3);
  // Between rows the line is within the tolerance of the parabolas.
  for (std::size_t i = 0; i + 1 < r.rows.size(); ++i) {
    const StabilityLimit &a = r.rows[i], &b = r.rows[i + 1];
    if (!(a.bounded() && b.bounded())) continue;
    for (double t : {0.25, 0.5, 0.75}) {
      const double n = a.spindle_rpm + t * (b.spindle_rpm - a.spindle_rpm);
      const double exact = env(n).depth_limit_m;
      if (!std::isfinite(exact)) continue;
      const double line = a.depth_limit_m + t * (b.depth_limit_m - a.depth_limit_m);
      EXPECT_LE(std::abs(line - exact), o.depth_rel_tol * exact + o.depth_abs_tol_m)
          << "at " << n << ": line " << line << ", exact " << exact;
    }
  }
}

TEST(RefineEnvelope, BadOptionsAndStartThrow) {
  const auto f = [](double n) {
    StabilityLimit r;
    r.spindle_rpm = n;
    return r;
  };
  chatter::EnvelopeRefinement o;
  o.depth_rel_tol = 0;
  EXPECT_THROW(chatter::refine_envelope(f, {f(1), f(2)}, o), chatter::InputError);
  o = {};
  o.cusp_rel_tol = 0;
  EXPECT_THROW(chatter::refine_envelope(f, {f(1), f(2)}, o), chatter::InputError);
  EXPECT_THROW(chatter::refine_envelope(f, {}, {}), chatter::InputError);
  EXPECT_THROW(chatter::refine_envelope(f, {f(1), f(1)}, {}), chatter::InputError);
  EXPECT_THROW(chatter::adaptive_envelope(f, 100, 200, 1), chatter::InputError);
}

TEST(AdaptiveEnvelope, CaseAEveryMidpointIsWithinToleranceOfTheLine) {
  const chatter::AnalyticSolver solver = case_a_solver();
  chatter::EnvelopeRefinement o;
  o.depth_rel_tol = kRefineRelTol;
  o.cusp_rel_tol = 1e-5;
  const int budget = 8000;
  const auto r = chatter::adaptive_envelope([&](double n) { return solver.limit_at(chatter::SpindleSpeed(n)); }, 50, 2000, budget, o, 2);
  ASSERT_TRUE(r.converged) << "budget " << budget << " too small";
  ASSERT_LE(r.rows.size(), static_cast<std::size_t>(budget));
  EXPECT_EQ(r.rows.size(), r.solves);
  EXPECT_EQ(r.rows.front().spindle_rpm, 50.0);
  EXPECT_EQ(r.rows.back().spindle_rpm, 2000.0);
  std::size_t below_300 = 0;
  for (std::size_t i = 0; i + 1 < r.rows.size(); ++i) {
    const StabilityLimit &a = r.rows[i], &b = r.rows[i + 1];
    ASSERT_LT(a.spindle_rpm, b.spindle_rpm);
    if (a.spindle_rpm < 300) ++below_300;
    const double n = 0.5 * (a.spindle_rpm + b.spindle_rpm);
    const double exact = solver.limit_at(chatter::SpindleSpeed(n)).depth_limit_m;
    const double line = 0.5 * (a.depth_limit_m + b.depth_limit_m);
    EXPECT_LE(std::abs(line - exact), kRefineRelTol * exact + o.depth_abs_tol_m)
        << "midpoint " << n << " rev/min: exact " << exact << " m, line " << line << " m";
  }
  // The dense lobes get the rows: below 300 rev/min (lobes k >= 18, each
  // under 17 rev/min wide, against 60 to 400 rev/min above 600) at least 3x
  // as many rows per rev/min as above (an even table: the same density).
  const double density_low = static_cast<double>(below_300) / 250.0,
               density_high = static_cast<double>(r.rows.size() - below_300) / 1700.0;
  EXPECT_GT(density_low, 3 * density_high) << below_300 << " of " << r.rows.size() << " rows below 300 rev/min";
  std::cout << "adaptive case A: " << r.rows.size() << " rows, " << below_300 << " below 300 rev/min\n";
}
