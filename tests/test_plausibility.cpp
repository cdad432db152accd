// The units rule of docs/results.md, as a property: every number a shipped
// config or example gives, taken 1000 times too large and 1000 times too
// small (a unit slipped: m for mm, N/mm^2 for N/m^2, ...), is refused or
// named in a warning; the config is never read silently. Keys with no unit to
// slip (counts, money in any currency, indices) are listed below with why.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "chatter/error.hpp"
#include "chatter/io/config.hpp"
#include "chatter/io/grinding_config.hpp"
#include "chatter/usual_bands.hpp"

namespace {

namespace fs = std::filesystem;

// Keys that carry no length, speed or coefficient, so no band can tell a
// slipped unit from a real value. Each with the reason it is not walked.
const std::map<std::string, std::string>& Exempt() {
  static const std::map<std::string, std::string> exempt = {
      {"teeth", "a count: 1000 teeth is refused by its own rule, a fraction too"},
      {"tool_uses", "a count of parts per tool"},
      {"seed", "a random seed, any integer"},
      {"samples", "a Monte Carlo sample count: its own upper bound"},
      {"machine_rate_per_h", "money per hour, in any currency"},
      {"tool_cost", "money, in any currency"},
      {"max_cost", "money, in any currency"},
      {"operation_cost", "money, in any currency"},
      {"part_value", "money, in any currency"},
      {"previous_operations_cost", "money, in any currency"},
      {"index", "an index into a list"},
      {"frequency_percent", "a modal fit gives the frequency to 0.01 %: a thousandth of 5 % is a real spread "
                            "(1000 times it is refused: above 33 %)"},
  };
  return exempt;
}

struct Numeric {
  std::size_t line = 0;
  std::string key;
  std::string prefix;  // the line up to the value
  std::string value;
  std::string suffix;  // the rest (a comment)
};

// `key = number` lines (not inline tables or arrays: their keys are walked
// where the shipped files give them one per line).
std::vector<Numeric> NumericLines(const std::vector<std::string>& lines) {
  static const std::regex kLine(R"(^(\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*)([-+]?[0-9][0-9_.eE+-]*)(\s*(#.*)?)$)");
  std::vector<Numeric> out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (!std::regex_match(lines[i], m, kLine)) continue;
    out.push_back({i, m[2], m[1], m[3], m[4]});
  }
  return out;
}

