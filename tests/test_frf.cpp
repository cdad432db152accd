// FRF readers and writers: an FRF built from known modes goes through every
// format and comes back to the precision the format holds; unit conversions
// agree; every malformed file in tests/corpus/frf/ is refused with a message
// that names the file, the record and the line.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/frf.hpp"
#include "chatter/structural_model.hpp"

namespace chatter {
namespace {

namespace fs = std::filesystem;
constexpr double kPi = std::numbers::pi;

// Precision each format holds, relative to |G| at each line:
constexpr double kExact = 0.0;           // CSV / tab (17 digits), 58b double
constexpr double kE13_5 = 5e-6;          // 6 significant digits: half a unit in the 6th digit
constexpr double kE20_12 = 5e-13;        // 13 significant digits
constexpr double kFloat = 0x1p-24;       // IEEE single, round to nearest
constexpr double kConversion = 1e-15;    // one multiply and one divide in double

/// The synthetic structure of the tests (tool, along X).
Body two_modes() {
  Body b;
  b.modes.push_back(Mode::from_stiffness(650.0, 0.03, 2e7, {1.0, 0.0}));
  b.modes.push_back(Mode::from_stiffness(1100.0, 0.02, 5e7, {1.0, 0.0}));
  return b;
}

FrfTable synthesize(const std::vector<double>& f_hz) {
  const Body b = two_modes();
  FrfTable t;
  t.source = "synthetic";
  for (const double f : f_hz) {
    t.frequency_hz.push_back(f);
    t.value.push_back(b.receptance(2 * kPi * f)(0, 0));
  }
  return t;
}

/// 0 to 2000 Hz every 2.5 Hz (801 lines): exact in E13.5 (min 0, increment 2.5).
std::vector<double> even_grid() {
  std::vector<double> f;
  for (int i = 0; i <= 800; ++i) f.push_back(2.5 * i);
  return f;
}

/// 600 uneven lines from 5 to 2000 Hz rounded to 0.01 Hz: 6 significant
/// digits, so E13.5 holds them exactly.
std::vector<double> uneven_grid() {
  std::vector<double> f;
  for (int i = 0; i < 600; ++i) f.push_back(std::round(100.0 * (5.0 + 1995.0 * std::pow(i / 599.0, 1.3))) / 100.0);
  return f;
}

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("chatter_test_frf_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(std::random_device{}()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void spit(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

/// Every line equal within `tol_value` (relative to |G|) and `tol_f`
/// (relative to f); the first failure prints both numbers.
void expect_same(const FrfTable& expected, const FrfTable& got, double tol_value, double tol_f, bool real_only = false) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Complex want = real_only ? Complex(expected.value[i].real(), 0.0) : expected.value[i];
    const double scale = real_only ? std::abs(want.real()) : std::abs(want);
    ASSERT_LE(std::abs(got.frequency_hz[i] - expected.frequency_hz[i]), tol_f * expected.frequency_hz[i])
        << "line " << i << ": f written " << expected.frequency_hz[i] << ", read " << got.frequency_hz[i];
    ASSERT_LE(std::abs(got.value[i] - want), tol_value * scale)
        << "line " << i << " (" << expected.frequency_hz[i] << " Hz): written " << want << ", read " << got.value[i]
        << ", relative error " << std::abs(got.value[i] - want) / scale;
  }
}

// ------------------------------------------------------------- round trips

TEST(FrfRoundTrip, CsvIsBitExact) {
  TempDir dir;
  const FrfTable t = synthesize(even_grid());
  write_frf_csv(dir / "g.csv", t);
  expect_same(t, read_frf_csv(dir / "g.csv"), kExact, kExact);
  write_frf_csv(dir / "g_noheader.csv", t, false);
  expect_same(t, read_frf_csv(dir / "g_noheader.csv"), kExact, kExact);
  EXPECT_EQ(read_frf_csv(dir / "g.csv").source, (dir / "g.csv").string());
}

TEST(FrfRoundTrip, TabIsBitExact) {
  TempDir dir;
  const FrfTable t = synthesize(uneven_grid());
  write_frf_tab(dir / "g.frf", t);
  expect_same(t, read_frf_tab(dir / "g.frf"), kExact, kExact);
}

struct UffCase {
  bool binary, double_precision, even, complex_data;
};

std::string name_of(const UffCase& c) {
  return std::string(c.binary ? "58b" : "58") + (c.double_precision ? "_double" : "_single") +
         (c.even ? "_even" : "_uneven") + (c.complex_data ? "_complex" : "_real");
}

class UffRoundTrip : public ::testing::TestWithParam<UffCase> {};

TEST_P(UffRoundTrip, ValuesComeBackToTheWrittenPrecision) {
  const UffCase c = GetParam();
  TempDir dir;
  const FrfTable t = synthesize(c.even ? even_grid() : uneven_grid());
  UffWriteOptions o;
  o.binary = c.binary;
  o.double_precision = c.double_precision;
  o.even_abscissa = c.even;
  o.complex_data = c.complex_data;
  o.response_node = 101;
  o.response_direction = 2;
  o.reference_node = 7;
  o.reference_direction = -1;
  const fs::path file = dir / (name_of(c) + ".uff");
  write_uff58(file, {t, t}, o);

  const auto records = read_uff58_records(file);
  ASSERT_EQ(records.size(), 2u);
  // ASCII: E13.5 single, E20.12 double; uneven abscissa E13.5 (exact for
  // this grid). Binary: float or double, abscissa in the same type.
  const double tol = c.binary ? (c.double_precision ? kExact : kFloat) : (c.double_precision ? kE20_12 : kE13_5);
  const double tol_f = c.even ? kExact : (c.binary && !c.double_precision ? kFloat : kExact);
  for (int r = 0; r < 2; ++r) {
    SCOPED_TRACE("record " + std::to_string(r + 1));
    expect_same(t, records[r].table, tol, tol_f, !c.complex_data);
    EXPECT_EQ(records[r].record, r + 1);
    EXPECT_EQ(records[r].binary, c.binary);
    EXPECT_EQ(records[r].even_abscissa, c.even);
    EXPECT_EQ(records[r].ordinate_data_type, c.complex_data ? (c.double_precision ? 6 : 5) : (c.double_precision ? 4 : 2));
    EXPECT_EQ(records[r].response_node, 101);
    EXPECT_EQ(records[r].response_direction, 2);
    EXPECT_EQ(records[r].reference_node, 7);
    EXPECT_EQ(records[r].reference_direction, -1);
    EXPECT_EQ(records[r].table.source, file.string() + " (record " + std::to_string(r + 1) + ")");
  }
}

INSTANTIATE_TEST_SUITE_P(AllLayouts, UffRoundTrip,
                         ::testing::Values(UffCase{false, false, true, true}, UffCase{false, false, false, true},
                                           UffCase{false, true, true, true}, UffCase{false, true, false, true},
                                           UffCase{true, false, true, true}, UffCase{true, false, false, true},
                                           UffCase{true, true, true, true}, UffCase{true, true, false, true},
                                           UffCase{false, false, true, false}, UffCase{false, false, false, false},
                                           UffCase{false, true, true, false}, UffCase{false, true, false, false},
                                           UffCase{true, false, true, false}, UffCase{true, false, false, false},
                                           UffCase{true, true, true, false}, UffCase{true, true, false, false}),
                         [](const auto& p) { return name_of(p.param); });

TEST(FrfRoundTrip, UffWriterRefusesAnUnevenTableAsEven) {
  TempDir dir;
  EXPECT_THROW(write_uff58(dir / "x.uff", {synthesize(uneven_grid())}), std::invalid_argument);
  FrfTable bad = synthesize({10.0, 5.0});
  EXPECT_THROW(write_frf_csv(dir / "x.csv", bad), std::invalid_argument);
}

// -------------------------------------------------------- unit conversion

TEST(FrfUnits, MobilityAndAccelerance) {
  TempDir dir;
  std::vector<double> f = even_grid();
  f.erase(f.begin());  // no 0 Hz line: it has no receptance from mobility or accelerance
  const FrfTable g = synthesize(f);
  FrfTable mob = g, acc = g;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double w = 2 * kPi * g.frequency_hz[i];
    mob.value[i] = Complex(0.0, w) * g.value[i];
    acc.value[i] = -w * w * g.value[i];
  }
  write_frf_csv(dir / "mob.csv", mob);
  write_frf_tab(dir / "acc.frf", acc);
  expect_same(g, read_frf_csv(dir / "mob.csv", FrfQuantity::kMobility), kConversion, kExact);
  expect_same(g, read_frf_tab(dir / "acc.frf", FrfQuantity::kAccelerance), kConversion, kExact);

