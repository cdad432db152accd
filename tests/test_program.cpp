// `chatter program` end to end, through LinuxCNC's interpreter
// (docs/program.md): each number against an independent answer — the depth
// of cut (D₀ − D₁)/2 and the position along the bar, the slot's arc, every
// cutting block's limit equal to `chatter point` on the same cut (speed,
// engagement, position, searched depth), the cache on and off giving the
// same record, a fixed program checked again, LinuxCNC's own example
// programs, G41 with a G81 cycle and arcs, and every bad input named.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

namespace chatter::test {
namespace {

using json = nlohmann::json;

const std::string kSource = CHATTER_SOURCE_DIR;
const std::string kNcFiles = "/usr/share/linuxcnc/ncfiles";

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

class ProgramCli : public CliFixture {
 protected:
  void SetUp() override {
    CliFixture::SetUp();
    if (!fs::exists("/usr/bin/rs274")) GTEST_SKIP() << "LinuxCNC's rs274 is not installed (scripts/setup.sh installs it)";
  }
  fs::path dir() const { return dir_; }

  // A slender bar (cantilever workpiece) turned with the seed shaft's insert.
  void turning_job(double diameter_mm = 25.0, const std::string& extra = "") {
    write(dir() / "insert.toml", R"(name = "insert"
[process]
operation = "turning"
feed_force_coefficient_n_per_m2 = 954e6
[tool]
[[tool.modes]]
frequency_hz = 1200
damping_ratio = 0.03
stiffness_n_per_m = 5e7
direction = "x"
)");
    write(dir() / "job.toml", R"(
[stock]
shape = "bar"
diameter_mm = )" + std::to_string(diameter_mm) + R"(
length_mm = 80
face_z_mm = 0
resolution_mm = 0.5

[[tools]]
number = 1
config = "insert.toml"

[[workpiece.modes]]
damping_ratio = 0.04
direction = "x"
cantilever = { youngs_modulus_pa = 205e9, density_kg_per_m3 = 7870, length_m = 0.080, diameter_m = 0.025 }

[machine]
rpm_min = 200
rpm_max = 4000
)" + extra);
  }

  void milling_job(const std::string& machine = "") {
    write(dir() / "mill.toml", R"(name = "10 mm 3-flute"
[process]
operation = "milling"
teeth = 3
tangential_coefficient_n_per_m2 = 7e8
radial_coefficient_n_per_m2 = 2.1e8
radial_immersion = 1
tool_diameter_mm = 10
[[tool.modes]]
frequency_hz = 900
damping_ratio = 0.03
stiffness_n_per_m = 8e6
direction = "x"
[[tool.modes]]
frequency_hz = 950
damping_ratio = 0.03
stiffness_n_per_m = 9e6
direction = "y"
)");
    write(dir() / "job.toml", R"(
[stock]
shape = "box"
min_mm = [0, 0, -20]
max_mm = [60, 40, 0]
resolution_mm = 0.1

[[tools]]
number = 1
config = "mill.toml"

[machine]
rpm_min = 1000
rpm_max = 12000
)" + machine);
  }

  json run_json(const std::vector<std::string>& extra, int expect_exit) {
    std::vector<std::string> args = {"program", (dir() / "part.ngc").string(), "--config", (dir() / "job.toml").string(),
                                     "--json", "-", "--threads", "2"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, expect_exit) << r.err;
    if (r.exit_code != expect_exit || r.out.empty()) return json();
    return json::parse(r.out);
  }