std::vector<std::string> Lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string Join(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

// Warnings of the text read as the kind of config the original is, or
// nullopt when it is refused.
std::optional<std::vector<std::string>> WarningsOf(const std::string& text, const fs::path& origin, bool grinding) {
  try {
    return grinding ? chatter::parse_grinding_config(text, origin.string()).warnings
                    : chatter::parse_config(text, origin.string()).warnings;
  } catch (const chatter::InputError&) {
    return std::nullopt;
  }
}

std::vector<fs::path> ShippedConfigs() {
  std::vector<fs::path> files;
  for (const char* dir : {"configs", "examples"})
    for (const auto& e : fs::recursive_directory_iterator(fs::path(CHATTER_SOURCE_DIR) / dir))
      if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string Scaled(const std::string& value, double factor) {
  std::string v = value;
  v.erase(std::remove(v.begin(), v.end(), '_'), v.end());
  std::ostringstream s;
  s.precision(12);
  s << std::stod(v) * factor;
  std::string out = s.str();
  // An integer key stays integer-typed when scaled up; scaled down it
  // becomes a float, which an integer key refuses: a refusal is an answer.
  if (out.find_first_of(".eE") == std::string::npos && value.find_first_of(".eE") != std::string::npos) out += ".0";
  return out;
}

TEST(UnitsRule, EveryShippedNumberThousandfoldOffIsRefusedOrWarned) {
  std::vector<std::string> silent;
  int walked = 0;
  int configs = 0;
  for (const fs::path& file : ShippedConfigs()) {
    const std::vector<std::string> lines = Lines(file);
    const std::string text = Join(lines);
    bool grinding = false;
    if (!WarningsOf(text, file, false)) {
      grinding = true;
      if (!WarningsOf(text, file, true)) continue;  // a job, a modes fragment: not a config on its own
    }
    ++configs;
    const std::vector<std::string> before = *WarningsOf(text, file, grinding);
    for (const Numeric& n : NumericLines(lines)) {
      if (Exempt().count(n.key)) continue;
      if (std::stod(std::string(n.value.begin(), n.value.end())) == 0.0) continue;  // zero has no scale
      for (const double factor : {1000.0, 0.001}) {
        std::vector<std::string> changed = lines;
        changed[n.line] = n.prefix + Scaled(n.value, factor) + n.suffix;
        const auto warnings = WarningsOf(Join(changed), file, grinding);
        ++walked;
        if (!warnings) continue;
        bool named = false;
        for (const std::string& w : *warnings)
          if (w.find(n.key) != std::string::npos &&
              std::find(before.begin(), before.end(), w) == before.end())
            named = true;
        if (!named)
          silent.push_back(fs::relative(file, CHATTER_SOURCE_DIR).string() + ":" + std::to_string(n.line + 1) +
                           ": " + n.key + " x" + (factor > 1 ? "1000" : "1/1000"));
      }
    }
  }
  EXPECT_GE(configs, 15) << "the shipped configs were not found under " << CHATTER_SOURCE_DIR;
  EXPECT_GE(walked, 400);
  std::string list;
  for (const std::string& s : silent) list += "\n  " + s;
  EXPECT_TRUE(silent.empty()) << silent.size() << " of " << walked
                              << " thousandfold slips were read without a word:" << list;
}

// ------------------------------------------------------------------ flags

std::string Cli(const std::string& args) {
  const std::string command = std::string(CHATTER_CLI) + " " + args + " 2>&1";
  std::string out;
  if (FILE* p = popen(command.c_str(), "r")) {
    char buf[4096];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  return out;
}

// Every command's flags that take a value, from its --help.
std::set<std::string> ValueFlags() {
  const char* commands[] = {"lobes", "point", "check", "program", "recommend", "map", "compare", "simulate",
                            "surface", "forced", "sle", "performance", "optimize", "adapt", "design-pitch", "fit",
                            "frf", "coefficients", "detect", "grind predict", "grind sweep", "grind fit",
                            "grind impacts", "grind simulate", "grind plan"};
  static const std::regex kFlag(R"(^\s+(?:-[a-z] \[ )?--([a-z0-9-]+)(?: \])? arg)");
  std::set<std::string> flags;
  for (const char* c : commands) {
    std::istringstream help(Cli(std::string(c) + " --help"));
    for (std::string line; std::getline(help, line);) {
      std::smatch m;
      if (std::regex_search(line, m, kFlag)) flags.insert(m[1]);
    }
  }
  return flags;
}

// Flags that take a file, a name, a list or a choice: not numbers.
bool TextFlag(const std::string& f) {
  static const std::set<std::string> text = {
      "method", "methods", "table", "json", "plot", "out", "operations", "config", "format", "quantity",
      "band", "body", "direction", "family", "milling-direction", "axes", "rpm-spacing", "probability-table",
      "measurements", "start", "bias", "series", "spectrum", "tests", "objective", "plot-contours-mm", "model",
      "variable", "periodic", "feed-mm-per-s-list"};
  return text.count(f) > 0;
}

// The units rule for flags: every numeric flag of every command has a usual
// band (chatter/usual_bands.hpp kFlagBands) or is listed with why it has
// none; each band holds its typical value and not 1000 times it nor a
// thousandth of it.
TEST(UnitsRule, EveryNumericFlagHasABandOrAReason) {
  std::set<std::string> known;
  for (const chatter::FlagBand& f : chatter::kFlagBands) {
    known.insert(f.flag);
    EXPECT_TRUE(f.band->contains(f.typical)) << "--" << f.flag << " " << f.typical;
    EXPECT_FALSE(f.band->contains(f.typical * 1000.0)) << "--" << f.flag << " x1000";
    EXPECT_FALSE(f.band->contains(f.typical / 1000.0)) << "--" << f.flag << " /1000";
    EXPECT_FALSE(chatter::unusual(f.flag, f.typical * 1000.0, *f.band).empty());
  }
  for (const chatter::UnbandedFlag& f : chatter::kUnbandedFlags) {
    EXPECT_FALSE(known.count(f.flag)) << "--" << f.flag << " both banded and unbanded";
    known.insert(f.flag);
  }
  const std::set<std::string> flags = ValueFlags();
  EXPECT_GE(flags.size(), 60u) << "the commands' --help were not read";
  for (const std::string& f : flags) {
    if (TextFlag(f)) continue;
    EXPECT_TRUE(known.count(f)) << "--" << f << ": neither banded (kFlagBands) nor listed with a reason";
  }
}

// The flag's warning reaches the user like a config's: on stderr, in the
// JSON record's warnings, and refused by --strict.
TEST(UnitsRule, AFlagOutsideItsBandIsWarnedInTextJsonAndStrict) {
  const std::string cfg = std::string(CHATTER_SOURCE_DIR) + "/configs/seed_turning_1dof.toml";
  const std::string out = Cli("point " + cfg + " --rpm 5 --depth-mm 1.5");
  EXPECT_NE(out.find("warning: --rpm = 5: outside the 10 to 200 000 rev/min"), std::string::npos) << out;
  EXPECT_NE(out.find("is it in rev/s (--rpm = 300)?"), std::string::npos) << out;
  const std::string json = Cli("point " + cfg + " --rpm 1200 --depth-mm 0.0015");
  EXPECT_NE(json.find("\"--depth-mm = 0.0015: outside the 0.01 to 100 mm of a depth of cut; is it in m (--depth-mm = 1.5)?\""),
            std::string::npos)
      << json;
  const std::string strict = Cli("lobes " + cfg + " --depth-max-mm 20000 --strict --table /dev/null");
  EXPECT_NE(strict.find("--depth-max-mm = 20000: outside the 0.05 to 1 000 mm"), std::string::npos) << strict;
  EXPECT_NE(strict.find("(--strict)"), std::string::npos) << strict;
}

}  // namespace