  // UFF: the record says what it holds (record 9: 11 velocity, 12 acceleration).
  UffWriteOptions o;
  o.quantity = FrfQuantity::kAccelerance;
  write_uff58(dir / "acc.uff", {acc}, o);
  const auto recs = read_uff58_records(dir / "acc.uff");
  EXPECT_EQ(recs[0].quantity, FrfQuantity::kAccelerance);
  expect_same(g, recs[0].table, kE20_12 + kConversion, kExact);
  o.quantity = FrfQuantity::kMobility;
  write_uff58(dir / "mob.uff", {mob}, o);
  expect_same(g, read_uff58(dir / "mob.uff")[0], kE20_12 + kConversion, kExact);
  // An explicit quantity overrides the record.
  FrfReadOptions as_receptance;
  as_receptance.quantity = FrfQuantity::kReceptance;
  expect_same(mob, read_uff58(dir / "mob.uff", as_receptance)[0], kE20_12, kExact);

  // µm/N with scale 1e-6.
  FrfTable um = g;
  for (Complex& v : um.value) v *= 1e6;
  write_frf_csv(dir / "um.csv", um);
  expect_same(g, read_frf_csv(dir / "um.csv", FrfQuantity::kReceptance, 1e-6), 1e-15, kExact);
}

TEST(FrfUnits, ZeroHzLineOfMobilityIsRefusedOrDropped) {
  TempDir dir;
  const FrfTable g = synthesize(even_grid());  // starts at 0 Hz
  write_frf_csv(dir / "acc.csv", g);
  try {
    read_frf_csv(dir / "acc.csv", FrfQuantity::kAccelerance);
    FAIL() << "0 Hz accelerance line accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0 Hz"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("acc.csv"), std::string::npos) << e.what();
  }
  FrfReadOptions o;
  o.quantity = FrfQuantity::kAccelerance;
  o.drop_zero_hz = true;
  const FrfTable t = read_frf_csv(dir / "acc.csv", o);
  EXPECT_EQ(t.size(), g.size() - 1);
  EXPECT_EQ(t.frequency_hz.front(), 2.5);
}