  // `chatter point` on `config` with the row's speed and depth: its record.
  json point(const fs::path& config, const json& row, const std::vector<std::string>& extra) {
    std::vector<std::string> args = {"point", config.string(), "--rpm", row["spindle_rpm"].dump(), "--depth-mm",
                                     row["depth_mm"].dump()};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return r.exit_code == 0 ? json::parse(r.out) : json();
  }
};

// Two passes along a slender bar: depth (D₀ − D₁)/2, the position from the
// clamp, the limit equal to `point --position-mm` on the tool config with
// the job's workpiece, the removed volume π/4 (D₀² − D₁²) L.
TEST_F(ProgramCli, TurningPassesGiveDepthPositionAndPointsLimit) {
  turning_job();
  write(dir() / "part.ngc", "G18 G21 G7\nT1 M6\nG97 S1500 M3\nG95 F0.1\nG0 X26 Z2\nG1 X24\nG1 Z-70\nG0 X26\n"
                           "G0 Z2\nG1 X21\nG1 Z-70\nG0 X30\nM2\n");
  const json rec = run_json({}, 0);
  ASSERT_TRUE(rec.is_object());
  // The tool config with the job's workpiece: what `point` needs for the same cut.
  write(dir() / "tool_here.toml", slurp(dir() / "insert.toml") + R"(
[[workpiece.modes]]
damping_ratio = 0.04
direction = "x"
cantilever = { youngs_modulus_pa = 205e9, density_kg_per_m3 = 7870, length_m = 0.080, diameter_m = 0.025 }
)");
  const double depth_max = rec["tools"][0]["depth_max_mm"];
  int checked = 0;
  for (const json& row : rec["rows"]) {
    if (row["air"]) continue;
    const int line = row["line"];
    ASSERT_TRUE(line == 7 || line == 11) << row.dump();
    EXPECT_DOUBLE_EQ(row["depth_mm"].get<double>(), line == 7 ? 0.5 : 1.5);  // 25 -> 24, 24 -> 21
    EXPECT_DOUBLE_EQ(row["feed_per_rev_mm"].get<double>(), 0.1);
    EXPECT_DOUBLE_EQ(row["spindle_rpm"].get<double>(), 1500.0);
    // The worst sample is at the free end: the last cell (80 mm, cells of 0.5 mm).
    EXPECT_DOUBLE_EQ(row["position_mm"].get<double>(), 79.75);
    const json p = point(dir() / "tool_here.toml", row,
                         {"--position-mm", row["position_mm"].dump(), "--depth-max-mm", json(depth_max).dump()});
    EXPECT_EQ(p["depth_limit_mm"], row["depth_limit_mm"]) << line;
    EXPECT_EQ(p["stable"], row["stable"]) << line;
    EXPECT_EQ(p["chatter_frequency_hz"], row["chatter_frequency_hz"]) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 2);
  // The plot's margin along the bar (every sample): its smallest on each pass
  // is the row's margin at the row's position, and mid-bar it is `point`'s
  // limit at that position over the depth.
  const RunResult plotted = run({"program", (dir() / "part.ngc").string(), "--config", (dir() / "job.toml").string(),
                                 "--plot", (dir() / "along.png").string()});
  ASSERT_EQ(plotted.exit_code, 0) << plotted.err;
  std::istringstream dat(slurp(dir() / "along.dat"));
  std::string text;
  while (std::getline(dat, text) && text.rfind("# index 1", 0) != 0) {
  }
  std::map<int, std::vector<std::array<double, 3>>> along;  // line -> (position, margin, error)
  while (std::getline(dat, text)) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream in(text);
    double pos = 0, margin = 0;
    std::string err;
    int line = 0;
    in >> pos >> margin >> err >> line;
    along[line].push_back({pos, margin, err == "?" ? NAN : std::stod(err)});
  }
  ASSERT_EQ(along.size(), 2u);
  for (const json& row : rec["rows"]) {
    if (row["air"]) continue;
    const auto& pts = along.at(row["line"].get<int>());
    EXPECT_GT(pts.size(), 100u);  // the 70 mm pass at 0.5 mm cells
    const auto low = std::min_element(pts.begin(), pts.end(), [](auto& a, auto& b) { return a[1] < b[1]; });
    EXPECT_NEAR((*low)[1], row["margin"].get<double>(), 1e-6 * row["margin"].get<double>());
    EXPECT_DOUBLE_EQ((*low)[0], row["position_mm"].get<double>());
    EXPECT_NEAR((*low)[2], row["diametral_error_um"].get<double>(), 1e-6 * std::abs(row["diametral_error_um"].get<double>()));
    const auto mid = std::find_if(pts.begin(), pts.end(), [](auto& p) { return p[0] == 40.25; });
    ASSERT_NE(mid, pts.end());
    const json p = point(dir() / "tool_here.toml", row,
                         {"--position-mm", "40.25", "--depth-max-mm", json(depth_max).dump()});
    // (the plot shows margins above 4 at 4)
    EXPECT_NEAR((*mid)[1], std::min(4.0, p["depth_limit_mm"].get<double>() / row["depth_mm"].get<double>()),
                1e-6 * (*mid)[1]);
    if (row["line"] == 11) {
      EXPECT_LT((*mid)[1], 4.0);  // one pass checked below the clip
    }
  }
  // The bar is turned from its face (z = 0) to z = −70.
  const double exact = M_PI / 4 * (25.0 * 25.0 - 21.0 * 21.0) * 70.0;
  EXPECT_NEAR(rec["summary"]["removed_volume_mm3"].get<double>(), exact, 1e-9 * exact);
  EXPECT_EQ(rec["summary"]["cutting_blocks"], 2);
}

// A straight slot across the box: arc [0, 180], a_e = D, a_p as programmed,
// the limit equal to `point` on the tool with engaged_arc_deg = [0, 180],
// D a_p L removed; the cache on and off give the same rows.
TEST_F(ProgramCli, SlotIsHalfACircleAndEqualsPoint) {
  milling_job();
  write(dir() / "part.ngc", "G17 G21 G90 G94\nT1 M6\nS6000 M3\nG0 X-8 Y20 Z5\nG1 Z-1 F300\nG1 X68 F600\nG0 Z5\nM2\n");
  const json rec = run_json({}, 0);
  ASSERT_TRUE(rec.is_object());
  const json* slot = nullptr;
  for (const json& row : rec["rows"])
    if (row["line"] == 6) slot = &row;
  ASSERT_NE(slot, nullptr);
  EXPECT_EQ((*slot)["entry_angle_deg"], 0.0);
  EXPECT_EQ((*slot)["exit_angle_deg"], 180.0);
  EXPECT_NEAR((*slot)["radial_depth_mm"].get<double>(), 10.0, 1e-12);
  EXPECT_NEAR((*slot)["axial_depth_mm"].get<double>(), 1.0, 1e-5);
  EXPECT_NEAR((*slot)["feed_per_tooth_mm"].get<double>(), 600.0 / (6000.0 * 3), 1e-15);
  write(dir() / "slot.toml", [&] {
    std::string t = slurp(dir() / "mill.toml");
    const auto at = t.find("radial_immersion = 1");
    return t.replace(at, std::string("radial_immersion = 1").size(), "engaged_arc_deg = [0, 180]");
  }());
  const json p = point(dir() / "slot.toml", *slot, {"--depth-max-mm", rec["tools"][0]["depth_max_mm"].dump()});
  EXPECT_EQ(p["depth_limit_mm"], (*slot)["depth_limit_mm"]);
  EXPECT_EQ(p["chatter_frequency_hz"], (*slot)["chatter_frequency_hz"]);
  // D a_p L across the 60 mm box, to a cell on each wall (0.1 mm).
  EXPECT_NEAR(rec["summary"]["removed_volume_mm3"].get<double>(), 10.0 * 1.0 * 60.0, 2 * 0.1 * 1.0 * 60.0 + 10.0 * 0.1 * 1.0);
  const json off = run_json({"--no-cache"}, 0);
  ASSERT_TRUE(off.is_object());
  EXPECT_EQ(off["rows"], rec["rows"]);
  EXPECT_GT(off["summary"]["solves"].get<int>(), rec["summary"]["solves"].get<int>());
}

// A 16 mm cutter down the middle of the 10 mm slot it widens: two arcs
// (the material on both sides of the slot), each given to the solver as an
// arc of the cut; the row's limit is `point`'s on the tool config with
// engaged_arc_deg = the row's arcs, and the arcs are the rim's construction
// [0, acos(5/8)], [180° − acos(5/8), 180°] on the 0.5° grid, widened outward.
TEST_F(ProgramCli, WideningASlotSolvesBothArcsAsPointDoes) {
  milling_job();
  write(dir() / "mill16.toml", [&] {
    std::string t = slurp(dir() / "mill.toml");
    return t.replace(t.find("tool_diameter_mm = 10"), std::string("tool_diameter_mm = 10").size(), "tool_diameter_mm = 16");
  }());
  write(dir() / "job.toml", slurp(dir() / "job.toml") + "\n[[tools]]\nnumber = 2\nconfig = \"mill16.toml\"\n");
  write(dir() / "part.ngc", "G17 G21 G90 G94\nT1 M6\nS6000 M3\nG0 X-10 Y20 Z5\nG1 Z-0.5 F300\nG1 X70 F600\nG0 Z5\n"
                            "T2 M6\nS6000 M3\nG0 X-10 Y20\nG1 Z-0.5 F300\nG1 X70 F600\nG0 Z5\nM2\n");
  const json rec = run_json({}, 0);
  ASSERT_TRUE(rec.is_object());
  const json* wide = nullptr;
  for (const json& row : rec["rows"])
    if (row["line"] == 12) wide = &row;
  ASSERT_NE(wide, nullptr);
  const json& arcs = (*wide)["engaged_arcs_deg"];
  ASSERT_EQ(arcs.size(), 2u) << wide->dump();
  const double inner = std::acos(5.0 / 8.0) * 180.0 / M_PI;  // 51.3°
  EXPECT_EQ(arcs[0][0].get<double>(), 0.0);
  EXPECT_NEAR(arcs[0][1].get<double>(), inner, 1.5);
  EXPECT_NEAR(arcs[1][0].get<double>(), 180.0 - inner, 1.5);
  EXPECT_EQ(arcs[1][1].get<double>(), 180.0);
  EXPECT_EQ((*wide)["entry_angle_deg"], arcs[0][0]);
  EXPECT_EQ((*wide)["exit_angle_deg"], arcs[1][1]);
  EXPECT_NEAR((*wide)["radial_depth_mm"].get<double>(), 6.0, 0.25);  // 3 mm each side, to the grid
  EXPECT_TRUE((*wide)["diametral_error_um"].is_null() || !wide->contains("diametral_error_um"));
  write(dir() / "two_arcs.toml", [&] {
    std::string t = slurp(dir() / "mill16.toml");
    return t.replace(t.find("radial_immersion = 1"), std::string("radial_immersion = 1").size(),
                     "engaged_arc_deg = " + arcs.dump());
  }());
  const json p = point(dir() / "two_arcs.toml", *wide, {"--depth-max-mm", rec["tools"][1]["depth_max_mm"].dump()});
  EXPECT_EQ(p["depth_limit_mm"], (*wide)["depth_limit_mm"]);
  EXPECT_EQ(p["chatter_frequency_hz"], (*wide)["chatter_frequency_hz"]);
}

// An unstable turning block fixed by --fix-speed: the fixed program checked
// again exits 0.
TEST_F(ProgramCli, FixedSpeedProgramChecksClean) {
  milling_job();
  write(dir() / "part.ngc", "G17 G21 G90 G94\nT1 M6\nS6000 M3\nG0 X-8 Y20 Z5\nG1 Z-2 F300\nG1 X68 F600\nG0 Z5\nM2\n");
  const json rec = run_json({}, 3);
  ASSERT_TRUE(rec.is_object());
  EXPECT_GT(rec["summary"]["unstable_blocks"].get<int>(), 0);
  const RunResult fix = run({"program", (dir() / "part.ngc").string(), "--config", (dir() / "job.toml").string(),
                             "--out", (dir() / "fixed.ngc").string(), "--fix-speed"});
  EXPECT_EQ(fix.exit_code, 3) << fix.err;
  const std::string fixed = slurp(dir() / "fixed.ngc");
  EXPECT_TRUE(contains(fixed, "(chatter: unstable")) << fixed;
  const RunResult again = run({"program", (dir() / "fixed.ngc").string(), "--config", (dir() / "job.toml").string()});
  EXPECT_EQ(again.exit_code, 0) << again.out << again.err << fixed;
}

// The docs' pocket (examples/program): its corners overload the 1 kW
// spindle on lines that run ten times in a loop and carry their own F word.
// --fix-feed replaces that word (two F words on a line is an interpreter
// error) with the smallest feed any run needs, and the fixed program checks
// clean. The scale is the power's: P ∝ F at a fixed engagement, so the new
// F over the old is at most max_power / the line's worst power.
TEST_F(ProgramCli, FixedFeedInALoopReplacesTheLinesFWordAndChecksClean) {
  const std::string ex = kSource + "/examples/program/";
  const RunResult first = run({"program", ex + "pocket.ngc", "--config", ex + "pocket_job.toml", "--json",
                               (dir() / "first.json").string(), "--out", (dir() / "fixed.ngc").string(), "--fix-feed"});
  ASSERT_EQ(first.exit_code, 3) << first.err;
  const json rec = json::parse(slurp(dir() / "first.json"));
  EXPECT_EQ(rec["summary"]["unstable_blocks"].get<int>(), 0);
  EXPECT_GT(rec["summary"]["overloaded_blocks"].get<int>(), 10);
  double worst_kw_line20 = 0.0;
  for (const json& r : rec["rows"])
    if (r["line"].get<int>() == 20) worst_kw_line20 = std::max(worst_kw_line20, r["power_kw"].get<double>());
  ASSERT_GT(worst_kw_line20, 1.0);
  std::istringstream lines(slurp(dir() / "fixed.ngc"));
  std::string line;
  for (int n = 1; n <= 20 && std::getline(lines, line); ++n) {
  }
  // Line 20 kept its place: one F word, and the comment.
  const auto f = line.find(" F");
  ASSERT_NE(f, std::string::npos) << line;
  EXPECT_EQ(line.find(" F", f + 1), line.find(" F4", f + 1)) << line;  // only the comment's "feed set to F…" after it
  const double feed = std::stod(line.substr(f + 2));
  EXPECT_LE(feed, 5200.0 * 1.0 / worst_kw_line20 * (1.0 + 1e-6)) << line;
  EXPECT_GT(feed, 5200.0 * 0.9 / worst_kw_line20) << line;
  EXPECT_TRUE(contains(line, "in 10 of the line's 10 runs")) << line;
  const RunResult again = run({"program", (dir() / "fixed.ngc").string(), "--config", ex + "pocket_job.toml"});
  EXPECT_EQ(again.exit_code, 0) << again.out << again.err;
}

TEST_F(ProgramCli, LinuxCncExamplesRunEndToEnd) {
  if (!fs::exists(kNcFiles + "/lathe_pawn.ngc")) GTEST_SKIP() << "LinuxCNC's example programs are not installed";
  turning_job(28.0);
  // The pawn selects no tool (the job's only one is used) and starts its spindle;
  // the G70/G71 demo changes to tools 2 and 10 and gives no S word.
  const std::string stock = "[stock]\nshape = \"bar\"\ndiameter_mm = 28\nlength_mm = 60\nface_z_mm = 1\n";
  write(dir() / "lathe_pawn.toml", stock + "[[tools]]\nnumber = 1\nconfig = \"insert.toml\"\n");
  write(dir() / "lathe_g70_71_demo.toml", stock + "[[tools]]\nnumber = 2\nconfig = \"insert.toml\"\n[[tools]]\nnumber = 10\n"
                                                  "config = \"insert.toml\"\n[program]\ndefault_spindle_rpm = 1000\n");
  for (const char* name : {"lathe_pawn.ngc", "lathe_g70_71_demo.ngc"}) {
    const std::string job = (dir() / (fs::path(name).stem().string() + ".toml")).string();
    const RunResult r = run({"program", kNcFiles + "/" + name, "--config", job, "--json",
                             (dir() / "out.json").string()});
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 3) << name << ": " << r.err;
    const json rec = json::parse(slurp(dir() / "out.json"));
    EXPECT_GT(rec["summary"]["cutting_blocks"].get<int>(), 5) << name;
    EXPECT_GT(rec["summary"]["removed_volume_mm3"].get<double>(), 0.0) << name;
  }
}