TEST(FrfUnits, UnitsDataset164ScalesToSi) {
  // Values in mm/N with a dataset 164 saying mm (length factor 1000: SI =
  // file / 1000) and N: read back in m/N.
  TempDir dir;
  const FrfTable g = synthesize(even_grid());
  FrfTable mm = g;
  for (Complex& v : mm.value) v *= 1e3;
  write_uff58(dir / "mm_data.uff", {mm});
  const std::string units =
      "    -1\n   164\n         5mm (milli-metre)            2\n"
      "  1.00000000000000000D+03  1.00000000000000000D+00  1.00000000000000000D+00\n"
      "  2.73150000000000000D+02\n    -1\n";
  spit(dir / "mm.uff", units + slurp(dir / "mm_data.uff"));
  const auto recs = read_uff58_records(dir / "mm.uff");
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].record, 2);
  expect_same(g, recs[0].table, kE20_12 + 1e-15, kExact);
}

TEST(FrfUnits, QuantityNames) {
  EXPECT_EQ(parse_frf_quantity("Accelerance"), FrfQuantity::kAccelerance);
  EXPECT_EQ(parse_frf_quantity("inertance"), FrfQuantity::kAccelerance);
  EXPECT_EQ(parse_frf_quantity("mobility"), FrfQuantity::kMobility);
  EXPECT_EQ(parse_frf_quantity("compliance"), FrfQuantity::kReceptance);
  EXPECT_FALSE(parse_frf_quantity("dynamic stiffness"));
  EXPECT_STREQ(to_string(FrfQuantity::kMobility), "mobility");
}

// ------------------------------------------------------------------ corpus

fs::path corpus_dir() { return fs::path(CHATTER_SOURCE_DIR) / "tests" / "corpus" / "frf"; }

/// Reads a corpus file with the reader its extension names.
std::vector<FrfTable> read_any(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".csv") return {read_frf_csv(p)};
  if (ext == ".frf") return {read_frf_tab(p)};
  if (ext == ".uff" || ext == ".unv") return read_uff58(p);
  ADD_FAILURE() << "corpus file with unknown extension: " << p;
  return {};
}

TEST(FrfCorpus, GoodFilesReadBadFilesThrowInputError) {
  int good = 0, bad = 0;
  for (const auto& entry : fs::directory_iterator(corpus_dir())) {
    const fs::path p = entry.path();
    const std::string name = p.filename().string();
    if (name.starts_with("good_")) {
      ++good;
      std::vector<FrfTable> tables;
      EXPECT_NO_THROW(tables = read_any(p)) << name;
      for (const FrfTable& t : tables) EXPECT_NO_THROW(validate(t)) << name;
      EXPECT_FALSE(tables.empty()) << name;
    } else if (name.starts_with("bad_")) {
      ++bad;
      try {
        read_any(p);
        ADD_FAILURE() << name << ": read without error";
      } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(name), std::string::npos) << name << ": message does not name the file: " << what;
      } catch (const std::exception& e) {
        ADD_FAILURE() << name << ": " << typeid(e).name() << " instead of InputError: " << e.what();
      }
    }
  }
  EXPECT_GE(good, 10);
  EXPECT_GE(bad, 20);
}

TEST(FrfCorpus, GoodFilesHoldTheSyntheticFrf) {
  // Every good corpus file holds the two-mode FRF on its own lines, to the
  // precision of its format (6 significant digits at worst; the
  // semicolon/comment files were written with 10).
  for (const auto& entry : fs::directory_iterator(corpus_dir())) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("good_")) continue;
    SCOPED_TRACE(name);
    const bool real_only = name.find("_real_") != std::string::npos;
    for (const FrfTable& t : read_any(entry.path())) expect_same(synthesize(t.frequency_hz), t, 5e-6, kExact, real_only);
  }
}

TEST(FrfCorpus, QuirkyUffRecordsAreAllRead) {
  const auto recs = read_uff58_records(corpus_dir() / "good_uff58_quirks_runtogether_crlf.uff");
  ASSERT_EQ(recs.size(), 2u);
  EXPECT_EQ(recs[0].table.size(), 16u);
  EXPECT_EQ(recs[1].table.size(), 16u);
  const auto mixed = read_uff58_records(corpus_dir() / "good_uff_mixed_datasets.uff");
  ASSERT_EQ(mixed.size(), 1u);
  EXPECT_EQ(mixed[0].record, 4) << "151, 164 and a time response come first";
}

struct BadCase {
  const char* file;
  std::vector<const char*> says;  // substrings the message must contain
};

TEST(FrfCorpus, MessagesNameRecordLineAndRule) {
  const std::vector<BadCase> cases = {
      {"bad_empty.csv", {"empty file"}},
      {"bad_two_columns.csv", {"line 2", "expected 3 columns", "got 2"}},
      {"bad_non_numeric.csv", {"line 9", "non-numeric field 'abc'", "column 3"}},
      {"bad_decreasing_frequency.csv", {"line 10", "decreasing frequency 690 Hz after 700 Hz"}},
      {"bad_repeated_frequency.frf", {"line 6", "repeated frequency 575 Hz"}},
      {"bad_single_line.csv", {"1 frequency line(s)", "at least 2"}},
      {"bad_nan_value.csv", {"line 4", "not finite"}},
      {"bad_negative_frequency.frf", {"line 1", "negative frequency"}},
      {"bad_second_header.csv", {"line 2", "non-numeric field 'Hz'", "column 1"}},
      {"bad_uff_empty.uff", {"empty file"}},
      {"bad_uff58_truncated_data.uff", {"record 1", "line 16", "truncated: expected 32 values (16 points), got 12 before the end of the file"}},
      {"bad_uff58_truncated_data_closed.uff", {"record 1", "line 17", "truncated: expected 32 values (16 points), got 12"}},
      {"bad_uff58_truncated_header.uff", {"record 1", "truncated header", "got 5"}},
      {"bad_uff_dataset55_only.uff", {"no FRF record", "record 1: dataset 55 is not an FRF"}},
      {"bad_uff58_time_response_only.uff", {"record 1: dataset 58 function type 1 (time response) is not an FRF"}},
      {"bad_uff58_non_numeric.uff", {"record 1", "line 15", "non-numeric field 'abc'", "column 2"}},
      {"bad_uff58_decreasing_frequency.uff", {"record 1", "line 17", "point 7", "decreasing frequency 640 Hz after 648.25 Hz"}},
      {"bad_uff58b_wrong_byte_count.uff", {"record 1", "line 2", "binary record holds 240 bytes", "needs 256"}},
      {"bad_uff58b_truncated_binary.uff", {"record 1", "truncated: expected 256 bytes"}},
      {"bad_uff58_ordinate_type3.uff", {"record 1", "line 9", "ordinate data type 3"}},
      {"bad_uff58_zero_increment.uff", {"record 1", "line 9", "increment 0 Hz must be > 0"}},
      {"bad_uff58_extra_data.uff", {"record 1", "line 22", "extra data"}},
      {"bad_uff_not_a_universal_file.uff", {"line 1", "expected '-1'"}},
      {"bad_uff58_one_point.uff", {"record 1", "at least 2"}},
      {"bad_uff58_ordinate_stress.uff", {"record 1", "line 11", "stress"}},
      {"bad_uff58_mobility_at_zero_hz.uff", {"record 1", "0 Hz", "mobility"}},
      {"bad_uff58_missing_dataset_number.uff", {"line 1", "not followed by a dataset number"}},
  };
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.file);
    try {
      read_any(corpus_dir() / c.file);
      ADD_FAILURE() << "read without error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find((corpus_dir() / c.file).string()), std::string::npos) << what;
      for (const char* s : c.says) EXPECT_NE(what.find(s), std::string::npos) << "missing '" << s << "' in: " << what;
    }
  }
}