TEST_F(ProgramCli, CompensationCycleAndArcsRun) {
  milling_job();
  write(dir() / "part.ngc", R"(G17 G21 G90 G94
T1 M6
S6000 M3
G0 X-10 Y-10 Z5
G1 Z-1 F300
G41 G1 X5 Y5 F600
G1 X40
G3 X50 Y15 I0 J10
G1 Y30
G3 X30 Y30 I-10 J0
G40 G1 X-10 Y45
G0 Z5
G81 X20 Y20 Z-4 R2 F100
X30
G80
M2
)");
  const RunResult r = run({"program", (dir() / "part.ngc").string(), "--config", (dir() / "job.toml").string(),
                           "--json", (dir() / "out.json").string()});
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 3) << r.err;
  const json rec = json::parse(slurp(dir() / "out.json"));
  // Every feed move keeps its source line: the compensated entry (6), the
  // arcs (8, 10) and the drilling cycle's feeds (13, 14).
  std::set<int> lines;
  for (const json& row : rec["rows"]) lines.insert(row["line"].get<int>());
  for (const int l : {8, 10, 13, 14}) EXPECT_TRUE(lines.count(l)) << l;
}

TEST_F(ProgramCli, BadInputsNameTheLineOrKey) {
  milling_job();
  const std::string job = (dir() / "job.toml").string();
  // A T word with no tool in the job: the interpreter's message and the line.
  write(dir() / "part.ngc", "G21\nT7 M6\nM2\n");
  RunResult r = run({"program", (dir() / "part.ngc").string(), "--config", job});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "part.ngc:2:")) << r.err;
  // A program that never cuts the stock.
  write(dir() / "part.ngc", "G21\nT1 M6\nS5000 M3\nG0 X0 Y0 Z50\nG1 X10 F100\nM2\n");
  r = run({"program", (dir() / "part.ngc").string(), "--config", job});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "never cuts the stock")) << r.err;
  // No [stock].
  write(dir() / "nostock.toml", "[[tools]]\nnumber = 1\nconfig = \"mill.toml\"\n");
  r = run({"program", (dir() / "part.ngc").string(), "--config", (dir() / "nostock.toml").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "stock")) << r.err;
  // A cut with no spindle speed names its line.
  write(dir() / "part.ngc", "G21\nT1 M6\nG0 X-8 Y20 Z5\nG1 Z-1 F100\nG1 X20\nM2\n");
  r = run({"program", (dir() / "part.ngc").string(), "--config", job});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.err, "part.ngc:5:")) << r.err;
}

}  // namespace
}  // namespace chatter::test