TEST(FrfReaders, NumberForms) {
  TempDir dir;
  // Fortran D exponent, exponent without letter, leading '+', overflow.
  spit(dir / "forms.csv", "1,1.5D-07,+2.0E-07\n2,1.5-107,-2.5d-7\n");
  const FrfTable t = read_frf_csv(dir / "forms.csv");
  EXPECT_EQ(t.value[0], Complex(1.5e-7, 2.0e-7));
  EXPECT_EQ(t.value[1], Complex(1.5e-107, -2.5e-7));
  spit(dir / "overflow.csv", "1,1e-7,0\n2,1e400,0\n");
  try {
    read_frf_csv(dir / "overflow.csv");
    FAIL() << "1e400 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not finite"), std::string::npos) << e.what();
  }
}

TEST(FrfReaders, FromMemory) {
  const FrfTable t = parse_frf_csv("f,re,im\n100,1e-7,-2e-8\n200,2e-7,-3e-8\n", "memory.csv");
  EXPECT_EQ(t.source, "memory.csv");
  EXPECT_EQ(t.value[1], Complex(2e-7, -3e-8));
  EXPECT_EQ(parse_frf_tab("header\n1\t2\t3\n2\t3\t4\n", "m.frf").size(), 2u);
  const std::string uff = slurp(corpus_dir() / "good_uff58b_double_even_le.uff");
  const auto recs = parse_uff58_records(uff, "memory.uff");
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].table.source, "memory.uff (record 1)");
  EXPECT_THROW(parse_uff58_records("", "empty.uff"), InputError);
}

TEST(FrfReaders, MissingFileAndDirectory) {
  EXPECT_THROW(read_frf_csv("/nonexistent/chatter/x.csv"), InputError);
  EXPECT_THROW(read_uff58(corpus_dir()), InputError);
}

TEST(FrfReaders, RandomDamageNeverCrashes) {
  // Cheap stand-in for the fuzzer: flip, cut and splice bytes of every
  // corpus file; each result must read or throw InputError, nothing else.
  std::mt19937 rng(12345);
  int runs = 0;
  for (const auto& entry : fs::directory_iterator(corpus_dir())) {
    const std::string original = slurp(entry.path());
    if (original.empty()) continue;
    for (int k = 0; k < 40; ++k) {
      std::string s = original;
      std::uniform_int_distribution<std::size_t> pos(0, s.size() - 1);
      switch (k % 4) {
        case 0: s[pos(rng)] = static_cast<char>(rng() & 0xff); break;
        case 1: s.resize(pos(rng)); break;
        case 2: s.insert(pos(rng), std::string(1 + rng() % 8, static_cast<char>("-1 \n\r.E9b"[rng() % 9]))); break;
        case 3: s.erase(pos(rng), 1 + rng() % 20); break;
      }
      const std::string ext = entry.path().extension().string();
      try {
        if (ext == ".csv")
          parse_frf_csv(s, "damaged.csv");
        else if (ext == ".frf")
          parse_frf_tab(s, "damaged.frf");
        else
          parse_uff58_records(s, "damaged.uff");
      } catch (const InputError&) {
      }
      ++runs;
    }
  }
  EXPECT_GT(runs, 0);
}

}  // namespace
}  // namespace chatter
